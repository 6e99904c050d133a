//! The behavioural verdicts (deadlock, starvation, dead-service,
//! unbounded-interrupt, and the dynamic part of unreachable-codel) on their
//! fixtures: each invalid fixture's verdict with its message, primary line
//! and exact trace; each trace replayed step by step by the independent
//! interpreter of LANGUAGE.md section 3 (`genom_checker::replay`), which
//! also checks that the end of the trace shows the claimed violation; the
//! near-identical valid twins, which must not have the verdict; corrupted
//! traces, which the replay must reject; the JSON form of a trace; and the
//! `incomplete` verdict when a state limit stops exploration.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

use crate::common;

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use gen_frontend::FsLoader;
use genom_check::{CheckOptions, CheckResult};
use genom_checker::Engine;
use genom_model::component::{Component, Outcome};
use genom_model::{Code, Diagnostic, Event, Trace, TraceStep};
use genom_oracles::replay::{Claim, ReplayError, replay, replay_claim};
use serde_json::Value;

/// The behavioural codes this file is about.
const BEHAVIOURAL: &[Code] = &[
    Code::Deadlock,
    Code::Starvation,
    Code::DeadService,
    Code::UnboundedInterrupt,
];

/// The `.gen` files of a directory (relative to the workspace root), sorted.
fn gen_files(dir: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(common::root().join(dir))
        .expect("directory is readable")
        .map(|e| e.expect("directory entry is readable").path())
        .filter(|p| p.extension().is_some_and(|e| e == "gen"))
        .collect();
    files.sort();
    files
}

/// One trace step as `event service::codel -> outcome` (absent parts left
/// out): the exact (event, service, codel, outcome) of the step.
fn step_line(s: &TraceStep) -> String {
    let mut out = s.event.as_str().to_owned();
    match (&s.service, &s.codel) {
        (Some(svc), Some(k)) => out.push_str(&format!(" {svc}::{k}")),
        (Some(svc), None) => out.push_str(&format!(" {svc}")),
        (None, Some(k)) => out.push_str(&format!(" ::{k}")),
        (None, None) => {}
    }
    if let Some(o) = &s.outcome {
        out.push_str(&format!(" -> {o}"));
    }
    out
}

fn trace_lines(t: &Trace) -> Vec<String> {
    t.steps.iter().map(step_line).collect()
}

/// The names quoted with backticks in a message, in order.
fn quoted(message: &str) -> Vec<&str> {
    message.split('`').skip(1).step_by(2).collect()
}

/// The claim a behavioural verdict makes, read from its code and message.
fn claim_of<'a>(d: &'a Diagnostic, names: &'a [&'a str]) -> Claim<'a> {
    match d.code {
        Code::Deadlock => Claim::Deadlock(names),
        Code::Starvation => Claim::Starvation {
            waiter: names[0],
            blocker: names[1],
        },
        Code::UnboundedInterrupt => Claim::UnboundedInterrupt(names[0]),
        Code::DeadService => Claim::DeadService(names[0]),
        other => panic!("`{other}` has no trace to replay"),
    }
}

/// What one verdict of one invalid fixture must be, to the step.
struct Expected<'a> {
    fixture: &'a str,
    code: Code,
    message: &'a str,
    line: usize,
    help: Option<&'a str>,
    /// The steps as [`step_line`] writes them.
    trace: &'a [&'a str],
    /// Index (0-based) of the first step of the repeating cycle.
    loop_start: Option<usize>,
    claim: Claim<'a>,
}

/// Checks the verdict's code, message, primary line, help and trace, then
/// replays the trace and checks the claim.
fn verify(e: &Expected<'_>) {
    let path = common::invalid(e.fixture);
    let result = common::check(&path);
    let report = common::render(&path, &result);
    let found: Vec<&Diagnostic> = result
        .diagnostics
        .iter()
        .filter(|d| d.code == e.code && d.message == e.message)
        .collect();
    assert_eq!(
        found.len(),
        1,
        "{}: one `{}` with message {:?}:\n{report}",
        e.fixture,
        e.code,
        e.message
    );
    let d = found[0];
    assert_eq!(
        common::primary_line(&result, d),
        e.line,
        "{}: primary line\n{report}",
        e.fixture
    );
    if let Some(help) = e.help {
        assert_eq!(d.help.as_deref(), Some(help), "{}: help", e.fixture);
    }
    let trace = d.trace.as_ref().expect("a behavioural verdict has a trace");
    let c = common::component(&result);
    let replayed = replay_claim(c, trace, e.claim)
        .map(|_| ())
        .map_err(|err| err.to_string());
    assert_eq!(
        trace_lines(trace),
        e.trace,
        "{}: trace (the replay says: {replayed:?})\n{report}",
        e.fixture
    );
    assert_eq!(
        trace.steps.first().map(|s| s.event),
        Some(Event::ComponentStart)
    );
    assert_eq!(trace.steps.last().map(|s| s.event), Some(Event::Violation));
    assert_eq!(trace.loop_start, e.loop_start, "{}: loop start", e.fixture);
    if e.loop_start.is_some() {
        assert_lasso(c, trace);
    }
    if let Err(err) = replayed {
        panic!(
            "{}: the replay rejects the `{}` trace: {err}\n{report}",
            e.fixture, e.code
        );
    }
}

/// Where a step leaves its service's instance, seen from the step alone:
/// running a codel, or ready at the next one (for an interrupted codel,
/// its `on-inter`).
fn position_after(c: &Component, s: &TraceStep) -> Option<(String, String, bool)> {
    let svc = s.service.clone()?;
    let codel = s.codel.clone()?;
    let sid = c.service_named(&svc)?;
    match s.event {
        Event::CodelStart => Some((svc, codel, true)),
        Event::CodelEnd => {
            let next = match &s.outcome {
                Some(o) => o.clone(),
                None => {
                    let k = c.codel_named(sid, &codel)?;
                    let inter = c.codels[k].on_inter?;
                    c.codels[inter.id].name.name.clone()
                }
            };
            Some((svc, next, false))
        }
        _ => None,
    }
}

