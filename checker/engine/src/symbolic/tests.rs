//! Differential tests: on generated components, every cluster's symbolic
//! reachable set has exactly as many configurations as the explicit
//! explorer stores without reduction, the verdicts agree with what the
//! explicit `analysis::visit` reads off the same states, and every
//! symbolic trace is replayed by `System::apply` to a witness of its
//! verdict, as short as the explicit one.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use genom_generate::{GeneratorConfig, generate};
use genom_model::behaviour::Behaviour;
use genom_model::component::Component;

use super::{Strategy, Symbolic, SymbolicLimits};
use crate::dialect::analysis::{Found, clusters, visit};
use crate::dialect::system::{Action, Config, System};
use crate::kernel::explore::{Limits, Model, explore};

fn component(cfg: &GeneratorConfig) -> Component {
    let text = generate(cfg);
    crate::testing::check(&text)
        .component
        .expect("generated text lowers")
}

/// The configuration `path` leads to from the initial one.
fn replay(sys: &System<'_>, path: &[Action]) -> Config {
    let mut cfg = sys.init_states().remove(0);
    for &a in path {
        cfg = sys.apply(&cfg, a, &mut None).expect("the step is enabled");
    }
    cfg
}

/// What the compared clusters exercised.
#[derive(Default, Debug)]
struct Seen {
    states: usize,
    deadlocks: usize,
    starvations: usize,
    unbounded: usize,
    pending: usize,
}

/// Compares one cluster and adds what it exercised to `seen`.
fn compare(
    c: &Component,
    b: &Behaviour,
    cluster: &[genom_model::component::ServiceId],
    seen: &mut Seen,
) {
    let sys = System::new(c, b, cluster, false);
    let mut found = Found::default();
    let limits = Limits {
        max_states: 300_000,
        ..Limits::default()
    };
    let e = explore(&sys, limits, |id, cfg| visit(&sys, id, cfg, &mut found));
    if e.stopped.is_some() {
        return;
    }
    let sym = Symbolic::new(&sys).expect("a whole cluster");
    for strategy in [Strategy::Breadth, Strategy::Chained] {
        let limits = SymbolicLimits {
            strategy,
            ..SymbolicLimits::default()
        };
        let reach = sym.reach(limits);
        assert!(reach.stopped.is_none());
        assert_eq!(reach.states(), e.store.len() as u128, "state count");
        let v = sym.verdicts(&reach, true);
        agree(&sys, &e, &found, &v, strategy == Strategy::Breadth);
        seen.deadlocks += v.deadlocks.len();
        seen.starvations += v.starvations.len();
        seen.unbounded += v.unbounded.len();
        seen.pending += v.pending.len();
    }
    seen.states += e.store.len();
}

/// The symbolic verdicts `v` agree with the explicit `found`, and their
/// traces lead to witnesses (as short as the explicit ones when
/// `shortest`).
fn agree(
    sys: &System<'_>,
    e: &crate::kernel::explore::Exploration<Action>,
    found: &Found,
    v: &super::Verdicts,
    shortest: bool,
) {
    assert_eq!(v.reached, found.reached, "codels reached");
    assert_eq!(v.started, found.started, "services started");
    let pending: Vec<_> = found.pending.keys().copied().collect();
    assert_eq!(v.pending.iter().copied().collect::<Vec<_>>(), pending);
    let unbounded: Vec<_> = found.unbounded.keys().copied().collect();
    assert_eq!(v.unbounded.keys().copied().collect::<Vec<_>>(), unbounded);
    for (s, path) in &v.unbounded {
        let end = replay(sys, path);
        let i = sys.member_index(*s).unwrap();
        assert!(sys.machine_of(i).stop_loops[usize::from(end.main[i])]);
        assert!(!shortest || path.len() == e.store.path(found.unbounded[s]).len());
    }
    let starving: Vec<_> = found.starvations.keys().copied().collect();
    assert_eq!(v.starvations.keys().copied().collect::<Vec<_>>(), starving);
    for (&(w, t), path) in &v.starvations {
        let end = replay(sys, path);
        let (i, j) = (sys.member_index(w).unwrap(), sys.member_index(t).unwrap());
        assert!(sys.blockers(&end, i).iter().any(|&(b, _)| b == j));
        assert!(sys.may_never_end(&end, j));
        let (id, _) = found.starvations[&(w, t)];
        assert!(!shortest || path.len() == e.store.path(id).len());
    }
    assert_eq!(
        v.deadlocks.is_empty(),
        found.deadlocks.is_empty(),
        "deadlock"
    );
    for d in &v.deadlocks {
        assert!(
            found.deadlocks.contains_key(&d.services),
            "{:?}",
            d.services
        );
        let end = replay(sys, &d.path);
        for s in &d.services {
            assert!(end.pending[sys.member_index(*s).unwrap()].is_some());
        }
    }
}

