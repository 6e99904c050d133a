//! The whole check (parse, resolve, static checks, behavioural
//! exploration) of generated components of growing size, services × codels
//! × threads, with a sparse rule density (0.3 `stops`/`delays`/`forbids`
//! references per service), a realistic one (about one) and a dense one
//! (three).
//!
//! `cargo bench -p genom-checker --bench explore -- --warm-up-time 1 --measurement-time 5`
//!
//! Before measuring, each case is checked once and its exploration figures
//! are printed on stderr (states, transitions, bytes per state, largest
//! cluster, whether the exploration finished), so that the time per
//! iteration can be read as states per second. Explorations are capped at
//! [`MAX_STATES`] states so that a case whose state space explodes still
//! gives a number (the time to explore that many states) instead of
//! running out of memory; such a case is marked `incomplete`.

#![allow(clippy::print_stderr, clippy::expect_used)]

use std::hint::black_box;
use std::path::Path;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use genom_checker::generate::{GeneratorConfig, generate};
use genom_checker::{CheckOptions, check_source};
use genom_model::component::Component;
use genom_parser::MemoryLoader;

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

/// Checks once and prints the exploration figures; returns the states.
fn report(name: &str, text: &str) -> u64 {
    let started = Instant::now();
    let result = check_source(
        Path::new("bench.gen"),
        text.to_owned(),
        &MemoryLoader::new(),
        &options(),
    );
    let elapsed = started.elapsed();
    let stats = result.statistics.expect("the engine ran");
    let largest = result.component.as_ref().map_or(0, largest_cluster);
    #[allow(clippy::cast_precision_loss)]
    let rate = stats.states as f64 / elapsed.as_secs_f64().max(1e-9);
    eprintln!(
        "{name}: {} states, {} transitions, {:.1} ms, {rate:.0} states/s, {:.1} B/state, largest cluster {largest} services{}",
        stats.states,
        stats.transitions,
        elapsed.as_secs_f64() * 1000.0,
        stats.bytes_per_state.unwrap_or(0.0),
        if stats.complete { "" } else { ", incomplete" }
    );
    stats.states
}

/// Services in the largest connected component of the `stops`/`delays`/
/// `forbids` relation (what the engine explores as one product).
fn largest_cluster(c: &Component) -> usize {
    let n = c.services.len();
    let mut root: Vec<usize> = (0..n).collect();
    fn find(root: &mut [usize], mut x: usize) -> usize {
        while root[x] != x {
            root[x] = root[root[x]];
            x = root[x];
        }
        x
    }
    for (s, svc) in c.services.iter() {
        for r in svc.stops.iter().chain(&svc.delays).chain(&svc.forbids) {
            let (a, b) = (
                find(&mut root, s.0 as usize),
                find(&mut root, r.id.0 as usize),
            );
            root[a] = b;
        }
    }
    let mut size = vec![0; n];
    for x in 0..n {
        size[find(&mut root, x)] += 1;
    }
    size.into_iter().max().unwrap_or(0)
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
