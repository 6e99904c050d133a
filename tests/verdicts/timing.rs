//! The timing verdicts (`codel-overrun`, `thread-overrun`,
//! `max-time-infeasible`, `max-time-exceeded`, `max-time-watchdog`,
//! `missing-wcet`) and behavioural verdicts decided on a timed model, on
//! their fixtures and near-identical twins; their concrete timed traces,
//! checked step by step by an independent checker of the timing rules
//! (`tests/timed_trace/mod.rs`) and by the untimed replay
//! (`genom_checker::replay`); the exact margins of max-time on the worked
//! example of `docs/timing.md`, and a hand formula for the worst case; the
//! timing verdicts of `specs/`.
//!
//! Four disagreements found between the engine and the contract by the
//! independent checker are regression tests at the end of this file (a
//! codel ending exactly at the next wake-up, the timed trace of
//! `codel-overrun`, one `request` step per request with a control codel,
//! integer instants with a 1 ns unit).

#![allow(clippy::expect_used)] // test support code outside #[test] functions

use crate::common;

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use genom_check::{CheckOptions, CheckResult};
use genom_model::component::{Component, ServiceId};
use genom_model::duration::format_ns;
use genom_model::{Code, Diagnostic, Event, Severity, Trace, TraceStep};
use genom_oracles::replay::{Claim, replay, replay_claim};
use genom_oracles::timed_trace::{TimedClaim, check_timed, loops_without_bound};
use serde_json::Value;

/// The timing codes.
const TIMING: &[Code] = &[
    Code::CodelOverrun,
    Code::ThreadOverrun,
    Code::MaxTimeInfeasible,
    Code::MaxTimeExceeded,
    Code::MaxTimeWatchdog,
    Code::MissingWcet,
];

/// One step as `@TIME event service::codel -> outcome` (the violation
/// without its instant, which is any point after the deadline).
fn step_line(s: &TraceStep) -> String {
    let mut out = String::new();
    if s.event != Event::Violation {
        out.push_str(&format!(
            "@{} ",
            s.time_ns.map_or_else(|| "?".to_owned(), format_ns)
        ));
    }
    out.push_str(s.event.as_str());
    if let Some(t) = s.thread.as_deref().filter(|_| s.event == Event::WakeUp) {
        out.push_str(&format!(" {t}"));
    }
    match (&s.service, &s.codel) {
        (Some(svc), Some(k)) => out.push_str(&format!(" {svc}::{k}")),
        (Some(svc), None) => out.push_str(&format!(" {svc}")),
        _ => {}
    }
    if let Some(o) = &s.outcome {
        out.push_str(&format!(" -> {o}"));
    }
    out
}

fn trace_lines(t: &Trace) -> Vec<String> {
    t.steps.iter().map(step_line).collect()
}

/// The one diagnostic of `result` with this code and message.
fn the<'r>(result: &'r CheckResult, code: Code, message: &str, report: &str) -> &'r Diagnostic {
    let found: Vec<&Diagnostic> = result
        .diagnostics
        .iter()
        .filter(|d| d.code == code && d.message == message)
        .collect();
    assert_eq!(
        found.len(),
        1,
        "one `{code}` with message {message:?}:\n{report}"
    );
    found[0]
}

/// What one timed verdict of one fixture must be.
struct Expected<'a> {
    fixture: &'a str,
    code: Code,
    message: &'a str,
    line: usize,
    claim: TimedClaim<'a>,
    /// The steps as [`step_line`] writes them.
    trace: &'a [&'a str],
}

/// Checks the verdict's code, message, primary line and exact trace; then
/// the trace's timing, step by step, with the independent checker; then
/// the claim; then replays the raw trace (wake-ups and all) in the untimed
/// semantics.
fn verify(e: &Expected<'_>) -> (CheckResult, Trace) {
    let path = common::invalid(e.fixture);
    let result = common::check(&path);
    let report = common::render(&path, &result);
    let d = the(&result, e.code, e.message, &report);
    assert_eq!(
        common::primary_line(&result, d),
        e.line,
        "{}: primary line\n{report}",
        e.fixture
    );
    let trace = d.trace.clone().expect("a timed verdict has a trace");
    let c = common::component(&result);
    let checked = check_timed(c, &trace, e.claim);
    assert_eq!(
        trace_lines(&trace),
        e.trace,
        "{}: trace (the timing checker says {:?})\n{report}",
        e.fixture,
        checked.as_ref().map(|_| ())
    );
    assert!(
        trace.steps.iter().all(|s| s.time_ns.is_some()),
        "{}: every step has an instant",
        e.fixture
    );
    let end = checked.unwrap_or_else(|err| {
        panic!(
            "{}: the timing checker rejects the trace: {err}\n{report}",
            e.fixture
        )
    });
    match e.claim {
        TimedClaim::Overrun(thread) => {
            let t = c.thread_named(thread).expect("the thread exists");
            let period = c.threads[t].period.expect("a periodic thread").ns;
            let wakes = &end.wake_ups[thread];
            assert!(wakes.iter().all(|w| w % period == 0));
            assert_eq!(wakes.last(), Some(&end.last_ns), "ends at a wake-up");
        }
        TimedClaim::LateService(service) => {
            let s = c.service_named(service).expect("the service exists");
            let m = c.services[s].max_time.expect("a max-time").ns;
            let ack = end.late_ack_ns.expect("the instance's acknowledgment");
            assert!(end.last_ns > ack + m, "strictly after the deadline");
        }
        TimedClaim::PastDeadline(_, d) => {
            let ack = end.late_ack_ns.expect("the instance's acknowledgment");
            assert!(end.last_ns > ack + d, "strictly after the deadline");
        }
        TimedClaim::Rules => {}
    }
    if let Err(err) = replay(c, &trace) {
        panic!(
            "{}: the untimed replay rejects the events of the timed trace: {err}\n    {}",
            e.fixture,
            trace_lines(&trace).join("\n    ")
        );
    }
    (result, trace)
}

