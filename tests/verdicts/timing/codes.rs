//! Each timing code on its fixtures (`codel-overrun`, `thread-overrun`,
//! `max-time-infeasible`, `max-time-exceeded`, `max-time-watchdog`,
//! `missing-wcet`) with its twin, and behavioural verdicts decided on a
//! timed model.

use super::support::{Expected, TIMING, TWINS, assert_twins, the, trace_lines, verify};
use crate::common;

use genom_model::component::{Component, ServiceId};
use genom_model::duration::format_ns;
use genom_model::{Code, Diagnostic, Severity};
use genom_oracles::replay::{Claim, replay_claim};
use genom_oracles::timed_trace::{TimedClaim, check_timed, loops_without_bound};
#[test]
fn each_timing_fixture_has_a_near_identical_clean_twin() {
    for &(bad, good, code) in TWINS {
        assert_twins(bad, good, code);
    }
}

#[test]
fn every_timing_code_has_a_fixture_pair() {
    for &code in TIMING {
        assert!(
            TWINS.iter().any(|&(_, _, c)| c == code),
            "`{code}` has a fixture pair"
        );
    }
}

// ----------------------------------------------------------- codel-overrun

#[test]
fn codel_overrun_wcet_longer_than_the_period() {
    let path = common::invalid("codel-overrun.wcet-longer-than-period.gen");
    let result = common::check(&path);
    let report = common::render(&path, &result);
    let d = the(
        &result,
        Code::CodelOverrun,
        "codel `Servo::step` may take 12ms but thread `servoTask` wakes up every 10ms",
        &report,
    );
    assert_eq!(common::primary_line(&result, d), 16, "{report}");
    assert_eq!(d.severity, Severity::Error);
}

// ---------------------------------------------------------- thread-overrun

#[test]
fn thread_overrun_when_two_services_share_a_period() {
    verify(&Expected {
        fixture: "thread-overrun.two-services-share-a-period.gen",
        code: Code::ThreadOverrun,
        message: "thread `servo` can overrun its 10ms period",
        line: 10,
        claim: TimedClaim::Overrun("servo"),
        trace: &[
            "@0 component-start",
            "@0 wake-up servo",
            "@10ms request Track",
            "@10ms acknowledge Track",
            "@10ms start Track::start",
            "@10ms request Scan",
            "@10ms acknowledge Scan",
            "@10ms start Scan::start",
            "@10ms wake-up servo",
            "@10ms codel-start Track::start",
            "@16ms codel-end Track::start -> start",
            "@16ms codel-start Scan::start",
            "@20ms wake-up servo",
            "violation",
        ],
    });
}

#[test]
fn thread_overrun_by_a_lock_wait_on_a_shared_ids() {
    verify(&Expected {
        fixture: "thread-overrun.lock-wait-on-shared-ids.gen",
        code: Code::ThreadOverrun,
        message: "thread `servoTask` can overrun its 10ms period",
        line: 14,
        claim: TimedClaim::Overrun("servoTask"),
        trace: &[
            "@0 component-start",
            "@0 wake-up servoTask",
            "@0 wake-up logTask",
            "@10ms request Record",
            "@10ms acknowledge Record",
            "@10ms start Record::start",
            "@10ms wake-up servoTask",
            "@20ms wake-up servoTask",
            "@30ms wake-up servoTask",
            "@40ms wake-up servoTask",
            "@50ms request Servo",
            "@50ms acknowledge Servo",
            "@50ms start Servo::start",
            "@50ms wake-up servoTask",
            "@50ms wake-up logTask",
            "@50ms codel-start Record::start",
            "@58ms codel-end Record::start -> start",
            "@58ms codel-start Servo::start",
            "@60ms wake-up servoTask",
            "violation",
        ],
    });
}