/// Where `svc` is at the end of `steps`: after its last codel step, or, when
/// an interrupt (the watchdog) came after a codel end, ready at that
/// codel's `on-inter`.
fn position_before_loop(
    c: &Component,
    steps: &[TraceStep],
    svc: Option<&str>,
) -> Option<(String, String, bool)> {
    let mine: Vec<&TraceStep> = steps
        .iter()
        .filter(|s| s.service.as_deref() == svc)
        .collect();
    let k = mine.iter().rposition(|s| position_after(c, s).is_some())?;
    let at = position_after(c, mine[k])?;
    let interrupted = mine[k + 1..]
        .iter()
        .any(|s| matches!(s.event, Event::Watchdog | Event::Interrupt));
    if !interrupted || at.2 {
        return Some(at);
    }
    let sid = c.service_named(&at.0)?;
    let ran = c.codel_named(sid, mine[k].codel.as_deref()?)?;
    let inter = c.codels[ran].on_inter?;
    Some((at.0, c.codels[inter.id].name.name.clone(), false))
}

/// The steps from `loop_start` to the violation form a cycle: they are codel
/// steps (and, on a timed model, the wake-ups that let them run), and the
/// last one leaves its service where it was just before the
/// loop began (the replay checks the whole state; this checks the trace's
/// shape on its own).
fn assert_lasso(c: &Component, t: &Trace) {
    let start = t.loop_start.expect("a lasso trace has a loop start");
    let last = t.steps.len() - 1;
    assert!(
        start > 0 && start < last,
        "loop start {start} inside the trace"
    );
    let cycle = &t.steps[start..last];
    assert!(
        cycle
            .iter()
            .all(|s| matches!(s.event, Event::CodelStart | Event::CodelEnd | Event::WakeUp)),
        "the repeating steps are codel steps: {:?}",
        trace_lines(t)
    );
    let svc = cycle
        .iter()
        .find(|s| s.event == Event::CodelStart)
        .and_then(|s| s.service.clone());
    let before = position_before_loop(c, &t.steps[..start], svc.as_deref());
    let after = position_after(c, &t.steps[last - 1]);
    assert!(before.is_some(), "the looping service ran before the loop");
    assert_eq!(
        before,
        after,
        "the loop returns to where it began: {:?}",
        trace_lines(t)
    );
}

// ---------------------------------------------------------------- deadlock

#[test]
fn deadlock_circular_wait_through_delays() {
    verify(&Expected {
        fixture: "deadlock.circular-delays.gen",
        code: Code::Deadlock,
        message: "deadlock: `Grasp` and `Release` can be pending and wait on each other forever",
        line: 25,
        help: Some(
            "break the cycle: remove one of these `delays`, or use `forbids` to make the services exclusive",
        ),
        trace: &[
            "component-start",
            "request Calibrate",
            "acknowledge Calibrate",
            "start Calibrate::start",
            "request Grasp",
            "acknowledge Grasp",
            "request Release",
            "acknowledge Release",
            "violation",
        ],
        loop_start: None,
        claim: Claim::Deadlock(&["Grasp", "Release"]),
    });
}

#[test]
fn deadlock_three_way_cycle() {
    verify(&Expected {
        fixture: "deadlock.three-way-cycle.gen",
        code: Code::Deadlock,
        message: "deadlock: `Localize`, `Plan` and `Drive` can be pending and wait on each other forever",
        line: 26,
        help: None,
        trace: &[
            "component-start",
            "request Map",
            "acknowledge Map",
            "start Map::start",
            "request Localize",
            "acknowledge Localize",
            "request Plan",
            "acknowledge Plan",
            "request Drive",
            "acknowledge Drive",
            "violation",
        ],
        loop_start: None,
        claim: Claim::Deadlock(&["Localize", "Plan", "Drive"]),
    });
}

// -------------------------------------------------------------- starvation

#[test]
fn starvation_behind_an_auto_service() {
    verify(&Expected {
        fixture: "starvation.behind-auto-service.gen",
        code: Code::Starvation,
        message: "`Calibrate` can wait forever for `Stream`, which may never end",
        line: 38,
        help: Some(
            "give `Stream` a `max-time` or an exit from its loop, or do not make `Calibrate` wait for it",
        ),
        trace: &[
            "component-start",
            "start Stream::start",
            "request Calibrate",
            "acknowledge Calibrate",
            "codel-start Stream::start",
            "codel-end Stream::start -> grab",
            "codel-start Stream::grab",
            "codel-end Stream::grab -> grab",
            "violation",
        ],
        loop_start: Some(6),
        claim: Claim::Starvation {
            waiter: "Calibrate",
            blocker: "Stream",
        },
    });
}

#[test]
fn starvation_behind_a_loop_without_max_time() {
    verify(&Expected {
        fixture: "starvation.behind-endless-loop.gen",
        code: Code::Starvation,
        message: "`Park` can wait forever for `Track`, which may never end",
        line: 24,
        help: Some(
            "give `Track` a `max-time` or an exit from its loop, or do not make `Park` wait for it",
        ),
        trace: &[
            "component-start",
            "request Track",
            "acknowledge Track",
            "start Track::start",
            "request Park",
            "acknowledge Park",
            "codel-start Track::start",
            "codel-end Track::start -> follow",
            "codel-start Track::follow",
            "codel-end Track::follow -> follow",
            "violation",
        ],
        loop_start: Some(8),
        claim: Claim::Starvation {
            waiter: "Park",
            blocker: "Track",
        },
    });
}