/// `bad` reports `code`; `good`, one line away from it (or one line
/// added), has no error or warning at all.
fn assert_twins(bad: &str, good: &str, code: Code) {
    let (bad_path, good_path) = (common::invalid(bad), common::valid(good));
    let changed = common::changed_lines(&common::body(&bad_path), &common::body(&good_path));
    assert!(
        changed <= 2,
        "{bad} and {good} differ by {changed} lines: one rule should change"
    );
    let bad_result = common::check(&bad_path);
    assert!(
        bad_result.diagnostics.iter().any(|d| d.code == code),
        "{bad} reports `{code}`:\n{}",
        common::render(&bad_path, &bad_result)
    );
    let good_result = common::check(&good_path);
    let report = common::render(&good_path, &good_result);
    assert!(
        !good_result.diagnostics.iter().any(|d| d.code == code),
        "{good} has no `{code}`:\n{report}"
    );
    assert!(
        common::codes(&good_result, Severity::Warning).is_empty(),
        "{good} is clean:\n{report}"
    );
    if code != Code::CodelOverrun {
        assert!(
            good_result.statistics.as_ref().is_some_and(|s| s.complete),
            "{good} is fully explored"
        );
    }
}

/// The fixture pairs of this file: (invalid, valid twin, code).
const TWINS: &[(&str, &str, Code)] = &[
    (
        "codel-overrun.wcet-longer-than-period.gen",
        "codel-wcet-within-period.gen",
        Code::CodelOverrun,
    ),
    (
        "thread-overrun.two-services-share-a-period.gen",
        "two-services-exclusive-by-stops.gen",
        Code::ThreadOverrun,
    ),
    (
        "thread-overrun.lock-wait-on-shared-ids.gen",
        "shared-ids-read-only.gen",
        Code::ThreadOverrun,
    ),
    (
        "thread-overrun.control-codel-holds-the-lock.gen",
        "control-codel-fits-the-period.gen",
        Code::ThreadOverrun,
    ),
    (
        "max-time-infeasible.three-codels-in-15ms.gen",
        "three-codels-in-30ms.gen",
        Code::MaxTimeInfeasible,
    ),
    (
        "max-time-exceeded.worked-example.gen",
        "worst-case-equals-max-time.gen",
        Code::MaxTimeExceeded,
    ),
    (
        "max-time-watchdog.servo-loop.gen",
        "bounded-service-with-max-time.gen",
        Code::MaxTimeWatchdog,
    ),
    (
        "missing-wcet.codel-without-wcet.gen",
        "every-codel-has-wcet.gen",
        Code::MissingWcet,
    ),
    (
        "unreachable-codel.watchdog-never-fires.gen",
        "watchdog-fires-at-the-deadline.gen",
        Code::UnreachableCodel,
    ),
    (
        "dead-service.init-always-times-out.gen",
        "init-ends-within-its-max-time.gen",
        Code::DeadService,
    ),
    (
        "max-time-exceeded.waits-for-a-looping-watchdog.gen",
        "looping-watchdog-fires-on-time.gen",
        Code::MaxTimeExceeded,
    ),
    (
        "unreachable-codel.looping-watchdog-fires-late.gen",
        "looping-watchdog-fires-early.gen",
        Code::UnreachableCodel,
    ),
];

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

// ------------------------------------------------------- every timed trace

