//! Worst-case response times (LANGUAGE.md dialect) and `deadline-miss`:
//! the engine's [`ServiceResponse`]s become dialect-independent
//! [`ResponseTime`]s, and each `--deadline SERVICE=DURATION` is decided
//! against them.

use std::collections::BTreeMap;

use genom_model::behaviour::Behaviour;
use genom_model::component::{CodelId, Component, Idx, Outcome, ServiceId};
use genom_model::duration::format_ns;
use genom_model::graph::heaviest_path;
use genom_model::kinds::CodelKind;
use genom_model::response::{Bound, ResponseTime, sort_response_times};
use genom_model::{Code, Diagnostic};

use super::registry::Explained;
use crate::timed::{ServiceResponse, Worst};

/// `genom-check explain deadline-miss`.
pub const EXPLANATION: &str = r#"`--deadline SERVICE=DURATION` asks that every instance of the service
replies (its final reply: success, a report, `INTERRUPTED` or `TIMEOUT`)
at most DURATION after its acknowledgment. The zone engine computed the
service's worst-case response time (the table after the diagnostics) and
it is later than that: some execution replies later, or never replies
(`unbounded`). The timed trace shows an instance still without reply when
the deadline passes (for `unbounded`, the loop or the wait that can last
forever).

Why it matters: the deadline is the response time a client (a
supervisor, a planner) relies on; the GenoM3 UPPAAL and Fiacre templates
check such bounded-response properties one bound at a time.

Margins are exact: a worst case equal to the deadline is in time.

Example (`--deadline Step=11ms`):

```
thread t { period: 10ms; }
service Step {
  thread: t;
  start codel { exec: step(); max-time: 2ms; next: end; }
  // acknowledged at a wake-up, run at the next one: 10ms + 2ms = 12ms
}
```"#;

/// The codes of this verdict, for the registry ([`super::VERDICTS`]).
pub const CODES: &[Explained] = &[(Code::DeadlineMiss, EXPLANATION)];

/// The response times of `c`'s services from the engine's results, by
/// service name.
pub fn response_times(c: &Component, found: &[ServiceResponse]) -> Vec<ResponseTime> {
    let b = Behaviour::new(c);
    let mut out: Vec<ResponseTime> = found
        .iter()
        .map(|r| {
            let (worst, note) = bound(c, &b, r);
            let svc = &c.services[r.service];
            ResponseTime {
                service: svc.name.name.clone(),
                span: svc.name.span,
                worst,
                own: own_time(c, r.service),
                note,
            }
        })
        .collect();
    sort_response_times(&mut out);
    out
}

/// The service's own time: its control codels (GenoM3: `validate` and an
/// attribute's or function's codel) plus its longest chain of codels from
/// `start` to an end (the `next`/`yield` graph, interrupt codels left out),
/// each at its WCET (0 without codels); `None` when that graph has a cycle
/// (a loop has no longest chain). A worst response above it
/// is time spent waiting: for locks, for other requests, for ticks.
pub fn own_time(c: &Component, s: ServiceId) -> Option<u64> {
    let svc = &c.services[s];
    let wcet = |k: CodelId| c.codels[k].wcet.map_or(0, |d| d.ns);
    let control: u64 = svc
        .codels
        .iter()
        .filter(|&&k| c.codels[k].kind == CodelKind::Control)
        .map(|&k| wcet(k))
        .sum();
    // Longest chain from `start` along the codels' `next`/`yield`s.
    let next = |k: usize| {
        c.codels[CodelId::new(k)]
            .outcomes()
            .into_iter()
            .filter_map(|o| match o {
                Outcome::Codel(next) => Some(next.index()),
                _ => None,
            })
            .collect::<Vec<_>>()
    };
    let chain = heaviest_path(c.codels.len(), svc.start.map(Idx::index), next, |k| {
        Some(wcet(CodelId::new(k)))
    })?;
    Some(control.saturating_add(chain))
}

fn bound(c: &Component, b: &Behaviour, r: &ServiceResponse) -> (Bound, Option<String>) {
    let approximate = "a watchdog of its cluster is timed approximately";
    match (&r.worst, r.exact) {
        (Worst::Incomplete, _) => (Bound::Unknown, Some("exploration incomplete".to_owned())),
        (Worst::AtMost(ns), _) => (
            Bound::AtMost(*ns),
            Some("static bound; the exploration stopped on a limit".to_owned()),
        ),
        (Worst::Never, _) => (Bound::Unknown, Some("never acknowledged".to_owned())),
        (Worst::Undecided(why), _) => (Bound::Unknown, Some((*why).to_owned())),
        (Worst::Exact(ns), true) => (Bound::Exact(*ns), None),
        (Worst::Above(ns), true) => (
            Bound::Above(*ns),
            Some("horizon of the computation".to_owned()),
        ),
        (Worst::Unbounded, true) => (Bound::Unbounded, None),
        // No response is shorter than 0: a bound of 0 is exact.
        (Worst::Exact(0), false) => (Bound::Exact(0), None),
        (Worst::Exact(ns), false) => (Bound::AtMost(*ns), Some(approximate.to_owned())),
        (Worst::Above(_) | Worst::Unbounded, false) => {
            if let Some(ns) = watchdog_bound(c, b, r.service) {
                let note = "max-time + worst stop latency";
                return (Bound::AtMost(ns), Some(note.to_owned()));
            }
            let why = if r.worst == Worst::Unbounded {
                "unbounded in the model, where a watchdog of its cluster is timed approximately"
            } else {
                approximate
            };
            (Bound::Unknown, Some(why.to_owned()))
        }
    }
}

