//! The causes of overrun the static bound leaves possible
//! (docs/genom3-semantics.md 15.14), against every violation of the whole
//! exploration, and the groups decided once each of them is found.

use std::collections::{BTreeMap, BTreeSet};

use genom_model::component::Component;

use super::analysis::{Cause, TimingAnalysis, Tuning, analyse_timing_tuned};
use super::bound::possible_causes;
use super::groups::groups;
use super::locks::Locks;
use super::tests::{mixed_cases, replays};
use super::{TimedEngine, unit_ns};
use crate::genom3::machine::Machine;
use crate::kernel::explore::Limits;

/// Per task: the causes the static bound leaves possible (its group's).
fn possible(m: &Machine<'_>) -> BTreeMap<usize, BTreeSet<Cause>> {
    let locks = Locks::new(m, unit_ns(m));
    let mut out = BTreeMap::new();
    for group in groups(m, &locks) {
        let te = TimedEngine::with_locks(m.clone(), &group, locks.clone()).expect("few tasks");
        for (t, causes) in possible_causes(&te).into_iter().enumerate() {
            if group.tasks[t] {
                out.insert(t, causes);
            }
        }
    }
    out
}

/// The whole exploration, unreduced, every violation examined for its
/// cause; `None` when it does not finish within `limits`.
fn every_cause(m: &Machine<'_>, limits: Limits) -> Option<TimingAnalysis> {
    let all = Tuning {
        probe: usize::MAX,
        examined: usize::MAX,
    };
    let a = analyse_timing_tuned(m, limits, false, false, all)?;
    a.stopped.is_none().then_some(a)
}

fn causes(a: &TimingAnalysis) -> BTreeSet<(usize, Cause)> {
    a.overruns.iter().map(|o| (o.task, o.cause)).collect()
}

/// Generated components of several shapes and the timing fixtures.
fn cases() -> Vec<(String, Component)> {
    mixed_cases((1, 2), 5)
}

#[test]
fn every_cause_a_violation_shows_is_one_the_static_bound_leaves_possible() {
    // Every violation of the whole exploration (unreduced, no early stop),
    // its cause read off its path: the cause is among those the bound of
    // 15.14 leaves possible for its task. And the bound does rule some out
    // (causes of tasks that do overrun), so the check is not vacuous.
    let limits = Limits {
        max_states: 40_000,
        ..Limits::default()
    };
    let (mut compared, mut ruled_out) = (0, 0);
    for (name, c) in &cases() {
        for instances in [1, 2] {
            let m = Machine::new(c, instances).expect("GenoM3");
            let Some(whole) = every_cause(&m, limits) else {
                continue;
            };
            compared += 1;
            let possible = possible(&m);
            for (t, cause) in causes(&whole) {
                assert!(
                    possible[&t].contains(&cause),
                    "{name}, {instances} instance(s): task {} overruns for {cause:?}, which the bound rules out",
                    m.tasks[t].name
                );
            }
            let overrunning: BTreeSet<usize> = causes(&whole).iter().map(|&(t, _)| t).collect();
            for t in overrunning {
                let kinds = [Cause::LockWait, Cause::Chain, Cause::Shared];
                ruled_out += kinds.iter().filter(|c| !possible[&t].contains(c)).count();
            }
        }
    }
    assert!(compared >= 60, "{compared} whole explorations compared");
    assert!(
        ruled_out >= 10,
        "the bound ruled out {ruled_out} causes only"
    );
    eprintln!("{compared} whole explorations, {ruled_out} causes ruled out");
}

