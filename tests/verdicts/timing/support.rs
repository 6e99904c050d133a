//! Shared helpers of the timing verdict tests: the timing codes, traces as
//! lines, `verify` (a verdict with its message, line and exact trace,
//! checked by the independent timing checker and replayed untimed), and
//! the fixtures' near-identical twins.

use crate::common;

use genom_check::CheckResult;
use genom_model::duration::format_ns;
use genom_model::{Code, Diagnostic, Event, Severity, Trace, TraceStep};
use genom_oracles::replay::replay;
use genom_oracles::timed_trace::{TimedClaim, check_timed};
/// The timing codes.
pub(crate) const TIMING: &[Code] = &[
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

pub(crate) fn trace_lines(t: &Trace) -> Vec<String> {
    t.steps.iter().map(step_line).collect()
}

/// The one diagnostic of `result` with this code and message.
pub(crate) fn the<'r>(
    result: &'r CheckResult,
    code: Code,
    message: &str,
    report: &str,
) -> &'r Diagnostic {
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
pub(crate) struct Expected<'a> {
    pub(crate) fixture: &'a str,
    pub(crate) code: Code,
    pub(crate) message: &'a str,
    pub(crate) line: usize,
    pub(crate) claim: TimedClaim<'a>,
    /// The steps as [`step_line`] writes them.
    pub(crate) trace: &'a [&'a str],
}

/// Checks the verdict's code, message, primary line and exact trace; then
/// the trace's timing, step by step, with the independent checker; then
/// the claim; then replays the raw trace (wake-ups and all) in the untimed
/// semantics.
pub(crate) fn verify(e: &Expected<'_>) -> (CheckResult, Trace) {
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
pub(crate) fn assert_twins(bad: &str, good: &str, code: Code) {
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
pub(crate) const TWINS: &[(&str, &str, Code)] = &[
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