/// For a looping service with a max-time on a periodic thread: its
/// max-time plus its worst stop latency (the `max-time-watchdog` figure),
/// an upper bound of every response.
fn watchdog_bound(c: &Component, b: &Behaviour, s: ServiceId) -> Option<u64> {
    let svc = &c.services[s];
    let max = svc.max_time?.ns;
    svc.thread.and_then(|t| c.threads[t.id].period)?;
    if !b.machine(s).active_loop {
        return None;
    }
    let latency = super::max_time::stop_latency(c, s, b)?;
    Some(max.saturating_add(latency))
}

/// `incomplete` when a limit stopped the response-time exploration: the
/// services whose worst case it left unknown, those it decided anyway
/// (e.g. `unbounded`, from a loop found before the limit), those with an
/// upper bound only (a static one, GenoM3 16.8), and what it spent.
pub fn unfinished(
    c: &Component,
    stop: crate::dialect::Stop,
    times: &[ResponseTime],
    started: std::time::Instant,
) -> Diagnostic {
    let names = |keep: fn(&Bound) -> bool| {
        times
            .iter()
            .filter(|t| keep(&t.worst))
            .map(|t| format!("`{}`", t.service))
            .collect::<Vec<_>>()
    };
    let left = names(|b| matches!(b, Bound::Unknown));
    let what = if left.is_empty() {
        "nothing".to_owned()
    } else {
        format!("the worst-case response times of {}", left.join(", "))
    };
    let decided = names(|b| !matches!(b, Bound::Unknown | Bound::AtMost(_)));
    let bounded = names(|b| matches!(b, Bound::AtMost(_)));
    let mut proven: Vec<String> = Vec::new();
    if !decided.is_empty() {
        proven.push(format!("the response times of {}", decided.join(", ")));
    }
    if !bounded.is_empty() {
        proven.push(format!(
            "upper bounds on the response times of {} (the table's `≤`)",
            bounded.join(", ")
        ));
    }
    let spent = format!("{:.1} s", started.elapsed().as_secs_f64());
    super::incomplete::incomplete_partly(c, stop, &what, &proven, &spent)
}

/// The `deadline-miss` errors (and `incomplete` when a deadline cannot be
/// decided) for `deadlines` (nanoseconds by service).
pub fn check(
    c: &Component,
    found: &[ServiceResponse],
    times: &[ResponseTime],
    deadlines: &BTreeMap<ServiceId, u64>,
) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for (&s, &d) in deadlines {
        let svc = &c.services[s];
        let Some(t) = times.iter().find(|t| t.service == svc.name.name) else {
            continue;
        };
        let trace = found
            .iter()
            .find(|r| r.service == s)
            .and_then(|r| r.trace.clone());
        if t.worst.exceeds(d) {
            let mut diag = Diagnostic::new(
                Code::DeadlineMiss,
                format!(
                    "`{}` can reply later than its deadline of {}: worst-case response time {}",
                    svc.name.name,
                    format_ns(d),
                    t.worst.human()
                ),
                svc.name.span,
                "some execution replies after the deadline",
            )
            .with_help("raise the deadline to the worst case, or make the service faster (fewer codels, shorter WCETs, fewer lock waits)");
            if let Some(trace) = trace {
                diag = diag.with_trace(trace);
            }
            out.push(diag);
        } else if matches!(t.worst, Bound::Unknown) || matches!(t.worst, Bound::AtMost(n) if n > d)
        {
            out.push(
                Diagnostic::new(
                    Code::Incomplete,
                    format!(
                        "verification is incomplete: the deadline of `{}` ({}) is not decided",
                        svc.name.name,
                        format_ns(d)
                    ),
                    svc.name.span,
                    "deadline not decided",
                )
                .with_help(format!(
                    "the worst-case response time is {}{}",
                    t.worst.human(),
                    t.note
                        .as_deref()
                        .map(|n| format!(" ({n})"))
                        .unwrap_or_default()
                )),
            );
        }
    }
    out
}