/// The trace goes through initialisation: `Open` replies `end` once, then
/// the auto service is acknowledged. (The explorer currently adds a second
/// `reply` step for `Open`, with no value, to say that initialisation
/// completes: section 3 gives each instance exactly one final reply.)
#[test]
fn starvation_behind_an_auto_service_started_by_init() {
    verify(&Expected {
        fixture: "starvation.auto-started-by-init.gen",
        code: Code::Starvation,
        message: "`Calibrate` can wait forever for `Sample`, which may never end",
        line: 39,
        help: None,
        trace: &[
            "component-start",
            "request Open",
            "acknowledge Open",
            "start Open::start",
            "codel-start Open::start",
            "codel-end Open::start -> end",
            "reply Open -> end",
            "start Sample::start",
            "request Calibrate",
            "acknowledge Calibrate",
            "codel-start Sample::start",
            "codel-end Sample::start -> start",
            "codel-start Sample::start",
            "violation",
        ],
        loop_start: Some(11),
        claim: Claim::Starvation {
            waiter: "Calibrate",
            blocker: "Sample",
        },
    });
}

#[test]
fn starvation_of_a_service_delayed_by_an_auto_service() {
    verify(&Expected {
        fixture: "dead-service.delayed-by-auto.gen",
        code: Code::Starvation,
        message: "`Update` can wait forever for `Heartbeat`, which may never end",
        line: 24,
        help: None,
        trace: &[
            "component-start",
            "start Heartbeat::start",
            "request Update",
            "acknowledge Update",
            "codel-start Heartbeat::start",
            "codel-end Heartbeat::start -> beat",
            "codel-start Heartbeat::beat",
            "codel-end Heartbeat::beat -> beat",
            "violation",
        ],
        loop_start: Some(6),
        claim: Claim::Starvation {
            waiter: "Update",
            blocker: "Heartbeat",
        },
    });
}

// ------------------------------------------------------------ dead-service

/// Every request is rejected with `NOT_INITIALIZED`; the rejection step
/// gives that reason in `outcome`, as the trace format says.
#[test]
fn dead_services_behind_an_init_service_that_never_succeeds() {
    for (service, line) in [("Move", 25), ("GetPosition", 32)] {
        let message = format!("service `{service}` can never start");
        let request = format!("request {service}");
        let reject = format!("reject {service} -> NOT_INITIALIZED");
        verify(&Expected {
            fixture: "dead-service.init-never-succeeds.gen",
            code: Code::DeadService,
            message: &message,
            line,
            help: Some("NOT_INITIALIZED, because `Connect` can never complete successfully"),
            trace: &["component-start", &request, &reject, "violation"],
            loop_start: None,
            claim: Claim::DeadService(service),
        });
    }
}

#[test]
fn dead_service_forbidden_by_an_auto_service() {
    verify(&Expected {
        fixture: "dead-service.forbidden-by-auto.gen",
        code: Code::DeadService,
        message: "service `Calibrate` can never start",
        line: 24,
        help: Some("FORBIDDEN by `Monitor`, which runs forever"),
        trace: &[
            "component-start",
            "start Monitor::start",
            "request Calibrate",
            "reject Calibrate -> FORBIDDEN",
            "violation",
        ],
        loop_start: None,
        claim: Claim::DeadService("Calibrate"),
    });
}

#[test]
fn dead_service_delayed_by_an_auto_service() {
    verify(&Expected {
        fixture: "dead-service.delayed-by-auto.gen",
        code: Code::DeadService,
        message: "service `Update` can never start",
        line: 24,
        help: Some("`Update` is acknowledged but never starts: it is always delayed or waiting"),
        trace: &[
            "component-start",
            "start Heartbeat::start",
            "request Update",
            "acknowledge Update",
            "violation",
        ],
        loop_start: None,
        claim: Claim::DeadService("Update"),
    });
}

// ----------------------------------------------------- unbounded-interrupt

/// The second `Move` request interrupts the first while `start` runs; the
/// first then loops in `brake` forever.
const SELF_STOP_INTO_BRAKE: &[&str] = &[
    "component-start",
    "request Move",
    "acknowledge Move",
    "start Move::start",
    "codel-start Move::start",
    "request Move",
    "interrupt Move::start",
    "acknowledge Move",
    "codel-end Move::start",
    "codel-start Move::brake",
    "codel-end Move::brake -> brake",
    "violation",
];

#[test]
fn unbounded_interrupt_looping_inter_codel() {
    verify(&Expected {
        fixture: "unbounded-interrupt.looping-inter-codel.gen",
        code: Code::UnboundedInterrupt,
        message: "`Move` may never end once interrupted: its inter codels can loop forever",
        line: 16,
        help: Some("give the inter codels a way to `end` (or a report): cleanup must terminate"),
        trace: SELF_STOP_INTO_BRAKE,
        loop_start: Some(9),
        claim: Claim::UnboundedInterrupt("Move"),
    });
}

#[test]
fn unbounded_interrupt_even_when_the_loop_has_an_exit() {
    verify(&Expected {
        fixture: "unbounded-interrupt.loop-with-exit.gen",
        code: Code::UnboundedInterrupt,
        message: "`Move` may never end once interrupted: its inter codels can loop forever",
        line: 17,
        help: None,
        trace: SELF_STOP_INTO_BRAKE,
        loop_start: Some(9),
        claim: Claim::UnboundedInterrupt("Move"),
    });
}

#[test]
fn unbounded_interrupt_after_the_watchdog() {
    verify(&Expected {
        fixture: "unbounded-interrupt.watchdog-cleanup-loop.gen",
        code: Code::UnboundedInterrupt,
        message: "`Home` may never end once interrupted: its inter codels can loop forever",
        line: 13,
        help: None,
        trace: &[
            "component-start",
            "wake-up",
            "request Home",
            "acknowledge Home",
            "start Home::start",
            "wake-up",
            "codel-start Home::start",
            "codel-end Home::start -> seek",
            "wake-up",
            "codel-start Home::seek",
            "codel-end Home::seek -> seek",
            "wake-up",
            "codel-start Home::seek",
            "codel-end Home::seek -> seek",
            "watchdog Home::seek",
            "wake-up",
            "codel-start Home::retract",
            "codel-end Home::retract -> park",
            "wake-up",
            "codel-start Home::park",
            "codel-end Home::park -> retract",
            "violation",
        ],
        loop_start: Some(15),
        claim: Claim::UnboundedInterrupt("Home"),
    });
}