#[test]
fn thread_overrun_behind_a_control_codel_holding_the_lock() {
    verify(&Expected {
        fixture: "thread-overrun.control-codel-holds-the-lock.gen",
        code: Code::ThreadOverrun,
        message: "thread `servoTask` can overrun its 10ms period",
        line: 13,
        claim: TimedClaim::Overrun("servoTask"),
        trace: &[
            "@0 component-start",
            "@0 wake-up servoTask",
            "@10ms request Servo",
            "@10ms acknowledge Servo",
            "@10ms start Servo::start",
            "@10ms request SetGain::control",
            "@10ms wake-up servoTask",
            "@15ms accept SetGain::control",
            "@15ms acknowledge SetGain",
            "@15ms start SetGain",
            "@15ms reply SetGain -> end",
            "@15ms codel-start Servo::start",
            "@20ms wake-up servoTask",
            "violation",
        ],
    });
}

// ----------------------------------------------------- max-time-infeasible

#[test]
fn max_time_infeasible_three_codels_in_fifteen_milliseconds() {
    let (result, _) = verify(&Expected {
        fixture: "max-time-infeasible.three-codels-in-15ms.gen",
        code: Code::MaxTimeInfeasible,
        message: "`Move` can never end within its max-time of 15ms",
        line: 13,
        claim: TimedClaim::LateService("Move"),
        trace: &[
            "@0 component-start",
            "@0 wake-up motion",
            "@0 request Move",
            "@0 acknowledge Move",
            "@0 start Move::start",
            "@10ms wake-up motion",
            "@10ms codel-start Move::start",
            "@10ms codel-end Move::start -> b",
            "violation",
        ],
    });
    // By hand: the shortest path start → b → c → end runs one codel per
    // period, so it ends at best two periods after the acknowledgment.
    let c = common::component(&result);
    let s = c.service_named("Move").expect("Move");
    let best = (shortest_path(c, s) - 1) * 10_000_000;
    assert_eq!(best, 20_000_000);
    assert!(c.services[s].max_time.expect("max-time").ns < best);
}

/// Codels on the shortest path from the start codel to `end` or a report.
fn shortest_path(c: &Component, s: ServiceId) -> u64 {
    use genom_model::component::Outcome;
    let start = c.services[s].start.expect("a start codel");
    let mut frontier = vec![start];
    let mut seen = vec![start];
    for n in 1.. {
        let mut next = Vec::new();
        for k in frontier {
            for o in c.codels[k].outcomes() {
                match o {
                    Outcome::Codel(x) if !seen.contains(&x) => {
                        seen.push(x);
                        next.push(x);
                    }
                    Outcome::Codel(_) => {}
                    Outcome::End | Outcome::Report(_) => return n,
                }
            }
        }
        assert!(!next.is_empty(), "the service can end");
        frontier = next;
    }
    unreachable!()
}

// ------------------------------------------------------- max-time-exceeded

#[test]
fn max_time_exceeded_on_the_worked_example() {
    verify(&Expected {
        fixture: "max-time-exceeded.worked-example.gen",
        code: Code::MaxTimeExceeded,
        message: "`Step` can miss its max-time of 11ms",
        line: 13,
        claim: TimedClaim::LateService("Step"),
        trace: &[
            "@0 component-start",
            "@0 wake-up servoTask",
            "@0 request Step",
            "@0 acknowledge Step",
            "@0 start Step::start",
            "@10ms wake-up servoTask",
            "@10ms codel-start Step::start",
            "violation",
        ],
    });
}

// ------------------------------------------------------ max-time-watchdog

#[test]
fn max_time_watchdog_on_a_servo_loop() {
    let path = common::invalid("max-time-watchdog.servo-loop.gen");
    let result = common::check(&path);
    let report = common::render(&path, &result);
    let d = the(
        &result,
        Code::MaxTimeWatchdog,
        "`Goto` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 20ms",
        &report,
    );
    assert_eq!(common::primary_line(&result, d), 13, "{report}");
    assert_eq!(d.severity, Severity::Advice);
    let c = common::component(&result);
    let s = c.service_named("Goto").expect("Goto");
    assert!(loops_without_bound(c, s));
    // By hand: interrupted while `approach` runs, the service ends its
    // codel within the period, then `brake` runs at the next wake-up.
    let period = 10_000_000;
    assert_eq!(format_ns(period * 2), "20ms");
    // The watchdog interrupts the looping service (at the max-time), so
    // `brake` is reachable, and a looping service's max-time is a watchdog
    // bound, not a deadline: no `max-time-exceeded` is claimed.
    assert!(
        !result
            .diagnostics
            .iter()
            .any(|d| d.code == Code::MaxTimeExceeded || d.code == Code::UnreachableCodel),
        "{report}"
    );
}