/// Every trace of every verdict of the timed fixtures (and of `specs/`)
/// has an instant on each step, passes the independent timing checker,
/// and its events replay in the untimed semantics.
#[test]
fn every_timed_trace_is_a_timed_execution_and_replays() {
    let mut files: Vec<PathBuf> = TWINS
        .iter()
        .flat_map(|&(bad, good, _)| [common::invalid(bad), common::valid(good)])
        .collect();
    files.extend(spec_files());
    let mut checked = 0;
    let mut failures = Vec::new();
    for path in &files {
        let result = common::check(path);
        let Some(c) = result.component.as_ref() else {
            continue;
        };
        for d in &result.diagnostics {
            let Some(trace) = &d.trace else { continue };
            checked += 1;
            let names: Vec<&str> = d.message.split('`').skip(1).step_by(2).collect();
            let claim = match d.code {
                Code::ThreadOverrun => TimedClaim::Overrun(names[0]),
                Code::CodelOverrun => TimedClaim::Overrun(names[1]),
                Code::MaxTimeExceeded | Code::MaxTimeInfeasible => {
                    TimedClaim::LateService(names[0])
                }
                _ => TimedClaim::Rules,
            };
            let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
            if let Err(e) = check_timed(c, trace, claim) {
                failures.push(format!("{name}: `{}`: timing: {e}", d.code));
            }
            if let Err(e) = replay(c, trace) {
                failures.push(format!("{name}: `{}`: replay: {e}", d.code));
            }
        }
    }
    assert!(checked >= 7, "only {checked} traces");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The independent checker rejects traces whose timing is wrong.
#[test]
fn the_timing_checker_rejects_corrupted_timings() {
    let path = common::invalid("thread-overrun.two-services-share-a-period.gen");
    let result = common::check(&path);
    let c = common::component(&result);
    let d = result
        .diagnostics
        .iter()
        .find(|d| d.code == Code::ThreadOverrun)
        .expect("the overrun");
    let original = d.trace.clone().expect("a trace");
    let claim = TimedClaim::Overrun("servo");
    check_timed(c, &original, claim).expect("the original is accepted");
    let index = |line: &str| {
        trace_lines(&original)
            .iter()
            .position(|l| l == line)
            .expect("the step exists")
    };
    let corrupt = |k: usize, ns: u64| {
        let mut t = original.clone();
        t.steps[k].time_ns = Some(ns);
        check_timed(c, &t, claim).expect_err("the corrupted trace is rejected")
    };
    // A codel that ends after its WCET.
    let end = index("@16ms codel-end Track::start -> start");
    let mut late = original.clone();
    for s in &mut late.steps[end..] {
        s.time_ns = s.time_ns.map(|t| t.max(17_000_000));
    }
    let why = check_timed(c, &late, claim).expect_err("a codel longer than its WCET");
    assert!(
        why.contains("must have ended") || why.contains("WCET"),
        "{why}"
    );
    // A wake-up off the period (and the violation with it).
    let mut off = original.clone();
    let last = off.steps.len() - 1;
    for s in &mut off.steps[last - 1..] {
        s.time_ns = Some(21_000_000);
    }
    let why = check_timed(c, &off, claim).expect_err("a wake-up off the period");
    assert!(why.contains("should have woken up at 20000000"), "{why}");
    // Time going backwards.
    let why = corrupt(index("@16ms codel-start Scan::start"), 15_000_000);
    assert!(why.contains("backwards"), "{why}");
    // A thread idling although its codel could start (urgency).
    let mut idle = original.clone();
    let start = index("@10ms codel-start Track::start");
    idle.steps[start].time_ns = Some(11_000_000);
    let why = check_timed(c, &idle, claim).expect_err("codel starts are urgent");
    assert!(why.contains("at its turn"), "{why}");
    // Scan before Track although Track was acknowledged first.
    let mut swapped = original.clone();
    let scan = index("@16ms codel-start Scan::start");
    swapped.steps.swap(start, scan);
    swapped.steps[start].time_ns = Some(10_000_000);
    let why = check_timed(c, &swapped, claim).expect_err("acknowledgment order");
    assert!(
        why.contains("not its turn") || why.contains("still runs"),
        "{why}"
    );
    // An overrun claimed on the wrong thread.
    assert!(check_timed(c, &original, TimedClaim::Overrun("nothing")).is_err());
}

/// `--format json` gives `time_ns` on every step of a timed trace.
#[test]
fn json_timed_traces_have_an_instant_per_step() {
    let out = Command::cargo_bin("genom-check")
        .expect("binary is built")
        .args([
            "--format",
            "json",
            "tests/fixtures/invalid/thread-overrun.two-services-share-a-period.gen",
        ])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(1));
    let v: Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let d = &v["files"][0]["diagnostics"][0];
    assert_eq!(d["code"], "thread-overrun");
    let steps = d["trace"].as_array().expect("a trace");
    let times: Vec<u64> = steps
        .iter()
        .map(|s| s["time_ns"].as_u64().expect("time_ns is a number"))
        .collect();
    assert!(times.windows(2).all(|w| w[0] <= w[1]), "{times:?}");
    assert_eq!(times.last(), Some(&20_000_000));
}

// ------------------------------------------------------------ exact margins

/// The worked example of docs/timing.md with this max-time.
fn worked_example(max_time: &str) -> String {
    format!(
        "component servo {{ category: default; lang: C; }}\n\
         thread servoTask {{ priority: 50; period: 10ms; }}\n\
         service Step {{\n\
         \x20 thread: servoTask;\n\
         \x20 max-time: {max_time};\n\
         \x20 start codel {{ exec: servoStep(); max-time: 2ms; next: end; }}\n\
         }}\n"
    )
}

