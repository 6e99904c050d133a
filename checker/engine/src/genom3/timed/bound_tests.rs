//! The static bound's refinements (docs/genom3-semantics.md 15.12), each
//! on a small component whose bound is computed by hand, and checked
//! against the whole exploration (no early stop, no bound): a task the
//! bound clears never overruns there.

use genom_model::component::Component;

use super::TimedEngine;
use super::analysis::analyse_timing_early;
use super::bound::wake_up_bounds;
use crate::genom3::machine::Machine;
use crate::kernel::explore::Limits;
use crate::testing::load_genom3_wcet;

/// The bound of task `task`'s wake-up, in microseconds, with `instances`.
fn bound_us(c: &Component, instances: usize, task: &str) -> Option<u64> {
    let m = Machine::new(c, instances).expect("GenoM3");
    let t = m.tasks.iter().position(|x| x.name == task).expect("task");
    let te = TimedEngine::new(m).expect("few tasks");
    let units = wake_up_bounds(&te)[t]?;
    Some(u64::try_from(units).ok()? * te.unit / 1000)
}

/// Whether task `task` overruns in the whole exploration (which must end).
fn overruns(c: &Component, instances: usize, task: &str) -> bool {
    let m = Machine::new(c, instances).expect("GenoM3");
    let t = m.tasks.iter().position(|x| x.name == task).expect("task");
    let whole = analyse_timing_early(&m, Limits::default(), true, false).expect("few tasks");
    assert!(whole.stopped.is_none(), "the whole exploration ends");
    whole.overruns.iter().any(|o| o.task == t)
}

/// A 10 ms task whose activity runs two 3 ms codels without `pause::`;
/// `restart` adds `interrupts r`.
fn one_activity(restart: bool) -> Component {
    let interrupts = if restart { "interrupts r; " } else { "" };
    let text = format!(
        "component d {{\n  ids {{ long x; }};\n  task t {{ period 10 ms; }};\n  activity r() {{ task t; codel<start> fa(in x) yield s; codel<s> fb(in x) yield pause::s, ether; {interrupts}}};\n}};\n"
    );
    load_genom3_wcet(&text, "r.start 3ms\nr.s 3ms\n")
}

#[test]
fn an_activity_that_interrupts_itself_runs_one_instance_per_wake_up() {
    // Restarted, the new request waits for the interrupted one to end and
    // starts at a tick: one 6 ms chain per wake-up, whatever the instances.
    let restart = one_activity(true);
    for instances in [1, 2] {
        assert_eq!(bound_us(&restart, instances, "t"), Some(6_000));
        assert!(!overruns(&restart, instances, "t"));
    }
    // Without `interrupts`, two instances run their chains in one wake-up
    // (12 ms): the bound counts both, and the task does overrun.
    let twice = one_activity(false);
    assert_eq!(bound_us(&twice, 2, "t"), Some(12_000));
    assert!(overruns(&twice, 2, "t"));
}

#[test]
fn activities_that_interrupt_one_another_run_one_per_wake_up() {
    let text = "component d {\n  ids { long x; };\n  task t { period 10 ms; };\n  activity r() { task t; codel<start> fa(in x) yield s; codel<s> fb(in x) yield pause::s, ether; interrupts r, q; };\n  activity q() { task t; codel<start> ga(in x) yield s; codel<s> gb(in x) yield pause::s, ether; interrupts r, q; };\n};\n";
    let c = load_genom3_wcet(text, "r.start 3ms\nr.s 3ms\nq.start 2ms\nq.s 5ms\n");
    for instances in [1, 2] {
        // The longer of the two chains, not their sum (13 ms).
        assert_eq!(bound_us(&c, instances, "t"), Some(7_000));
        assert!(!overruns(&c, instances, "t"));
    }
}

#[test]
fn a_periodic_task_holds_a_lock_at_most_its_period() {
    // `u`'s 5 ms writer of `x` runs past its 2 ms tick only in runs that
    // end there (`u` overruns): in every other run it holds `x` at most
    // 2 ms, so each of `t`'s two readers waits at most 2 ms: 2 × (2.5 + 2)
    // = 9 ms < 10 ms (it was 2 × (2.5 + 5) = 15 ms).
    let text = "component d {\n  ids { long x; };\n  task t { period 10 ms; codel<start> ta(in x) yield main; codel<main> tb(in x) yield pause::main; };\n  task u { period 2 ms; codel<start> us() yield main; codel<main> uw(out x) yield pause::main; };\n};\n";
    let c = load_genom3_wcet(text, "t.start 2500us\nt.main 2500us\nu.main 5ms\n");
    assert_eq!(bound_us(&c, 1, "t"), Some(9_000));
    assert!(!overruns(&c, 1, "t"));
    assert!(overruns(&c, 1, "u"), "the writer itself overruns");
}

#[test]
fn behind_the_queue_a_codel_waits_only_for_what_it_conflicts_with() {
    // `w`'s five 100 us codels read `x`, which `main`'s 200 us codel
    // writes; `main`'s codel also writes `lg`, which the control thread's
    // 2 ms `log` writes. A codel of `w` waits for the last thread queued
    // ahead to begin (`main` within its 1 ms period, the control thread
    // within 200 + 100 us), then for the running codels it conflicts
    // with (`main`'s 200 us): 1.2 ms, not 2.3 ms. Five codels: 5 × 1.3 =
    // 6.5 ms < 10 ms (it was 11.5 ms).
    let text = "component d {\n  ids { long x; long lg; };\n  task main { period 1 ms; codel<start> mc(out x, inout lg) yield pause::start; };\n  task w { period 10 ms; codel<start> w1(in x) yield s2; codel<s2> w2(in x) yield s3; codel<s3> w3(in x) yield s4; codel<s4> w4(in x) yield s5; codel<s5> w5(in x) yield pause::start; };\n  function log() { codel fl(inout lg); };\n};\n";
    let wcet = "main.start 200us\nw.start 100us\nw.s2 100us\nw.s3 100us\nw.s4 100us\nw.s5 100us\nlog.codel 2ms\n";
    let c = load_genom3_wcet(text, wcet);
    assert_eq!(bound_us(&c, 1, "w"), Some(6_500));
    assert!(!overruns(&c, 1, "w"));
    assert!(
        overruns(&c, 1, "main"),
        "`log` makes `main` wait past its tick"
    );
}