// ------------------------------------------------- unreachable-codel (dynamic)

/// `unreachable-codel` for a codel the codel graph reaches (so the static
/// part is silent) but no execution runs; it carries no trace.
fn assert_never_reached(fixture: &str, service: &str, codel: &str, line: usize) {
    let path = common::invalid(fixture);
    let result = common::check(&path);
    let report = common::render(&path, &result);
    let found: Vec<&Diagnostic> = result
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::UnreachableCodel)
        .collect();
    assert_eq!(found.len(), 1, "{report}");
    assert_eq!(
        found[0].message,
        format!("inter codel `{codel}` of service `{service}` is never reached in any execution")
    );
    assert_eq!(common::primary_line(&result, found[0]), line, "{report}");
    assert!(found[0].trace.is_none());
    let statically = genom_check::check_file(
        &common::relative(&path),
        &FsLoader,
        &CheckOptions::new().behaviour(false),
    )
    .expect("fixture is readable");
    assert!(
        !statically
            .diagnostics
            .iter()
            .any(|d| d.code == Code::UnreachableCodel),
        "the codel graph reaches `{codel}`: only exploration finds it unreachable"
    );
}

#[test]
fn unreachable_inter_codel_whose_only_interrupter_is_forbidden() {
    assert_never_reached(
        "unreachable-codel.inter-only-when-forbidden.gen",
        "Scan",
        "abortScan",
        24,
    );
}

#[test]
fn unreachable_inter_codel_whose_interrupter_is_locked_out() {
    assert_never_reached(
        "unreachable-codel.stopper-locked-out.gen",
        "Home",
        "restoreGoal",
        20,
    );
}

#[test]
fn unreachable_cleanup_of_an_auto_service_nothing_stops() {
    let path = common::invalid("dead-service.delayed-by-auto.gen");
    let result = common::check(&path);
    let d: Vec<&Diagnostic> = result
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::UnreachableCodel)
        .collect();
    assert_eq!(d.len(), 1);
    assert_eq!(
        d[0].message,
        "inter codel `close` of service `Heartbeat` is never reached in any execution"
    );
    assert_eq!(common::primary_line(&result, d[0]), 21);
}

// ------------------------------------------------------------------- twins

/// Each invalid fixture, its valid twin, and the verdicts only the invalid
/// one has.
const TWINS: &[(&str, &str, &[Code])] = &[
    (
        "deadlock.circular-delays.gen",
        "delays-chain-without-back-edge.gen",
        &[Code::Deadlock],
    ),
    (
        "deadlock.three-way-cycle.gen",
        "../invalid/max-time-exceeded.delays-cycle-broken-by-watchdog.gen",
        &[Code::Deadlock],
    ),
    (
        "starvation.behind-auto-service.gen",
        "../invalid/max-time-exceeded.waiter-behind-auto-service.gen",
        &[Code::Starvation],
    ),
    (
        "starvation.behind-endless-loop.gen",
        "loop-blocker-has-max-time.gen",
        &[Code::Starvation],
    ),
    (
        "starvation.auto-started-by-init.gen",
        "calibrate-stops-sampling.gen",
        &[Code::Starvation],
    ),
    (
        "dead-service.init-never-succeeds.gen",
        "init-can-succeed.gen",
        &[Code::DeadService],
    ),
    (
        "dead-service.forbidden-by-auto.gen",
        "auto-service-forbids-nothing.gen",
        &[Code::DeadService],
    ),
    (
        "dead-service.delayed-by-auto.gen",
        "update-stops-auto-service.gen",
        &[Code::DeadService, Code::Starvation, Code::UnreachableCodel],
    ),
    (
        "unbounded-interrupt.looping-inter-codel.gen",
        "inter-codel-exits.gen",
        &[Code::UnboundedInterrupt],
    ),
    (
        "unbounded-interrupt.loop-with-exit.gen",
        "inter-codel-exits.gen",
        &[Code::UnboundedInterrupt],
    ),
    (
        "unbounded-interrupt.watchdog-cleanup-loop.gen",
        "watchdog-cleanup-ends.gen",
        &[Code::UnboundedInterrupt],
    ),
    (
        "unreachable-codel.inter-only-when-forbidden.gen",
        "halt-may-interrupt-scan.gen",
        &[Code::UnreachableCodel],
    ),
    (
        "unreachable-codel.stopper-locked-out.gen",
        "stopper-control-codel-without-lock.gen",
        &[Code::UnreachableCodel],
    ),
];

#[test]
fn each_invalid_fixture_has_a_near_identical_twin_without_the_verdict() {
    for &(bad, good, codes) in TWINS {
        let (bad_path, good_path) = (common::invalid(bad), common::valid(good));
        let changed = common::changed_lines(&common::body(&bad_path), &common::body(&good_path));
        assert!(
            changed <= 2,
            "{bad} and {good} differ by {changed} lines: one rule should change"
        );
        let bad_result = common::check(&bad_path);
        let good_result = common::check(&good_path);
        for &code in codes {
            assert!(
                bad_result.diagnostics.iter().any(|d| d.code == code),
                "{bad} reports `{code}`:\n{}",
                common::render(&bad_path, &bad_result)
            );
        }
        let unexpected: Vec<&Diagnostic> = good_result
            .diagnostics
            .iter()
            .filter(|d| BEHAVIOURAL.contains(&d.code) || d.code == Code::UnreachableCodel)
            .collect();
        assert!(
            unexpected.is_empty(),
            "{good} must be clean:\n{}",
            common::render(&good_path, &good_result)
        );
        assert!(
            good_result.statistics.as_ref().is_some_and(|s| s.complete),
            "{good} is fully explored"
        );
    }
}