fn check_inline(src: &str) -> CheckResult {
    genom_check::check_source(
        Path::new("inline.gen"),
        src.to_owned(),
        &gen_frontend::MemoryLoader::new(),
        &CheckOptions::new(),
    )
}

fn timing_codes(result: &CheckResult) -> Vec<Code> {
    result
        .diagnostics
        .iter()
        .map(|d| d.code)
        .filter(|c| TIMING.contains(c))
        .collect()
}

/// The time unit of the timed model of the whole component.
fn unit_of(result: &CheckResult) -> u64 {
    let c = common::component(result);
    let all: Vec<ServiceId> = c.services.ids().collect();
    genom_checker::timed::clocks::unit_ns(c, &all)
}

/// Worst case 12 ms (acknowledged at a wake-up but run at the next one,
/// 10 ms later, then 2 ms of codel): a max-time of 12 ms is clean, and one
/// time unit less is reported, whatever the unit (which the max-time
/// itself changes: the unit is the GCD of 10 ms, 2 ms and the max-time).
#[test]
fn margins_are_exact_on_the_worked_example() {
    let cases: &[(&str, u64, bool)] = &[
        // (max-time, time unit in ns, exceeded)
        ("12ms", 2_000_000, false),
        ("10ms", 2_000_000, true), // 12 ms minus one unit of the 12 ms model
        ("11ms", 1_000_000, true), // 12 ms minus one unit of 1 ms
        ("11999999ns", 1, true),   // 12 ms minus one nanosecond
        ("12000001ns", 1, false),
        ("13ms", 1_000_000, false),
    ];
    for &(max_time, unit, exceeded) in cases {
        let result = check_inline(&worked_example(max_time));
        let report = common::render(Path::new("inline.gen"), &result);
        assert_eq!(unit_of(&result), unit, "max-time {max_time}: unit");
        let expected: &[Code] = if exceeded {
            &[Code::MaxTimeExceeded]
        } else {
            &[]
        };
        assert_eq!(
            timing_codes(&result),
            expected,
            "max-time {max_time}:\n{report}"
        );
        if exceeded {
            let d = &result.diagnostics[0];
            let trace = d.trace.as_ref().expect("a trace");
            let end = check_timed(
                common::component(&result),
                trace,
                TimedClaim::LateService("Step"),
            )
            .expect("a timed execution");
            let m = common::component(&result).services[ServiceId(0)]
                .max_time
                .expect("a max-time")
                .ns;
            assert!(end.last_ns > end.late_ack_ns.expect("acknowledged") + m);
        }
    }
}

/// A service of `n` codels on a thread of period `p`, each codel with
/// WCET `w`, and optionally another looping service with a codel of WCET
/// `b` on the same thread: by hand, the worst case from acknowledgment to
/// the end is `n·p + b + w` (acknowledged exactly at a wake-up but run at
/// the next one; then one codel per period, each after the other
/// service's codel when that one was acknowledged first), as long as
/// `b + w < p` (no overrun) — and the best case is `(n − 1)·p`.
fn chain(p: u64, n: usize, w: u64, b: Option<u64>, max_time_ns: u64) -> String {
    let mut src = format!(
        "component chain {{ category: default; lang: C; }}\n\
         thread t {{ period: {p}ns; }}\n\
         service S {{\n  thread: t;\n  max-time: {max_time_ns}ns;\n"
    );
    for i in 0..n {
        let name = if i == 0 {
            "start codel".to_owned()
        } else {
            format!("exec codel c{i}")
        };
        let next = if i + 1 == n {
            "end".to_owned()
        } else {
            format!("c{}", i + 1)
        };
        src.push_str(&format!(
            "  {name} {{ exec: f{i}(); max-time: {w}ns; next: {next}; }}\n"
        ));
    }
    src.push_str("}\n");
    if let Some(b) = b {
        src.push_str(&format!(
            "service B {{\n  thread: t;\n  start codel {{ exec: g(); max-time: {b}ns; next: start, end; }}\n}}\n"
        ));
    }
    src
}

