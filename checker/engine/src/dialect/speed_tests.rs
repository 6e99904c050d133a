//! The analysis's fast paths against their plain definitions, on every
//! reached state of generated components: the bit-mask search for a cycle
//! of pending instances finds what the general one finds, and
//! [`visit`]'s facts (which skip what is already known) are those of a
//! plain reading of every state.

#![allow(clippy::expect_used, clippy::unwrap_used)]

use std::collections::{BTreeMap, BTreeSet};

use genom_model::behaviour::{Behaviour, IDLE};
use genom_model::component::{CodelId, Component, ServiceId};

use super::analysis::{Found, visit};
use super::pending::{pending_cycle_any, pending_cycle_small};
use super::system::{Config, System};
use crate::kernel::explore::{Limits, explore};
use crate::kernel::store::StateId;
use crate::testing::{check, generated};

/// A generated component: seed, services, codels per service, threads
/// and rules per service.
fn component(config: (u64, usize, usize, usize, f64)) -> Component {
    generated(config, 0.0)
}

#[test]
fn the_bit_mask_cycle_search_agrees_with_the_general_one() {
    let mut cycles = 0;
    let mut compared = 0;
    for seed in 1..=12 {
        let c = component((seed, 6, 2, 2, 3.0));
        let b = Behaviour::new(&c);
        let all: Vec<ServiceId> = c.services.ids().collect();
        let sys = System::new(&c, &b, &all, false);
        let limits = Limits {
            max_states: 20_000,
            ..Limits::default()
        };
        explore(&sys, limits, |_, cfg| {
            let small = pending_cycle_small(&sys, cfg);
            assert_eq!(small, pending_cycle_any(&sys, cfg));
            cycles += usize::from(small.is_some());
            compared += 1;
        });
    }
    assert!(compared > 1000, "{compared} states");
    assert!(cycles > 0, "some state has a cycle of pending instances");
}

/// The facts of [`Found`], read plainly: every fact of every member asked
/// on every state, the first state showing it kept.
#[derive(Debug, Default, PartialEq)]
struct Plain {
    reached: BTreeSet<CodelId>,
    started: BTreeSet<ServiceId>,
    deadlocks: BTreeMap<Vec<ServiceId>, StateId>,
    starvations: BTreeMap<(ServiceId, ServiceId), (StateId, bool)>,
    unbounded: BTreeMap<ServiceId, StateId>,
    pending: BTreeMap<ServiceId, StateId>,
    init_success: Option<StateId>,
    root: Option<StateId>,
}

fn plain_visit(sys: &System<'_>, id: StateId, cfg: &Config, out: &mut Plain) {
    out.root.get_or_insert(id);
    if cfg.init_done && out.init_success.is_none() && sys.init().is_some() {
        out.init_success = Some(id);
    }
    let running = sys.running(cfg);
    for i in (0..sys.len()).filter(|&i| !sys.is_input(i)) {
        let s = sys.service(i);
        let m = sys.machine_of(i);
        let pos = sys.position(cfg, i);
        if let Some(codel) = pos.codel().filter(|_| pos.is_running()) {
            out.reached.insert(codel);
        }
        if cfg.main[i] != IDLE {
            out.started.insert(s);
        }
        if sys.request_enabled_among(cfg, i, &running) {
            out.reached.extend(sys.component().services[s].control);
            if m.start.is_none() {
                out.started.insert(s);
            }
        }
        if m.stop_loops[usize::from(cfg.main[i])] {
            out.unbounded.entry(s).or_insert(id);
        }
        if cfg.pending[i].is_none() {
            continue;
        }
        out.pending.entry(s).or_insert(id);
        for (t, via_delays) in sys.blockers(cfg, i) {
            if !m.watchdog && sys.may_never_end(cfg, t) {
                let pair = (s, sys.service(t));
                out.starvations.entry(pair).or_insert((id, via_delays));
            }
        }
    }
    if let Some(cycle) = pending_cycle_any(sys, cfg) {
        out.deadlocks.entry(cycle).or_insert(id);
    }
}

#[test]
fn visit_finds_the_facts_a_plain_reading_finds() {
    let mut facts = [0usize; 4];
    // Generated components with deadlocks and starvations, and fixtures
    // with an unbounded interrupt and a starvation behind a loop.
    let generated = [
        (3, 7, 2, 2, 3.0),
        (8, 6, 2, 2, 5.0),
        (12, 8, 2, 1, 3.0),
        (10, 7, 3, 2, 4.0),
        (6, 8, 4, 2, 1.0),
    ]
    .map(component);
    let fixtures = [
        include_str!("../../../../tests/fixtures/invalid/unbounded-interrupt.loop-with-exit.gen"),
        include_str!("../../../../tests/fixtures/invalid/starvation.behind-endless-loop.gen"),
    ]
    .map(|text| check(text).component.expect("a fixture"));
    for c in generated.iter().chain(&fixtures) {
        let b = Behaviour::new(c);
        let all: Vec<ServiceId> = c.services.ids().collect();
        for pre_init in [true, false] {
            let sys = System::new(c, &b, &all, pre_init);
            let limits = Limits {
                max_states: 100_000,
                ..Limits::default()
            };
            let (mut fast, mut plain) = (Found::default(), Plain::default());
            explore(&sys, limits, |id, cfg| {
                visit(&sys, id, cfg, &mut fast);
                plain_visit(&sys, id, cfg, &mut plain);
            });
            let fast = Plain {
                reached: fast.reached,
                started: fast.started,
                deadlocks: fast.deadlocks,
                starvations: fast.starvations,
                unbounded: fast.unbounded,
                pending: fast.pending,
                init_success: fast.init_success,
                root: fast.root,
            };
            assert_eq!(fast, plain);
            for (k, n) in [
                plain.deadlocks.len(),
                plain.starvations.len(),
                plain.unbounded.len(),
                plain.pending.len(),
            ]
            .into_iter()
            .enumerate()
            {
                facts[k] += n;
            }
        }
    }
    // Every kind of fact is exercised.
    assert!(facts.iter().all(|&n| n > 0), "{facts:?}");
}
