//! Shared helpers of the behavioural verdict tests: the fixtures' files,
//! traces as lines, the claim a diagnostic makes, `verify` (a verdict with
//! its message, line and exact trace, replayed), and the lasso check of a
//! trace that ends in a loop.

use crate::common;

use std::path::PathBuf;

use genom_model::component::Component;
use genom_model::{Code, Diagnostic, Event, Trace, TraceStep};
use genom_oracles::replay::{Claim, replay_claim};
/// The behavioural codes this file is about.
pub(crate) const BEHAVIOURAL: &[Code] = &[
    Code::Deadlock,
    Code::Starvation,
    Code::DeadService,
    Code::UnboundedInterrupt,
];

/// The `.gen` files of a directory (relative to the workspace root), sorted.
pub(crate) fn gen_files(dir: &str) -> Vec<PathBuf> {
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
pub(crate) fn step_line(s: &TraceStep) -> String {
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

pub(crate) fn trace_lines(t: &Trace) -> Vec<String> {
    t.steps.iter().map(step_line).collect()
}

/// The names quoted with backticks in a message, in order.
pub(crate) fn quoted(message: &str) -> Vec<&str> {
    message.split('`').skip(1).step_by(2).collect()
}

/// The claim a behavioural verdict makes, read from its code and message.
pub(crate) fn claim_of<'a>(d: &'a Diagnostic, names: &'a [&'a str]) -> Claim<'a> {
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
pub(crate) struct Expected<'a> {
    pub(crate) fixture: &'a str,
    pub(crate) code: Code,
    pub(crate) message: &'a str,
    pub(crate) line: usize,
    pub(crate) help: Option<&'a str>,
    /// The steps as [`step_line`] writes them.
    pub(crate) trace: &'a [&'a str],
    /// Index (0-based) of the first step of the repeating cycle.
    pub(crate) loop_start: Option<usize>,
    pub(crate) claim: Claim<'a>,
}

/// Checks the verdict's code, message, primary line, help and trace, then
/// replays the trace and checks the claim.
pub(crate) fn verify(e: &Expected<'_>) {
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