#[test]
fn the_worst_case_matches_the_hand_formula() {
    let ms = 1_000_000;
    let cases: &[(u64, usize, u64, Option<u64>)] = &[
        (10 * ms, 1, 2 * ms, None),
        (10 * ms, 3, 4 * ms, None),
        (5 * ms, 2, ms, None),
        (7 * ms, 2, 3 * ms, None),
        (10 * ms, 2, 3 * ms, Some(4 * ms)),
        (20 * ms, 1, 5 * ms, Some(12 * ms)),
        (1_000_000, 2, 250_000, None),
    ];
    for &(p, n, w, b) in cases {
        let n64 = n as u64;
        let worst = n64 * p + b.unwrap_or(0) + w;
        let best = (n64 - 1) * p;
        let unit = [p, w, b.unwrap_or(0)].into_iter().fold(0, gcd);
        let run = |m: u64| {
            let src = chain(p, n, w, b, m);
            let result = check_inline(&src);
            let codes = timing_codes(&result);
            (codes, common::render(Path::new("inline.gen"), &result))
        };
        let label = format!("p={p} n={n} w={w} b={b:?}: worst {worst}, best {best}");
        let (codes, report) = run(worst);
        assert_eq!(
            codes,
            [],
            "{label}: max-time = worst case is clean\n{report}"
        );
        let (codes, report) = run(worst - unit);
        assert_eq!(
            codes,
            [Code::MaxTimeExceeded],
            "{label}: one unit less is exceeded\n{report}"
        );
        if best == 0 {
            continue; // a max-time must be positive
        }
        let (codes, report) = run(best);
        let expected: &[Code] = if best < worst {
            &[Code::MaxTimeExceeded]
        } else {
            &[]
        };
        assert_eq!(
            codes, expected,
            "{label}: max-time = best case is feasible\n{report}"
        );
        if best > unit {
            let (codes, report) = run(best - unit);
            assert_eq!(
                codes,
                [Code::MaxTimeInfeasible],
                "{label}: under the best case is infeasible\n{report}"
            );
        }
    }
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 { a } else { gcd(b, a % b) }
}

// ------------------------------------------------------------------ specs

fn spec_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(common::root().join("specs"))
        .expect("specs/ is readable")
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "gen"))
        .collect();
    files.sort();
    files
}

/// The timing verdicts of every file in `specs/`, as docs/timing.md
/// explains them.
#[test]
fn the_timing_verdicts_of_the_specs_are_the_documented_ones() {
    let expected: &[(&str, &[&str])] = &[
        (
            "arm.gen",
            &[
                "max-time-watchdog: `Calibrate` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 20ms",
                "max-time-watchdog: `MoveJoints` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 20ms",
            ],
        ),
        (
            "battery.gen",
            &[
                "max-time-watchdog: `CalibrateGauge` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 2s",
                "max-time-watchdog: `WaitCharged` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 1s",
            ],
        ),
        ("camera.gen", &[]),
        (
            "gripper.gen",
            &[
                "max-time-watchdog: `Home` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 20ms",
                "max-time-watchdog: `Open` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 20ms",
                "max-time-watchdog: `Grasp` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 30ms",
            ],
        ),
        (
            "localization.gen",
            &[
                "max-time-watchdog: `Init` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 200ms",
                "missing-wcet: 5 codels without WCET (`max-time`) are taken as running in no time",
            ],
        ),
        (
            "mobileBase.gen",
            &[
                "missing-wcet: 7 codels without WCET (`max-time`) are taken as running in no time",
                "max-time-watchdog: `GotoPosition` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 100ms",
            ],
        ),
        (
            "pilot.gen",
            &["missing-wcet: 4 codels without WCET (`max-time`) are taken as running in no time"],
        ),
    ];
    let mut found = Vec::new();
    for path in spec_files() {
        let result = common::check(&path);
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_default()
            .to_owned();
        let lines: Vec<String> = result
            .diagnostics
            .iter()
            .filter(|d| TIMING.contains(&d.code))
            .map(|d| format!("{}: {}", d.code, d.message))
            .collect();
        found.push((name, lines));
    }
    let expected: Vec<(String, Vec<String>)> = expected
        .iter()
        .map(|(n, l)| ((*n).to_owned(), l.iter().map(|s| (*s).to_owned()).collect()))
        .collect();
    assert_eq!(found, expected);
}

// ------------------------------------------ former disagreements (fixed)

/// A codel whose WCET equals its thread's period, alone on its thread,
/// always finishes by the next wake-up (it starts at a wake-up); LANGUAGE.md
/// section 3: a thread overruns when "its codels of one period have not
/// finished by the next wake-up". `codel-overrun` agrees (`>`), and the
/// max-time margin is "ending exactly at the deadline is in time". The
/// engine used to let the wake-up come before the codel's end at the same
/// instant; codel ends now come first. One nanosecond more is a
/// `codel-overrun`, with a trace where the thread overruns.
#[test]
fn a_codel_ending_exactly_at_the_next_wake_up_is_not_an_overrun() {
    let path = common::root().join("tests/fixtures/timing/wcet-equals-period.gen");
    let result = common::check(&path);
    let report = common::render(&path, &result);
    assert!(result.diagnostics.is_empty(), "{report}");
    assert!(
        result.statistics.as_ref().is_some_and(|s| s.complete),
        "fully explored"
    );
    let text = std::fs::read_to_string(&path).expect("readable");
    let longer = check_inline(&text.replace("max-time: 10ms", "max-time: 10000001ns"));
    let report = common::render(Path::new("inline.gen"), &longer);
    assert_eq!(timing_codes(&longer), [Code::CodelOverrun], "{report}");
    let d = &longer.diagnostics[0];
    let trace = d.trace.as_ref().expect("a trace");
    let end = check_timed(
        common::component(&longer),
        trace,
        TimedClaim::Overrun("servoTask"),
    )
    .unwrap_or_else(|e| panic!("{e}\n{report}"));
    assert_eq!(end.last_ns % 10_000_000, 0, "ends at a wake-up");
}