#[test]
fn every_behavioural_code_has_at_least_two_fixture_pairs() {
    let invalid = gen_files("tests/fixtures/invalid");
    for code in [
        Code::Deadlock,
        Code::Starvation,
        Code::DeadService,
        Code::UnboundedInterrupt,
        Code::UnreachableCodel,
    ] {
        let n = TWINS
            .iter()
            .filter(|(bad, _, _)| bad.starts_with(&format!("{code}.")))
            .count();
        assert!(n >= 2, "`{code}` has {n} fixtures with twins");
        for (bad, _, _) in TWINS
            .iter()
            .filter(|(bad, _, _)| bad.starts_with(&format!("{code}.")))
        {
            assert!(invalid.iter().any(|p| p.ends_with(bad)), "{bad} exists");
        }
    }
}

// ------------------------------------------------------------------ replay

/// Every trace of every verdict of every fixture and shipped spec replays,
/// and its end shows the verdict's claim.
#[test]
fn every_verdict_trace_replays_against_the_semantics() {
    let mut files = gen_files("tests/fixtures/invalid");
    files.extend(gen_files("tests/fixtures/valid"));
    files.extend(gen_files("specs"));
    let mut replayed = 0;
    let mut failures = Vec::new();
    for path in &files {
        let result = common::check(path);
        let Some(c) = result.component.as_ref() else {
            continue;
        };
        for d in &result.diagnostics {
            let Some(trace) = &d.trace else { continue };
            if !BEHAVIOURAL.contains(&d.code) {
                continue; // timing traces: tests/verdicts/timing.rs replays them
            }
            let names = quoted(&d.message);
            replayed += 1;
            if let Err(e) = replay_claim(c, trace, claim_of(d, &names)) {
                let name = path
                    .file_name()
                    .and_then(|n| n.to_str())
                    .unwrap_or_default();
                failures.push(format!(
                    "{name}: `{}` ({}): {e}\n    {}",
                    d.code,
                    d.message,
                    trace_lines(trace).join("\n    ")
                ));
            }
        }
    }
    assert!(replayed >= 13, "only {replayed} traces");
    assert!(
        failures.is_empty(),
        "{} of {replayed} traces do not replay:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// A fixture's verdict trace and the component.
fn trace_of(fixture: &str, code: Code) -> (CheckResult, Trace) {
    let result = common::check(&common::invalid(fixture));
    let trace = result
        .diagnostics
        .iter()
        .find(|d| d.code == code)
        .and_then(|d| d.trace.clone())
        .expect("the verdict has a trace");
    (result, trace)
}

fn rejected(c: &Component, t: &Trace, claim: Claim<'_>) -> ReplayError {
    match replay_claim(c, t, claim) {
        Ok(_) => panic!(
            "the corrupted trace replays:\n{}",
            trace_lines(t).join("\n")
        ),
        Err(e) => e,
    }
}

fn index_of(t: &Trace, line: &str) -> usize {
    t.steps
        .iter()
        .position(|s| step_line(s) == line)
        .unwrap_or_else(|| panic!("no step `{line}` in {:?}", trace_lines(t)))
}

const PARK: Claim<'static> = Claim::Starvation {
    waiter: "Park",
    blocker: "Track",
};

#[test]
fn the_replay_accepts_the_original_trace() {
    let (result, t) = trace_of("starvation.behind-endless-loop.gen", Code::Starvation);
    let end = replay_claim(common::component(&result), &t, PARK).expect("the trace replays");
    let c = common::component(&result);
    let park = c.service_named("Park").expect("service exists");
    assert!(end.state.pending(park).is_some());
    assert_eq!(end.loop_states.len(), 3, "two loop steps: three states");
    assert_eq!(end.violation_step, 11);
}

#[test]
fn a_corrupted_trace_with_a_step_removed_is_rejected() {
    let (result, mut t) = trace_of("starvation.behind-endless-loop.gen", Code::Starvation);
    let c = common::component(&result);
    // Without `start Track::start`, Track never becomes active: its codel
    // cannot run.
    let k = index_of(&t, "start Track::start");
    t.steps.remove(k);
    t.loop_start = t.loop_start.map(|l| l - 1);
    let e = rejected(c, &t, PARK);
    assert_eq!(e.step, 4, "{e}");
    assert!(
        e.to_string()
            .contains("`Track` is pending and nothing stops it from starting"),
        "{e}"
    );
}

#[test]
fn a_corrupted_trace_with_an_outcome_changed_is_rejected() {
    let (result, mut t) = trace_of("starvation.behind-endless-loop.gen", Code::Starvation);
    let c = common::component(&result);
    let k = index_of(&t, "codel-end Track::start -> follow");
    t.steps[k].outcome = Some("park".to_owned());
    let e = rejected(c, &t, PARK);
    assert_eq!(e.step, k + 1);
    assert_eq!(
        e.to_string(),
        "step 8 (codel-end `Track::start` → `park`): `park` is not an outcome of `start` (its `next` is `follow`, `NO_TARGET`)"
    );
}

#[test]
fn a_corrupted_loop_that_does_not_come_back_is_rejected() {
    let (result, mut t) = trace_of("starvation.behind-endless-loop.gen", Code::Starvation);
    let c = common::component(&result);
    // The loop now ends in the middle of `follow`: it is not a cycle.
    let last = t.steps.len() - 1;
    t.steps.remove(last - 1);
    let e = rejected(c, &t, PARK);
    assert!(
        e.to_string()
            .contains("do not lead back to the state where the loop starts"),
        "{e}"
    );
    // A loop that exits the cycle: `follow` ends the service.
    let (_, mut t) = trace_of("starvation.behind-endless-loop.gen", Code::Starvation);
    let k = index_of(&t, "codel-end Track::follow -> follow");
    t.steps[k].outcome = Some("end".to_owned());
    let e = rejected(c, &t, PARK);
    assert_eq!(e.step, k + 2, "the reply of `Track` is missing: {e}");
    assert!(
        e.to_string()
            .contains("its final reply `end` must come first"),
        "{e}"
    );
}

#[test]
fn a_starvation_claim_about_the_wrong_services_is_rejected() {
    let (result, t) = trace_of("starvation.behind-endless-loop.gen", Code::Starvation);
    let c = common::component(&result);
    let e = rejected(
        c,
        &t,
        Claim::Starvation {
            waiter: "Track",
            blocker: "Park",
        },
    );
    assert_eq!(e.step, 11);
    assert!(e.to_string().contains("`Track` is not pending"), "{e}");
    let e = rejected(c, &t, Claim::Deadlock(&["Park", "Track"]));
    assert!(
        e.to_string().contains("`Track` has no pending instance"),
        "{e}"
    );
}

#[test]
fn a_corrupted_deadlock_trace_is_rejected() {
    let (result, t) = trace_of("deadlock.circular-delays.gen", Code::Deadlock);
    let c = common::component(&result);
    let claim = Claim::Deadlock(&["Grasp", "Release"]);
    // Without `Calibrate`, `Grasp` is not delayed: it must start at once.
    let mut cut = t.clone();
    cut.steps.drain(1..4);
    let e = rejected(c, &cut, claim);
    assert_eq!(e.step, 4, "{e}");
    assert!(
        e.to_string()
            .contains("`Grasp` is pending and nothing stops it from starting"),
        "{e}"
    );
    // A start that the delays forbid.
    let mut early = t.clone();
    let mut start = early.steps[3].clone();
    start.service = Some("Grasp".to_owned());
    early.steps.insert(6, start);
    let e = rejected(c, &early, claim);
    assert_eq!(e.step, 7);
    assert!(
        e.to_string()
            .contains("`Calibrate` has an instance and delays `Grasp` (step 7a)"),
        "{e}"
    );
    // Stopping before `Release` is requested: no cycle yet.
    let mut short = t;
    short.steps.drain(6..8);
    let e = rejected(c, &short, claim);
    assert!(
        e.to_string().contains("`Release` has no pending instance"),
        "{e}"
    );
}

#[test]
fn corrupted_interrupts_and_replies_are_rejected() {
    let (result, t) = trace_of(
        "unbounded-interrupt.looping-inter-codel.gen",
        Code::UnboundedInterrupt,
    );
    let c = common::component(&result);
    let claim = Claim::UnboundedInterrupt("Move");
    // The acknowledgment without the interrupt of step 5.
    let mut missing = t.clone();
    let k = index_of(&missing, "interrupt Move::start");
    missing.steps.remove(k);
    missing.loop_start = missing.loop_start.map(|l| l - 1);
    let e = rejected(c, &missing, claim);
    assert_eq!(e.step, k + 1);
    assert!(
        e.to_string()
            .contains("was not interrupted (step 5 comes before the acknowledgment)"),
        "{e}"
    );
    // An interrupt that no request causes: a watchdog for a service without max-time.
    let mut watchdog = t.clone();
    watchdog.steps[k].event = Event::Watchdog;
    let e = rejected(c, &watchdog, claim);
    assert_eq!(e.step, k + 1);
    assert!(
        e.to_string()
            .contains("the request for `Move` is still being handled"),
        "{e}"
    );
    // The interrupted codel pretends to follow its outcome.
    let mut outcome = t.clone();
    let k = index_of(&outcome, "codel-end Move::start");
    outcome.steps[k].outcome = Some("cruise".to_owned());
    assert!(
        replay(c, &outcome).is_ok(),
        "the outcome of an interrupted codel is overridden"
    );
    // A reply where none is owed.
    let mut reply = t;
    let mut extra = reply.steps[k].clone();
    extra.event = Event::Reply;
    extra.codel = None;
    extra.outcome = Some("INTERRUPTED".to_owned());
    reply.steps.insert(k + 1, extra);
    reply.loop_start = reply.loop_start.map(|l| l + 1);
    let e = rejected(c, &reply, claim);
    assert_eq!(e.step, k + 2);
    assert!(
        e.to_string()
            .contains("no instance of `Move` has just ended"),
        "{e}"
    );
}

#[test]
fn corrupted_rejections_are_rejected() {
    let (result, mut t) = trace_of("dead-service.forbidden-by-auto.gen", Code::DeadService);
    let c = common::component(&result);
    let k = t
        .steps
        .iter()
        .position(|s| s.event == Event::Reject)
        .expect("a reject step");
    t.steps[k].outcome = Some("BUSY".to_owned());
    let e = rejected(c, &t, Claim::DeadService("Calibrate"));
    assert_eq!(
        e.to_string(),
        "step 4 (reject `Calibrate` → `BUSY`): the request must be rejected with `FORBIDDEN` (the first rule of section 3 that applies), not `BUSY`"
    );
    // Without `Monitor`, nothing rejects the request.
    t.steps[k].outcome = Some("FORBIDDEN".to_owned());
    t.steps.drain(1..2);
    let e = rejected(c, &t, Claim::DeadService("Calibrate"));
    assert_eq!(e.step, 2);
    assert!(
        e.to_string()
            .contains("auto service `Monitor` must start before anything else"),
        "{e}"
    );
}

#[test]
fn a_trace_must_start_with_the_component_and_end_with_the_violation() {
    let (result, t) = trace_of("deadlock.circular-delays.gen", Code::Deadlock);
    let c = common::component(&result);
    let mut headless = t.clone();
    headless.steps.remove(0);
    assert_eq!(
        replay(c, &headless).map(|_| ()).map_err(|e| e.to_string()),
        Err("trace: the first step must be `component-start`".to_owned())
    );
    let mut endless = t;
    endless.steps.pop();
    assert_eq!(
        replay(c, &endless).map(|_| ()).map_err(|e| e.to_string()),
        Err("trace: the last step must be the `violation`".to_owned())
    );
}

/// The explorer's own step function, driven by hand through a watchdog and
/// the cleanup codels that follow: section 3 says the instance then replies
/// `TIMEOUT` ("`TIMEOUT` when the watchdog interrupted it"). The replay
/// expects that; the explorer's positions do not remember who interrupted,
/// so its trace replies `INTERRUPTED`.
#[test]
fn the_explorer_replies_timeout_after_a_watchdog_and_cleanup_codels() {
    use genom_checker::dialect::system::{Action, System};
    use genom_model::behaviour::Behaviour;

    let result = common::check(&common::valid("watchdog-cleanup-ends.gen"));
    let c = common::component(&result);
    let home = c.service_named("Home").expect("service exists");
    let b = Behaviour::new(c);
    let all: Vec<_> = c.services.ids().collect();
    let sys = System::new(c, &b, &all, false);
    let mut steps = vec![TraceStep::new(
        Event::ComponentStart,
        "the component starts",
    )];
    let mut cfg = sys.initial(false, &mut Some(&mut steps));
    let actions = [
        Action::Request(home),
        Action::Begin(home),
        Action::Watchdog(home, false),
        Action::Finish(home, 0),
        Action::Begin(home),
        Action::Finish(home, 0),
        Action::Begin(home),
        Action::Finish(home, 0),
    ];
    for a in actions {
        cfg = sys
            .apply(&cfg, a, &mut Some(&mut steps))
            .expect("the action is enabled");
    }
    steps.push(TraceStep::new(Event::Violation, "end of the scenario"));
    let trace = Trace {
        steps,
        loop_start: None,
    };
    let lines = trace_lines(&trace);
    assert_eq!(
        lines[..lines.len() - 2],
        [
            "component-start",
            "request Home",
            "acknowledge Home",
            "start Home::start",
            "codel-start Home::start",
            "watchdog Home::start",
            "codel-end Home::start",
            "codel-start Home::retract",
            "codel-end Home::retract -> park",
            "codel-start Home::park",
            "codel-end Home::park -> end",
        ]
    );
    if let Err(e) = replay(c, &trace) {
        panic!(
            "the replay rejects the explorer's trace: {e}\n    {}",
            lines.join("\n    ")
        );
    }
}

/// Checks `src` (as `inline.gen`) with the default options.
fn check_inline(src: &str) -> CheckResult {
    genom_check::check_source(
        Path::new("inline.gen"),
        src.to_owned(),
        &gen_frontend::MemoryLoader::new(),
        &CheckOptions::new(),
    )
}

/// No `starvation` in `src`; if there is one, the failure says what the
/// replay thinks of its trace.
fn assert_no_starvation(src: &str) {
    let result = check_inline(src);
    let c = common::component(&result);
    let wrong: Vec<String> = result
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::Starvation)
        .map(|d| {
            let names = quoted(&d.message);
            let trace = d.trace.as_ref().expect("starvation has a trace");
            let replayed = replay_claim(c, trace, claim_of(d, &names))
                .map(|_| ())
                .map_err(|e| e.to_string());
            format!(
                "{} (replay: {replayed:?})\n    {}",
                d.message,
                trace_lines(trace).join("\n    ")
            )
        })
        .collect();
    assert!(
        wrong.is_empty(),
        "no execution waits forever, yet:\n{}",
        wrong.join("\n")
    );
}