// ------------------------------------------------------------ missing-wcet

#[test]
fn missing_wcet_names_the_codel_and_what_is_left_unproven() {
    let path = common::invalid("missing-wcet.codel-without-wcet.gen");
    let result = common::check(&path);
    let report = common::render(&path, &result);
    let d = the(
        &result,
        Code::MissingWcet,
        "1 codel without WCET (`max-time`) is taken as running in no time",
        &report,
    );
    assert_eq!(common::primary_line(&result, d), 14, "{report}");
    assert_eq!(d.severity, Severity::Advice);
    assert_eq!(
        d.help.as_deref(),
        Some(
            "left unproven: overruns of thread `motion`; the max-time of `Goto`; give every codel a `max-time`"
        )
    );
}

// ------------------------------------- behavioural verdicts on a timed model

/// The behavioural verdicts of the untimed engine on the same component:
/// every order, and a watchdog that may fire at any time.
fn untimed_verdicts(c: &Component) -> Vec<Diagnostic> {
    let analysis = genom_checker::dialect::analyse(c, genom_checker::dialect::Limits::default());
    genom_checker::checks::behaviour(c, &analysis)
}

/// `abort` is only reached through the watchdog, which never fires: the
/// timed engine finds it unreachable, the untimed one does not. The
/// verdict is a claim about every execution, so it has no trace.
#[test]
fn unreachable_codel_because_the_watchdog_never_fires() {
    let path = common::invalid("unreachable-codel.watchdog-never-fires.gen");
    let result = common::check(&path);
    let report = common::render(&path, &result);
    let d = the(
        &result,
        Code::UnreachableCodel,
        "inter codel `abort` of service `Scan` is never reached in any execution",
        &report,
    );
    assert_eq!(common::primary_line(&result, d), 19, "{report}");
    assert!(d.trace.is_none());
    let untimed = untimed_verdicts(common::component(&result));
    assert!(
        !untimed.iter().any(|d| d.code == Code::UnreachableCodel),
        "without time the watchdog may fire, and `abort` runs: {untimed:?}"
    );
}

/// The init service always times out, so `Move` is dead (with a timed
/// trace); the untimed engine lets the init service succeed.
#[test]
fn dead_service_behind_an_init_service_that_always_times_out() {
    let path = common::invalid("dead-service.init-always-times-out.gen");
    let result = common::check(&path);
    let report = common::render(&path, &result);
    let d = the(
        &result,
        Code::DeadService,
        "service `Move` can never start",
        &report,
    );
    assert_eq!(common::primary_line(&result, d), 22, "{report}");
    assert_eq!(
        d.help.as_deref(),
        Some("NOT_INITIALIZED, because `Calibrate` can never complete successfully")
    );
    let trace = d
        .trace
        .as_ref()
        .expect("a dead-service verdict has a trace");
    assert_eq!(
        trace_lines(trace),
        [
            "@0 component-start",
            "@0 wake-up armTask",
            "@0 request Move",
            "@0 reject Move -> NOT_INITIALIZED",
            "violation",
        ]
    );
    let c = common::component(&result);
    check_timed(c, trace, TimedClaim::Rules).expect("the timed trace is a timed execution");
    replay_claim(c, trace, Claim::DeadService("Move")).expect("the trace replays");
    the(
        &result,
        Code::MaxTimeInfeasible,
        "`Calibrate` can never end within its max-time of 15ms",
        &report,
    );
    let untimed = untimed_verdicts(c);
    assert!(
        !untimed.iter().any(|d| d.code == Code::DeadService),
        "without time `Calibrate` may succeed: {untimed:?}"
    );
}