/// Services of one period whose codels (with lock waits) take exactly the
/// period are in time; one time unit (here 1 ns) more is a
/// `thread-overrun`, whose trace the independent checker accepts as a
/// genuine overrun. `what` names the case; `{W}` in `src` is replaced by
/// the WCET that makes the sum exact, in ns.
fn exact_overrun(what: &str, src: &str, exact_ns: u64, thread: &str, base: &[Code]) {
    let at = |w: u64| check_inline(&src.replace("{W}", &format!("{w}ns")));
    let result = at(exact_ns);
    let report = common::render(Path::new("inline.gen"), &result);
    assert_eq!(
        timing_codes(&result),
        base,
        "{what}: exactly the period\n{report}"
    );
    assert!(
        result.statistics.as_ref().is_some_and(|s| s.complete),
        "{what}: fully explored"
    );
    let result = at(exact_ns + 1);
    let report = common::render(Path::new("inline.gen"), &result);
    let mut expected = base.to_vec();
    expected.push(Code::ThreadOverrun);
    expected.sort_by_key(|c| c.as_str());
    let mut found = timing_codes(&result);
    found.sort_by_key(|c| c.as_str());
    assert_eq!(found, expected, "{what}: one nanosecond more\n{report}");
    let d = result
        .diagnostics
        .iter()
        .find(|d| d.code == Code::ThreadOverrun)
        .expect("thread-overrun");
    let trace = d.trace.as_ref().expect("a trace");
    let c = common::component(&result);
    check_timed(c, trace, TimedClaim::Overrun(thread))
        .unwrap_or_else(|e| panic!("{what}: {e}\n{report}"));
    replay(c, trace).unwrap_or_else(|e| panic!("{what}: replay: {e}\n{report}"));
}

#[test]
fn work_that_takes_exactly_the_period_is_in_time() {
    // Two services on one thread: 4 ms + 6 ms in a 10 ms period.
    exact_overrun(
        "two services",
        "component c { category: default; lang: C; }\n\
         thread servo { period: 10ms; }\n\
         service A { thread: servo; start codel { exec: fa(); max-time: 4ms; next: start, end; } }\n\
         service B { thread: servo; start codel { exec: fb(); max-time: {W}; next: start, end; } }\n",
        6_000_000,
        "servo",
        &[],
    );
    // A lock held by another thread's codel for 6 ms, then 4 ms of codel.
    exact_overrun(
        "lock wait",
        "component c { category: default; lang: C; }\n\
         ids joints { double q := 0.0; }\n\
         thread servo { period: 10ms; }\n\
         thread log { period: 50ms; }\n\
         service Servo { thread: servo; start codel { exec: fs(const joints.q); max-time: 4ms; next: start, end; } }\n\
         service Record { thread: log; start codel { exec: fr(joints.q); max-time: {W}; next: start, end; } }\n",
        6_000_000,
        "servo",
        &[],
    );
    // A control codel holding the lock for 4 ms, then 6 ms of codel.
    exact_overrun(
        "control codel",
        "component c { category: default; lang: C; }\n\
         ids gains { double kp := 1.0; }\n\
         thread servo { period: 10ms; }\n\
         service Servo { thread: servo; start codel { exec: fs(gains.kp); max-time: 6ms; next: start, end; } }\n\
         service SetGain { report: BAD; input: gains.kp; control codel { exec: check(gains.kp); max-time: {W}; } }\n",
        4_000_000,
        "servo",
        &[],
    );
    // A codel without WCET (no time) waiting for a lock that another
    // thread's codel, started at the same wake-up, holds for up to 10 ms:
    // released at the next wake-up, it runs then, in time; held 1 ns
    // longer, the thread overruns.
    exact_overrun(
        "zero-time codel behind a lock",
        "component c { category: default; lang: C; }\n\
         ids joints { double q := 0.0; }\n\
         thread servo { period: 10ms; }\n\
         thread slow { period: 50ms; }\n\
         service Servo { thread: servo; start codel { exec: fs(joints.q); next: start, end; } }\n\
         service Log { thread: slow; start codel { exec: fl(joints.q); max-time: {W}; next: start, end; } }\n",
        10_000_000,
        "servo",
        &[Code::MissingWcet],
    );
}

