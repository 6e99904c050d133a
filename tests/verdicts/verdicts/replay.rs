//! Every verdict trace replayed by the independent interpreter of
//! LANGUAGE.md section 3 (`genom_oracles::replay`); corrupted traces, which
//! the replay must reject; the explorer's `TIMEOUT` reply after a watchdog;
//! `auto` services that do not starve what they delay.

use super::support::{BEHAVIOURAL, claim_of, gen_files, quoted, step_line, trace_lines};
use crate::common;

use std::path::Path;

use genom_check::{CheckOptions, CheckResult};
use genom_model::component::Component;
use genom_model::{Code, Event, Trace, TraceStep};
use genom_oracles::replay::{Claim, ReplayError, replay, replay_claim};
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
                continue; // timing traces: tests/verdicts/timing/ replays them
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

pub(crate) fn rejected(c: &Component, t: &Trace, claim: Claim<'_>) -> ReplayError {
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
