//! The whole check (parse, resolve, static checks, behavioural
//! exploration) of generated components of growing size, services × codels
//! × threads, with a sparse rule density (0.3 `stops`/`delays`/`forbids`
//! references per service), a realistic one (about one) and a dense one
//! (three).
//!
//! `cargo bench -p genom-check --bench explore -- --warm-up-time 1 --measurement-time 5`
//!
//! Before measuring, each case is checked once and its exploration figures
//! are printed on stderr (states, transitions, bytes per state, largest
//! cluster and part, whether the exploration finished): first exploring
//! every cluster whole (`--no-reduction`), then with the default engine
//! (compositional exploration and partial-order reduction), which is what
//! criterion measures, so that the time per iteration can be read as states
//! per second. Explorations are capped at
//! [`MAX_STATES`] states so that a case whose state space explodes still
//! gives a number (the time to explore that many states) instead of
//! running out of memory; such a case is marked `incomplete`.

#![allow(clippy::print_stderr, clippy::expect_used)]

use std::hint::black_box;
use std::path::Path;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gen_frontend::MemoryLoader;
use genom_check::{CheckOptions, check_source};
use genom_generate::{GeneratorConfig, generate};
use genom_model::component::Component;

/// Cap on the states of one check.
const MAX_STATES: usize = 1_000_000;

/// Services, codels per service, threads.
const SIZES: [(usize, usize, usize); 4] = [(5, 3, 1), (10, 5, 2), (20, 5, 3), (30, 5, 4)];

/// Rule densities: sparse (clusters of a few services, explorations that
/// finish), realistic and dense.
const DENSITIES: [(&str, f64); 3] = [("sparse", 0.3), ("realistic", 1.0), ("dense", 3.0)];

fn config(services: usize, codels: usize, threads: usize, density: f64) -> GeneratorConfig {
    GeneratorConfig {
        codels_per_service: codels,
        threads,
        rule_density: density,
        init: true,
        autos: 1,
        ..GeneratorConfig::new(1, services)
    }
}

fn options() -> CheckOptions {
    CheckOptions::new().max_states(MAX_STATES)
}

/// Checks once with the default engine, and once exploring every cluster
/// whole with every interleaving (`--no-reduction`), and prints the
/// exploration figures of both; returns the default's states.
fn report(name: &str, text: &str) -> u64 {
    run(
        &format!("{name} (whole)"),
        text,
        &options().reduction(false),
    );
    run(name, text, &options())
}

/// Checks once and prints the exploration figures; returns the states.
fn run(name: &str, text: &str, options: &CheckOptions) -> u64 {
    let started = Instant::now();
    let result = check_source(
        Path::new("bench.gen"),
        text.to_owned(),
        &MemoryLoader::new(),
        options,
    );
    let elapsed = started.elapsed();
    let stats = result.statistics.expect("the engine ran");
    let (cluster, part) = result.component.as_ref().map_or((0, 0), largest);
    #[allow(clippy::cast_precision_loss)]
    let rate = stats.states as f64 / elapsed.as_secs_f64().max(1e-9);
    eprintln!(
        "{name}: {} states, {} transitions, {:.1} ms, {rate:.0} states/s, {:.1} B/state, largest cluster {cluster}, largest part {part}{}",
        stats.states,
        stats.transitions,
        elapsed.as_secs_f64() * 1000.0,
        stats.bytes_per_state.unwrap_or(0.0),
        if stats.complete { "" } else { ", incomplete" }
    );
    stats.states
}

/// Services in the largest cluster (connected component of the `stops`/
/// `delays`/`forbids` relation) and in the largest part (strongly connected
/// component of the depends-on relation): what the engine explores as one
/// product without and with compositional exploration.
fn largest(c: &Component) -> (usize, usize) {
    let clusters = genom_checker::dialect::analysis::clusters(c);
    let cluster = clusters.iter().map(Vec::len).max().unwrap_or(0);
    let part = clusters
        .iter()
        .flat_map(|k| genom_checker::dialect::compose::parts(c, k))
        .map(|p| p.len())
        .max()
        .unwrap_or(0);
    (cluster, part)
}

fn bench(c: &mut Criterion) {
    for (label, density) in DENSITIES {
        let mut group = c.benchmark_group(format!("check/{label}"));
        group.sample_size(10);
        group.warm_up_time(Duration::from_secs(1));
        for (services, codels, threads) in SIZES {
            let id = format!("{services}x{codels}x{threads}");
            let text = generate(&config(services, codels, threads, density));
            let states = report(&format!("check/{label}/{id}"), &text);
            group.throughput(Throughput::Elements(states.max(1)));
            group.bench_with_input(BenchmarkId::from_parameter(&id), &text, |b, text| {
                b.iter(|| {
                    let r = check_source(
                        Path::new("bench.gen"),
                        text.clone(),
                        &MemoryLoader::new(),
                        &options(),
                    );
                    black_box(r.statistics)
                });
            });
        }
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
