//! Former disagreements between the engine and the contract found by the
//! independent checker (a codel ending exactly at the next wake-up, the
//! timed trace of `codel-overrun`, one `request` step per request with a
//! control codel, integer instants with a 1 ns unit), and the watchdogs of
//! looping services.

use super::support::{Expected, the, trace_lines, verify};
use super::traces_and_margins::{check_inline, timing_codes, worked_example};
use crate::common;

use std::path::Path;

use genom_model::{Code, Event, Trace, TraceStep};
use genom_oracles::replay::replay;
use genom_oracles::timed_trace::{TimedClaim, check_timed};
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
