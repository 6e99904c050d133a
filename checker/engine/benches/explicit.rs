//! The explicit (untimed) explorer per state: the behavioural analysis of
//! generated components exploring every interleaving (`--no-reduction`,
//! every cluster whole), and the bare exploration of the largest cluster
//! (no property read on the states), as states per second.
//!
//! `cargo bench -p genom-engine --bench explicit -- --warm-up-time 1 --measurement-time 5`
//!
//! The first case is issue 14's yardstick, `genom-check generate --seed 6
//! --services 8 --codels 4 --threads 2 --density 1 --init --autos 1`.
//! Before measuring, each case is explored once and its figures are printed
//! on stderr: states, transitions, time, states per second, bytes per
//! stored state, and whether the exploration finished. Criterion's
//! throughput is in states, so its `thrpt` reads as states per second.

#![allow(clippy::print_stderr, clippy::expect_used)]

use std::hint::black_box;
use std::path::Path;
use std::time::{Duration, Instant};

mod common;
use common::print;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gen_frontend::MemoryLoader;
use genom_engine::dialect::analyse_with;
use genom_engine::dialect::analysis::clusters;
use genom_engine::dialect::system::System;
use genom_engine::kernel::explore::{Limits, explore};
use genom_generate::{GeneratorConfig, generate};
use genom_model::behaviour::Behaviour;
use genom_model::component::Component;

/// Seed, services, codels per service, threads, rule density.
const CASES: [(u64, usize, usize, usize, f64); 1] = [(6, 8, 4, 2, 1.0)];

fn component(case: (u64, usize, usize, usize, f64)) -> Component {
    let (seed, services, codels, threads, density) = case;
    let text = generate(&GeneratorConfig {
        codels_per_service: codels,
        threads,
        rule_density: density,
        init: true,
        autos: 1,
        ..GeneratorConfig::new(seed, services)
    });
    // The front-end alone: the engines read only the model.
    let front = gen_frontend::lower(Path::new("bench.gen"), text, &MemoryLoader::new());
    front
        .model
        .filter(|_| front.has_component)
        .expect("a generated component resolves")
}

/// Explores the largest cluster of `c` whole, reading nothing; returns the
/// states, transitions, bytes per state and whether it finished.
fn bare(c: &Component, b: &Behaviour) -> (usize, u64, f64, bool) {
    let cluster = clusters(c)
        .into_iter()
        .max_by_key(Vec::len)
        .unwrap_or_default();
    let sys = System::new(c, b, &cluster, false);
    let e = explore(&sys, Limits::default(), |_, _| {});
    (
        e.store.len(),
        e.transitions,
        e.store.bytes_per_state(),
        e.stopped.is_none(),
    )
}

fn bench(cr: &mut Criterion) {
    let mut group = cr.benchmark_group("explicit");
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));
    for case in CASES {
        let (seed, services, codels, threads, density) = case;
        let id = format!("seed{seed}-{services}x{codels}x{threads}-d{density}");
        let c = component(case);
        let b = Behaviour::new(&c);

        let started = Instant::now();
        let a = analyse_with(&c, Limits::default(), false);
        let done = a.stopped.is_none();
        print(
            &format!("analysis/{id}"),
            a.states,
            a.transitions,
            started.elapsed(),
            a.footprint.bytes_per_state,
            done,
        );
        group.throughput(Throughput::Elements(a.states.max(1)));
        group.bench_with_input(BenchmarkId::new("analysis", &id), &c, |bch, c| {
            bch.iter(|| black_box(analyse_with(c, Limits::default(), false).states));
        });

        let started = Instant::now();
        let (states, transitions, bytes, done) = bare(&c, &b);
        print(
            &format!("explore/{id}"),
            states as u64,
            transitions,
            started.elapsed(),
            bytes,
            done,
        );
        group.throughput(Throughput::Elements(states.max(1) as u64));
        group.bench_with_input(BenchmarkId::new("explore", &id), &c, |bch, c| {
            bch.iter(|| black_box(bare(c, &b).0));
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