/// An `auto` service whose codels always end (here after one codel) ends:
/// a service it delays starts right after. Its `auto-terminates` warning is
/// deserved; a `starvation` is not (its trace has no loop to repeat).
#[test]
fn an_auto_service_that_ends_does_not_starve_what_it_delays() {
    let src = "component probe { lang: C; }\n\
        thread main { period: 10ms; }\n\
        auto service Warmup { thread: main; delays: Measure; start codel { exec: probeHeat(); next: end; } }\n\
        service Measure { thread: main; start codel { exec: probeMeasure(); next: end; } }\n";
    let result = check_inline(src);
    assert!(
        result
            .diagnostics
            .iter()
            .any(|d| d.code == Code::AutoTerminates)
    );
    assert_no_starvation(src);
}

/// An `auto` service with a `max-time` is interrupted by its watchdog,
/// then ends after its (finite) cleanup: what it delays then starts. The
/// verdict's own help ("give `Warmup` a `max-time`") shows the mismatch.
#[test]
fn an_auto_service_with_max_time_does_not_starve_what_it_delays() {
    assert_no_starvation(
        "component probe { lang: C; }\n\
        thread main { period: 10ms; }\n\
        auto service Warmup {\n\
          thread: main; delays: Measure; max-time: 30s;\n\
          start codel { exec: probeHeat(); on-inter: cool; next: start; }\n\
          inter codel cool { exec: probeCool(); next: end; }\n\
        }\n\
        service Measure { thread: main; start codel { exec: probeMeasure(); next: end; } }\n",
    );
}

