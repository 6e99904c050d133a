//! The zone engine on generated timed components (periods, WCETs,
//! max-times, several threads) of growing size, services × codels ×
//! threads, in three variants:
//!
//! - `default`: what `genom-check check` runs (LU extrapolation, and
//!   inclusion checking in the passed list: a state whose zone is included
//!   in a stored one with the same discrete part is not new);
//! - `no-extrapolation`: the model's `extrapolate` switch off;
//! - `no-inclusion`: a state is only old when a stored one has the same
//!   discrete part and the *same* zone (a wrapper model whose zones compare
//!   by equality; the engine is unchanged).
//!
//! `cargo bench -p genom-engine --bench zones -- --warm-up-time 1 --measurement-time 3`
//!
//! Before measuring, each case is explored once per variant and its figures
//! are printed on stderr: symbolic states, transitions, time, symbolic
//! states per second, bytes per state, and whether the exploration
//! finished (each is capped at [`MAX_STATES`] states).

#![allow(clippy::print_stderr, clippy::expect_used)]

use std::hint::black_box;
use std::path::Path;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use gen_frontend::MemoryLoader;
use genom_engine::kernel::explore::{Limits, Model, explore};
use genom_engine::kernel::store::Subsumes;
use genom_engine::timed::model::{TAction, TState, TimedSystem};
use genom_engine::zones::dbm::Dbm;
use genom_generate::{GeneratorConfig, generate};
use genom_model::behaviour::Behaviour;
use genom_model::component::Component;

/// Cap on the symbolic states of one exploration (all clusters).
const MAX_STATES: usize = 300_000;

/// Services, codels per service, threads.
const SIZES: [(usize, usize, usize); 4] = [(3, 2, 1), (5, 3, 2), (8, 3, 2), (12, 3, 3)];

/// The variants measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Variant {
    Default,
    NoExtrapolation,
    NoInclusion,
}

const VARIANTS: [(Variant, &str); 3] = [
    (Variant::Default, "default"),
    (Variant::NoExtrapolation, "no-extrapolation"),
    (Variant::NoInclusion, "no-inclusion"),
];

/// A zone that only subsumes an equal zone.
#[derive(Clone, PartialEq, Eq, Hash)]
struct ExactZone(Dbm);

impl Subsumes for ExactZone {
    fn subsumed_by(&self, other: &ExactZone) -> bool {
        self.0 == other.0
    }
}

/// A timed model explored without inclusion checking.
struct NoInclusion<'m, 'c>(&'m TimedSystem<'c>);

impl Model for NoInclusion<'_, '_> {
    type State = TState;
    type Action = TAction;
    type Zone = ExactZone;

    fn width(&self) -> usize {
        self.0.width()
    }
    fn init_states(&self) -> Vec<Self::State> {
        self.0.init_states()
    }
    fn actions(&self, state: &Self::State, out: &mut Vec<Self::Action>) {
        self.0.actions(state, out);
    }
    fn next_state(&self, state: &Self::State, action: Self::Action) -> Option<Self::State> {
        self.0.next_state(state, action)
    }
    fn encode(&self, state: &Self::State, out: &mut Vec<u64>) {
        self.0.encode(state, out);
    }
    fn decode(&self, words: &[u64], zone: &ExactZone) -> Self::State {
        self.0.decode(words, &zone.0)
    }
    fn zone(&self, state: &Self::State) -> ExactZone {
        ExactZone(self.0.zone(state))
    }
    fn expand(&self, state: &Self::State) -> bool {
        self.0.expand(state)
    }
}

fn config(services: usize, codels: usize, threads: usize) -> GeneratorConfig {
    GeneratorConfig {
        codels_per_service: codels,
        threads,
        rule_density: 0.5,
        init: true,
        autos: 1,
        timed: true,
        ..GeneratorConfig::new(7, services)
    }
}

/// The resolved component of a generated text (the front-end alone: the
/// engines read only the model).
fn component(text: &str) -> Component {
    let front = gen_frontend::lower(
        Path::new("bench.gen"),
        text.to_owned(),
        &MemoryLoader::new(),
    );
    front
        .model
        .filter(|_| front.has_component)
        .expect("a generated component resolves")
}

/// What one exploration of every cluster cost.
#[derive(Debug, Default, Clone, Copy)]
struct Figures {
    states: usize,
    transitions: u64,
    bytes: usize,
    complete: bool,
}

/// Explores the timed model of every cluster (as the timed engine does)
/// in `variant`; the state cap is shared by the clusters.
fn explore_all(c: &Component, variant: Variant) -> Figures {
    let b = Behaviour::new(c);
    let mut f = Figures {
        complete: true,
        ..Figures::default()
    };
    for (members, frozen) in genom_engine::timed::timed_explorations(c) {
        let mut ts = TimedSystem::new(c, &b, &members, frozen);
        ts.extrapolate = variant != Variant::NoExtrapolation;
        let limits = Limits {
            max_states: MAX_STATES.saturating_sub(f.states).max(1),
            ..Limits::default()
        };
        let (states, transitions, bytes, stopped) = if variant == Variant::NoInclusion {
            let e = explore(&NoInclusion(&ts), limits, |_, _| {});
            (e.store.len(), e.transitions, e.store.bytes(), e.stopped)
        } else {
            let e = explore(&ts, limits, |_, _| {});
            (e.store.len(), e.transitions, e.store.bytes(), e.stopped)
        };
        f.states += states;
        f.transitions += transitions;
        f.bytes += bytes;
        f.complete &= stopped.is_none();
        if !f.complete {
            break;
        }
    }
    f
}

#[allow(clippy::cast_precision_loss)]
fn report(name: &str, c: &Component, variant: Variant) -> usize {
    let started = Instant::now();
    let f = explore_all(c, variant);
    let secs = started.elapsed().as_secs_f64().max(1e-9);
    eprintln!(
        "{name}: {} symbolic states, {} transitions, {:.1} ms, {:.0} states/s, {:.1} B/state{}",
        f.states,
        f.transitions,
        secs * 1000.0,
        f.states as f64 / secs,
        f.bytes as f64 / f.states.max(1) as f64,
        if f.complete { "" } else { ", incomplete" }
    );
    f.states
}

fn bench(crit: &mut Criterion) {
    for (variant, label) in VARIANTS {
        let mut group = crit.benchmark_group(format!("zones/{label}"));
        group.sample_size(10);
        group.warm_up_time(Duration::from_secs(1));
        for (services, codels, threads) in SIZES {
            let id = format!("{services}x{codels}x{threads}");
            let c = component(&generate(&config(services, codels, threads)));
            let states = report(&format!("zones/{label}/{id}"), &c, variant);
            group.throughput(Throughput::Elements(states.max(1) as u64));
            group.bench_with_input(BenchmarkId::from_parameter(&id), &c, |b, c| {
                b.iter(|| black_box(explore_all(c, variant).states));
            });
        }
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