fn run(cfg: &GeneratorConfig, seen: &mut Seen) {
    let c = component(cfg);
    let b = Behaviour::new(&c);
    for k in clusters(&c) {
        compare(&c, &b, &k, seen);
    }
}

#[test]
fn counts_and_verdicts_match_the_explicit_engine_on_small_components() {
    let mut seen = Seen::default();
    for seed in 0..40 {
        run(&GeneratorConfig::small(seed), &mut seen);
    }
    assert!(seen.states > 1000, "{seen:?}");
    assert!(seen.pending > 0 && seen.starvations > 0, "{seen:?}");
}

#[test]
fn counts_and_verdicts_match_on_dense_interrupting_components() {
    let mut seen = Seen::default();
    for seed in 0..8u64 {
        for density in [1.0, 2.0, 3.0] {
            let cfg = GeneratorConfig {
                codels_per_service: 2 + (seed as usize % 2),
                threads: 1 + (seed as usize % 3),
                rule_density: density,
                init: seed % 2 == 0,
                autos: (seed % 3) as usize,
                timed: seed % 4 == 1,
                self_stops: if seed % 3 == 0 { 0.5 } else { 0.0 },
                ..GeneratorConfig::new(seed, 5)
            };
            run(&cfg, &mut seen);
        }
    }
    assert!(seen.states > 1000, "{seen:?}");
    assert!(seen.deadlocks > 0 && seen.starvations > 0, "{seen:?}");
}

#[test]
fn an_unbounded_interrupt_has_a_replayed_shortest_trace() {
    let body = "service move {
          thread: main; stops: move;
          start codel { exec: go(); on-inter: brake; next: start; }
          inter codel brake { exec: slow(); next: brake; }
        }
        service halt {
          thread: main; stops: move;
          start codel { exec: h(); next: end; }
        }\n";
    let c = crate::testing::check(&format!("{}{body}", crate::testing::HEADER))
        .component
        .expect("the snippet lowers");
    let b = Behaviour::new(&c);
    let mut seen = Seen::default();
    for k in clusters(&c) {
        compare(&c, &b, &k, &mut seen);
    }
    // Counted once per strategy.
    assert_eq!(seen.unbounded, 2, "{seen:?}");
    assert_eq!(seen.pending, 4, "{seen:?}");
}

#[test]
fn a_passed_deadline_stops_with_a_partial_set_and_says_so() {
    let c = component(&GeneratorConfig {
        rule_density: 2.0,
        ..GeneratorConfig::new(3, 5)
    });
    let b = Behaviour::new(&c);
    let all: Vec<_> = c.services.ids().collect();
    let sys = System::new(&c, &b, &all, false);
    let sym = Symbolic::new(&sys).unwrap();
    let full = sym.reach(SymbolicLimits::default());
    assert!(full.stopped.is_none() && full.states() > 1);
    for strategy in [Strategy::Breadth, Strategy::Chained] {
        let limits = SymbolicLimits {
            strategy,
            deadline: Some(std::time::Instant::now()),
            ..SymbolicLimits::default()
        };
        let cut = sym.reach(limits);
        assert_eq!(cut.stopped, Some(crate::kernel::explore::Stop::Time));
        assert!(cut.states() < full.states());
    }
}