// -------------------------------------------------------------- JSON trace

#[test]
fn the_json_trace_is_a_list_of_step_objects() {
    let out = Command::cargo_bin("genom-check")
        .expect("binary is built")
        .args([
            "--format",
            "json",
            "tests/fixtures/invalid/starvation.behind-endless-loop.gen",
        ])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(1));
    let doc: Value = serde_json::from_slice(&out.stdout).expect("one JSON document");
    let diagnostics = doc["files"][0]["diagnostics"]
        .as_array()
        .expect("diagnostics");
    let d = diagnostics
        .iter()
        .find(|d| d["code"] == "starvation")
        .expect("the starvation verdict");
    assert_eq!(
        d["message"],
        "`Park` can wait forever for `Track`, which may never end"
    );
    assert_eq!(d["line"], 24);
    let trace = d["trace"].as_array().expect("trace is a list");
    assert_eq!(trace.len(), 11);
    let keys = [
        "step",
        "event",
        "time_ns",
        "thread",
        "service",
        "codel",
        "outcome",
        "loop_start",
        "aside",
        "text",
        "location",
    ];
    let mut events = Vec::new();
    for (k, step) in trace.iter().enumerate() {
        let object = step.as_object().expect("each step is an object");
        let mut found: Vec<&str> = object.keys().map(String::as_str).collect();
        found.sort_unstable();
        let mut want = keys.to_vec();
        want.sort_unstable();
        assert_eq!(found, want, "step {k}");
        assert_eq!(step["step"], k + 1);
        assert!(step["time_ns"].is_null(), "untimed trace");
        assert_eq!(step["loop_start"], k == 8, "step {k}");
        assert_eq!(step["aside"], false, "step {k}: no thread set aside");
        assert!(step["text"].as_str().is_some_and(|t| !t.is_empty()));
        let location = &step["location"];
        if location.is_null() {
            assert!(
                matches!(k, 0 | 10),
                "only the start and the violation have no location"
            );
        } else {
            assert!(
                location["file"]
                    .as_str()
                    .is_some_and(|f| f.ends_with("starvation.behind-endless-loop.gen"))
            );
            assert!(location["line"].as_u64().is_some() && location["column"].as_u64().is_some());
            assert!(location["span"]["offset"].as_u64().is_some());
        }
        events.push(step["event"].as_str().expect("event").to_owned());
    }
    assert_eq!(
        events,
        [
            "component-start",
            "request",
            "acknowledge",
            "start",
            "request",
            "acknowledge",
            "codel-start",
            "codel-end",
            "codel-start",
            "codel-end",
            "violation",
        ]
    );
    assert_eq!(trace[1]["thread"], "control");
    assert_eq!(trace[1]["service"], "Track");
    assert!(trace[1]["codel"].is_null());
    assert_eq!(trace[7]["thread"], "servo");
    assert_eq!(trace[7]["codel"], "start");
    assert_eq!(trace[7]["outcome"], "follow");
    assert_eq!(trace[9]["outcome"], "follow");
    assert_eq!(trace[8]["location"]["line"], 21, "`follow` is on line 21");
}