#[test]
fn a_group_decided_by_its_witnesses_reports_every_cause_the_whole_exploration_shows() {
    // With a probe too small to finish, a group is decided once the search
    // with restricted clients has found every cause the bound leaves
    // possible: its report then holds every cause of the violations of
    // the whole exploration (unreduced, each examined; it may hold more,
    // the_causes_left_possible_on_a_component_computed_by_hand), and its
    // traces replay in the independent oracle. A group not decided so is
    // explored whole, as before: the same tasks overrun, and its causes are
    // among the whole exploration's.
    let limits = Limits {
        max_states: 40_000,
        ..Limits::default()
    };
    let tiny = Tuning {
        probe: 8,
        ..Tuning::DEFAULT
    };
    let (mut witnessed, mut compared) = (0, 0);
    for (name, c) in &cases() {
        let m = Machine::new(c, 1).expect("GenoM3");
        let Some(whole) = every_cause(&m, limits) else {
            continue;
        };
        let quick = analyse_timing_tuned(&m, limits, true, true, tiny).expect("few tasks");
        assert!(
            quick.stopped.is_none(),
            "{name}: the whole exploration finishes"
        );
        compared += 1;
        replays(name, c, 1, &quick);
        let all = causes(&whole);
        let tasks = |a: &TimingAnalysis| a.overruns.iter().map(|o| o.task).collect::<BTreeSet<_>>();
        assert_eq!(tasks(&quick), tasks(&whole), "{name}");
        for (t, cause) in causes(&quick) {
            assert!(
                all.contains(&(t, cause)),
                "{name}: {cause:?} of task {t} not in the whole exploration"
            );
        }
        for g in quick.records.iter().filter(|g| g.witnessed) {
            witnessed += 1;
            let of_group = |set: &BTreeSet<(usize, Cause)>| {
                set.iter()
                    .filter(|(t, _)| g.tasks.contains(t))
                    .copied()
                    .collect::<Vec<_>>()
            };
            assert_eq!(of_group(&causes(&quick)), of_group(&all), "{name}");
        }
    }
    assert!(compared >= 40, "{compared} components compared");
    assert!(
        witnessed >= 5,
        "{witnessed} groups decided by their witnesses only"
    );
    eprintln!("{compared} components, {witnessed} groups decided by their witnesses");
}

#[test]
fn the_causes_left_possible_on_a_component_computed_by_hand() {
    // Task `t` (10 ms) runs `r`'s two 3 ms codels without `pause::` and
    // `g`'s 12 ms codel; `w`'s 5 ms control codel writes `x`, which `r`'s
    // codels read. `g`'s codel is a long codel. Without it, `r`'s chain
    // with its waits takes up to 3 + 5 + 3 + 5 = 16 ms (a lock wait is
    // possible), without waits 6 ms: a chain or a shared wake-up cannot
    // reach the period.
    let text = "component d {\n  ids { long x; };\n  task t { period 10 ms; };\n  activity r() { task t; codel<start> fa(in x) yield s; codel<s> fb(in x) yield pause::s, ether; };\n  activity g() { task t; codel<start> ga() yield ether; };\n  function w(in long v) { codel fw(in v, out x); };\n};\n";
    let wcet = "r.start 3ms\nr.s 3ms\ng.start 12ms\nw.codel 5ms\n";
    let c = crate::testing::load_genom3_wcet(text, wcet);
    let m = Machine::new(&c, 1).expect("GenoM3");
    let g = m
        .activities
        .iter()
        .position(|a| m.service_name(a.service) == "g")
        .expect("g");
    let long = Cause::LongCodel(crate::genom3::machine::Owner::Activity(g), 0);
    let expected = vec![(0, long), (0, Cause::LockWait)];
    let possible = possible(&m);
    assert_eq!(
        possible[&0].iter().map(|&c| (0, c)).collect::<Vec<_>>(),
        expected
    );
    // Decided by witnesses (a probe too small to finish): both causes,
    // each with a trace that replays. The whole exploration shows the long
    // codel only: the state where the lock wait makes `t` overrun is also
    // reached, first, by a run where `g`'s codel began in that wake-up and
    // ended, and the cause is read off the one path kept to it (15.14).
    let tiny = Tuning {
        probe: 8,
        ..Tuning::DEFAULT
    };
    let quick = analyse_timing_tuned(&m, Limits::default(), true, true, tiny).expect("few");
    assert!(quick.stopped.is_none() && quick.records.iter().any(|g| g.witnessed));
    assert_eq!(causes(&quick).into_iter().collect::<Vec<_>>(), expected);
    replays("by hand", &c, 1, &quick);
    let whole = every_cause(&m, Limits::default()).expect("the whole exploration ends");
    assert_eq!(causes(&whole).into_iter().collect::<Vec<_>>(), [(0, long)]);
}