/// A codel that may use the whole period, with another service to run a
/// codel in the same period: the thread overruns, with a genuine witness
/// (when `A` runs first and ends exactly at the wake-up, `B` has not run
/// and may take time; the witness never shows a codel that has used its
/// whole WCET still running at the wake-up).
#[test]
fn a_full_period_codel_before_another_service_overruns() {
    let result = check_inline(
        "component c { category: default; lang: C; }\n\
         thread servo { period: 10ms; }\n\
         service A { thread: servo; start codel { exec: fa(); max-time: 10ms; next: start, end; } }\n\
         service B { thread: servo; start codel { exec: fb(); max-time: 1ms; next: start, end; } }\n",
    );
    let report = common::render(Path::new("inline.gen"), &result);
    assert_eq!(timing_codes(&result), [Code::ThreadOverrun], "{report}");
    let trace = result.diagnostics[0].trace.as_ref().expect("a trace");
    let c = common::component(&result);
    // The claim: at the wake-up, a codel still running has time left
    // before its WCET, or a codel still to run has a positive WCET; never a
    // codel running with its whole WCET used (that one ends first).
    check_timed(c, trace, TimedClaim::Overrun("servo")).unwrap_or_else(|e| panic!("{e}\n{report}"));
    replay(c, trace).unwrap_or_else(|e| panic!("replay: {e}\n{report}"));
}

/// Every timing verdict carries a concrete timed trace (issue 5), also
/// `codel-overrun`, a static check: the engines still run when it is the
/// only error, and the trace shows the codel still running when its
/// thread wakes up again (a genuine overrun for the independent checker).
#[test]
fn codel_overrun_carries_a_timed_trace() {
    verify(&Expected {
        fixture: "codel-overrun.wcet-longer-than-period.gen",
        code: Code::CodelOverrun,
        message: "codel `Servo::step` may take 12ms but thread `servoTask` wakes up every 10ms",
        line: 16,
        claim: TimedClaim::Overrun("servoTask"),
        trace: &[
            "@0 component-start",
            "@0 wake-up servoTask",
            "@10ms request Servo",
            "@10ms acknowledge Servo",
            "@10ms start Servo::start",
            "@10ms wake-up servoTask",
            "@10ms codel-start Servo::start",
            "@11ms codel-end Servo::start -> step",
            "@20ms wake-up servoTask",
            "@20ms codel-start Servo::step",
            "@30ms wake-up servoTask",
            "violation",
        ],
    });
    // The thread overrun it implies is not reported a second time.
    let path = common::invalid("codel-overrun.wcet-longer-than-period.gen");
    let result = common::check(&path);
    assert_eq!(
        timing_codes(&result),
        [Code::CodelOverrun],
        "{}",
        common::render(&path, &result)
    );
}

/// A timed trace with a control codel writes the request once, when the
/// control codel begins (`request S`, codel `control`), then `accept` or
/// `reject` when it ends; the untimed replay reads the raw trace, with
/// the other threads' steps inside the open request.
#[test]
fn a_request_with_a_control_codel_is_one_request_step() {
    let path = common::invalid("thread-overrun.control-codel-holds-the-lock.gen");
    let result = common::check(&path);
    let d = result
        .diagnostics
        .iter()
        .find(|d| d.code == Code::ThreadOverrun)
        .expect("thread-overrun");
    let trace = d.trace.as_ref().expect("a trace");
    let requests: Vec<&TraceStep> = trace
        .steps
        .iter()
        .filter(|s| s.event == Event::Request && s.service.as_deref() == Some("SetGain"))
        .collect();
    assert_eq!(requests.len(), 1, "{:?}", trace_lines(trace));
    assert_eq!(requests[0].codel.as_deref(), Some("control"));
    let replayed = replay(common::component(&result), trace).map(|_| ());
    assert!(
        replayed.is_ok(),
        "raw replay: {replayed:?}\n    {}",
        trace_lines(trace).join("\n    ")
    );
    // The replay still refuses a codel that conflicts with the running
    // control codel, and a second request while it runs.
    let c = common::component(&result);
    let lines = trace_lines(trace);
    let at = |l: &str| lines.iter().position(|x| x == l).expect("the step");
    let mut early = trace.clone();
    let start = early.steps.remove(at("@15ms codel-start Servo::start"));
    early.steps.insert(at("@10ms wake-up servoTask") + 1, start);
    let e = replay(c, &early).expect_err("Servo takes the lock of the control codel");
    assert!(
        e.to_string().contains("conflicts with the control codel"),
        "{e}"
    );
    let mut twice = trace.clone();
    let request = twice.steps[at("@10ms request SetGain::control")].clone();
    twice
        .steps
        .insert(at("@10ms wake-up servoTask") + 1, request);
    let e = replay(c, &twice).expect_err("one request at a time");
    assert!(e.to_string().contains("one request at a time"), "{e}");
}