// -------------------------------------------------------------- incomplete

#[test]
fn a_state_limit_gives_incomplete_and_no_negative_claim() {
    for (fixture, services) in [
        (
            "unreachable-codel.inter-only-when-forbidden.gen",
            "`Scan`, `Halt`",
        ),
        ("dead-service.delayed-by-auto.gen", "`Heartbeat`, `Update`"),
    ] {
        let path = common::invalid(fixture);
        let result = genom_check::check_file(
            &common::relative(&path),
            &FsLoader,
            // The explicit engine alone: `auto` would finish symbolically.
            &CheckOptions::new().max_states(3).engine(Engine::Explicit),
        )
        .expect("fixture is readable");
        let report = common::render(&path, &result);
        let incomplete: Vec<&Diagnostic> = result
            .diagnostics
            .iter()
            .filter(|d| d.code == Code::Incomplete)
            .collect();
        assert_eq!(incomplete.len(), 1, "{report}");
        assert_eq!(
            incomplete[0].message,
            "verification is incomplete: the state limit (--max-states) was reached"
        );
        let help = incomplete[0].help.as_deref().unwrap_or_default();
        assert!(
            help.starts_with(&format!(
                "left unproven: deadlock and starvation freedom, unbounded interrupts, dead services and codel reachability for services {services}; raise the limit to finish. "
            )),
            "{report}"
        );
        // What it spent; nothing is proven (one cluster, stopped).
        assert!(help.contains(". Stopped after "), "{report}");
        assert!(help.ends_with(" s"), "{report}");
        assert!(
            !result
                .diagnostics
                .iter()
                .any(|d| matches!(d.code, Code::DeadService | Code::UnreachableCodel)),
            "nothing negative is claimed about what was not explored:\n{report}"
        );
        assert!(result.statistics.as_ref().is_some_and(|s| !s.complete));
        // Whatever was found before the limit comes with a trace that replays.
        for d in result.diagnostics.iter().filter(|d| d.trace.is_some()) {
            let names = quoted(&d.message);
            let trace = d.trace.as_ref().expect("checked");
            replay_claim(common::component(&result), trace, claim_of(d, &names))
                .unwrap_or_else(|e| panic!("{e}"));
        }
    }
}

#[test]
fn without_a_limit_the_same_fixtures_are_complete() {
    for fixture in [
        "unreachable-codel.inter-only-when-forbidden.gen",
        "dead-service.delayed-by-auto.gen",
    ] {
        let result = common::check(&common::invalid(fixture));
        assert!(
            !result
                .diagnostics
                .iter()
                .any(|d| d.code == Code::Incomplete)
        );
        assert!(result.statistics.as_ref().is_some_and(|s| s.complete));
    }
}

#[test]
fn outcomes_named_in_traces_are_outcomes_of_the_model() {
    // A sanity check of the helper the lasso check uses: an interrupted
    // codel leads to its `on-inter`.
    let result = common::check(&common::invalid(
        "unbounded-interrupt.looping-inter-codel.gen",
    ));
    let c = common::component(&result);
    let mv = c.service_named("Move").expect("service exists");
    let start = c.codel_named(mv, "start").expect("codel exists");
    assert_eq!(
        c.codels[start]
            .on_inter
            .map(|r| c.codels[r.id].name.name.clone()),
        Some("brake".to_owned())
    );
    let brake = c.codel_named(mv, "brake").expect("codel exists");
    assert_eq!(c.codels[brake].outcomes(), vec![Outcome::Codel(brake)]);
}