/// The max-time-exceeded trace's last instant is strictly after the
/// acknowledgment plus the max-time, in whole nanoseconds, also with a
/// 1 ns time unit (max-time 11999999ns in the worked example): the engine
/// picks an integer point of the final zone (12 ms here), where it used to
/// round a fractional point down onto the deadline.
#[test]
fn the_late_instant_is_after_the_deadline_with_a_nanosecond_unit() {
    let result = check_inline(&worked_example("11999999ns"));
    let d = result
        .diagnostics
        .iter()
        .find(|d| d.code == Code::MaxTimeExceeded)
        .expect("max-time-exceeded");
    let trace = d.trace.as_ref().expect("a trace");
    let end = check_timed(
        common::component(&result),
        trace,
        TimedClaim::LateService("Step"),
    )
    .unwrap_or_else(|e| panic!("{e}\n    {}", trace_lines(trace).join("\n    ")));
    assert_eq!(end.late_ack_ns, Some(0));
    assert_eq!(
        end.last_ns, 12_000_000,
        "the first whole nanosecond after the deadline"
    );
}

// ------------------------------------------- watchdogs of looping services

/// The instant of the first step `event` of `service` in `trace`.
fn instant_of(trace: &Trace, event: Event, service: &str) -> (usize, u64) {
    trace
        .steps
        .iter()
        .enumerate()
        .find(|(_, s)| s.event == event && s.service.as_deref() == Some(service))
        .and_then(|(k, s)| Some((k, s.time_ns?)))
        .expect("the step is in the trace")
}

/// `poll` loops without bound; its watchdog fires exactly 75 ms after its
/// acknowledgment (not later: the twin with 120 ms is clean), so `user`
/// misses 100 ms but not 120 ms. The trace shows the watchdog on time, and
/// the independent timed checker rejects it 1 ms early or late.
#[test]
fn the_watchdog_of_a_looping_service_fires_exactly_at_its_max_time() {
    let path = common::invalid("max-time-exceeded.waits-for-a-looping-watchdog.gen");
    let result = common::check(&path);
    let report = common::render(&path, &result);
    let d = the(
        &result,
        Code::MaxTimeExceeded,
        "`user` can miss its max-time of 100ms",
        &report,
    );
    let trace = d
        .trace
        .as_ref()
        .expect("a max-time-exceeded verdict has a trace");
    let c = common::component(&result);
    check_timed(c, trace, TimedClaim::LateService("user")).expect("a timed execution");
    replay(c, trace).expect("the untimed replay accepts it");
    let (_, ack) = instant_of(trace, Event::Acknowledge, "poll");
    let (k, fired) = instant_of(trace, Event::Watchdog, "poll");
    assert_eq!(fired - ack, 75_000_000, "{report}");
    for shifted in [fired - 1_000_000, fired + 1_000_000] {
        let mut wrong = trace.clone();
        wrong.steps[k].time_ns = Some(shifted);
        let why = check_timed(c, &wrong, TimedClaim::LateService("user"))
            .expect_err("a watchdog off its deadline is rejected");
        assert!(why.contains("watchdog"), "{why}");
    }
    let clean = common::check(&common::valid("looping-watchdog-fires-on-time.gen"));
    assert!(
        !clean
            .diagnostics
            .iter()
            .any(|d| d.code == Code::MaxTimeExceeded),
        "{}",
        common::render(&common::valid("looping-watchdog-fires-on-time.gen"), &clean)
    );
}

/// The example verbatim: nothing but the watchdog interrupts
/// `spin`, 40 ms after its acknowledgment, long after its start codel ran:
/// `soon` is unreachable, `later` is not.
#[test]
fn an_inter_codel_only_an_early_watchdog_would_run_is_unreachable() {
    let src = "component w2 { category: default; lang: C; }
thread t { period: 10ms; }
service spin { thread: t; max-time: 40ms;
  start codel { exec: s(); max-time: 1ms; on-inter: soon; next: loop; }
  exec codel loop { exec: s(); max-time: 1ms; on-inter: later; next: loop; }
  inter codel soon { exec: c(); max-time: 1ms; next: end; }
  inter codel later { exec: c(); max-time: 1ms; next: end; } }
";
    let result = check_inline(src);
    let unreachable: Vec<&str> = result
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::UnreachableCodel)
        .map(|d| d.message.as_str())
        .collect();
    assert_eq!(
        unreachable,
        ["inter codel `soon` of service `spin` is never reached in any execution"]
    );
}

/// Auto services that delay and forbid each other all start when the
/// component starts (they are never pending): no deadlock, starvation or
/// dead service, and no `acknowledge` step for them in any trace.
#[test]
fn auto_services_start_whatever_they_say_about_each_other() {
    for name in [
        "autos-delay-each-other.gen",
        "auto-forbidden-and-delayed-by-auto.gen",
    ] {
        let path = common::valid(name);
        let result = common::check(&path);
        let report = common::render(&path, &result);
        for code in [Code::Deadlock, Code::Starvation, Code::DeadService] {
            assert!(
                !result.diagnostics.iter().any(|d| d.code == code),
                "{name}: no `{code}`:\n{report}"
            );
        }
        assert!(
            result.statistics.as_ref().is_some_and(|s| s.complete),
            "{name}"
        );
    }
}
