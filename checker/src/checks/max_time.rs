//! `max-time-infeasible`, `max-time-exceeded` and `max-time-watchdog`: a
//! service's `max-time` (deadline from acknowledgment to final reply)
//! against its timed executions.

use genom_model::behaviour::Behaviour;
use genom_model::component::{Component, ServiceId};
use genom_model::duration::format_ns;
use genom_model::{Code, Diagnostic, Trace};

use super::registry::Explained;
use crate::timed::TimedFacts;

/// `genom-check explain max-time-infeasible`.
pub const EXPLANATION_INFEASIBLE: &str = r#"Even the fastest execution of the service ends after its `max-time`: no
timed execution ends it by itself (success or report) within the deadline,
so every instance is ended by the watchdog with `TIMEOUT`.

Why it matters: the service as described can never succeed.

Example:

```
thread t { period: 10ms; }
service move {
  thread: t; max-time: 15ms;
  start codel { exec: a(); next: b; }
  exec codel b { exec: b(); next: c; }
  exec codel c { exec: c(); next: end; }   // three codels need three periods: 20ms at least
}
```"#;

/// `genom-check explain max-time-exceeded`.
pub const EXPLANATION_EXCEEDED: &str = r#"Some execution of the service misses its `max-time`: the instance can still
be running that long after its acknowledgment, so the watchdog interrupts
it. The service has no unbounded loop, so this is a timing error, not the
intended use of the watchdog. The timed trace shows such an execution.

Why it matters: a client is promised a reply within `max-time`.

Margins are exact: a service whose worst case equals its `max-time` is
clean (ending exactly at the deadline is in time); one time unit less is
reported.

Example:

```
thread t { period: 10ms; }
service move {
  thread: t; max-time: 11ms;
  start codel { exec: a(); max-time: 2ms; next: end; }
  // acknowledged at a wake-up and run at the next one: 10ms + 2ms = 12ms
}
```"#;

/// `genom-check explain max-time-watchdog`.
pub const EXPLANATION_WATCHDOG: &str = r#"The service has an unbounded loop (its codels can loop forever), so its
`max-time` is only enforced by the watchdog: the service ends with
`TIMEOUT` when the deadline passes. The advice gives the worst stop latency:
how long after the watchdog fires the service can still run (its current
codel, then its inter codels, one per period on a periodic thread).

This is advice: a servo loop bounded by a watchdog is a normal design. Check
that the stop latency is acceptable."#;

/// The codes of this verdict, for the registry ([`super::VERDICTS`]).
pub const CODES: &[Explained] = &[
    (Code::MaxTimeInfeasible, EXPLANATION_INFEASIBLE),
    (Code::MaxTimeExceeded, EXPLANATION_EXCEEDED),
    (Code::MaxTimeWatchdog, EXPLANATION_WATCHDOG),
];

/// The diagnostics for every service with a `max-time`.
pub fn check(c: &Component, facts: &TimedFacts) -> Vec<Diagnostic> {
    let b = Behaviour::new(c);
    let mut out = Vec::new();
    for (sid, _) in c.services.iter().filter(|(_, s)| s.max_time.is_some()) {
        let looping = b.machine(sid).active_loop;
        let exceeded = facts.exceeded.iter().find(|e| e.service == sid);
        if looping {
            out.push(watchdog(c, sid, &b));
        } else if let Some(e) = exceeded {
            let infeasible = facts.acknowledged.contains(&sid) && !facts.in_time.contains(&sid);
            out.push(if infeasible {
                infeasible_d(c, sid, e.trace.clone())
            } else {
                exceeded_d(c, sid, e.trace.clone())
            });
        }
    }
    out
}

fn infeasible_d(c: &Component, s: ServiceId, trace: Trace) -> Diagnostic {
    let svc = &c.services[s];
    let m = svc.max_time.map_or(0, |m| m.ns);
    let mut d = Diagnostic::new(
        Code::MaxTimeInfeasible,
        format!(
            "`{}` can never end within its max-time of {}",
            svc.name.name,
            format_ns(m)
        ),
        svc.name.span,
        "every execution times out",
    );
    if let Some(mt) = svc.max_time {
        d = d.with_label(mt.span, "the deadline");
    }
    d.with_help("the shortest path from acknowledgment to `end` takes longer: raise `max-time` or shorten the path")
        .with_trace(trace)
}

fn exceeded_d(c: &Component, s: ServiceId, trace: Trace) -> Diagnostic {
    let svc = &c.services[s];
    let m = svc.max_time.map_or(0, |m| m.ns);
    let mut d = Diagnostic::new(
        Code::MaxTimeExceeded,
        format!(
            "`{}` can miss its max-time of {}",
            svc.name.name,
            format_ns(m)
        ),
        svc.name.span,
        "some execution is still running at the deadline",
    );
    if let Some(mt) = svc.max_time {
        d = d.with_label(mt.span, "the deadline");
    }
    d.with_help("raise `max-time` to the worst case, or make the service faster (fewer codels, shorter WCETs, fewer lock waits)")
        .with_trace(trace)
}

fn watchdog(c: &Component, s: ServiceId, b: &Behaviour) -> Diagnostic {
    let svc = &c.services[s];
    let latency = stop_latency(c, s, b);
    let text = match latency {
        Some(ns) => format!("at most {}", format_ns(ns)),
        None => "unbounded (its inter codels can loop)".to_owned(),
    };
    let mut d = Diagnostic::new(
        Code::MaxTimeWatchdog,
        format!(
            "`{}` loops without bound: its max-time is enforced only by the watchdog; worst stop latency {text}",
            svc.name.name
        ),
        svc.name.span,
        "unbounded loop",
    );
    if let Some(mt) = svc.max_time {
        d = d.with_label(mt.span, "enforced by the watchdog");
    }
    d.with_help("the service ends with TIMEOUT; check that the stop latency is acceptable")
}

/// Worst time from the watchdog firing to the end of the instance: the
/// running codel, then the longest chain of inter codels. On a periodic
/// thread each codel ends within its period; on an aperiodic one codels run
/// back to back (lock waits not counted). `None` when inter codels loop.
pub fn stop_latency(c: &Component, s: ServiceId, b: &Behaviour) -> Option<u64> {
    let svc = &c.services[s];
    let m = b.machine(s);
    if m.stop_loops.iter().any(|&l| l) {
        return None;
    }
    let period = svc
        .thread
        .and_then(|t| c.threads[t.id].period)
        .map(|p| p.ns);
    let wcet = |k: genom_model::component::CodelId| c.codels[k].wcet.map_or(0, |w| w.ns);
    let mut worst = 0u64;
    for (i, &p) in m.positions.iter().enumerate() {
        if p.is_interrupted() || p == genom_model::behaviour::Position::Idle {
            continue;
        }
        let current = p.codel().map_or(0, wcet);
        let chain = inter_chain(m, i, &wcet);
        let total = match period {
            Some(per) => per.saturating_mul(1 + chain.0),
            None => current + chain.1,
        };
        worst = worst.max(total);
    }
    Some(worst)
}

/// Longest chain of inter codels after an interrupt at position `i`: its
/// length and the sum of their WCETs.
fn inter_chain(
    m: &genom_model::behaviour::ServiceMachine,
    i: usize,
    wcet: &dyn Fn(genom_model::component::CodelId) -> u64,
) -> (u64, u64) {
    use genom_model::behaviour::{Effect, Position};
    let mut best = (0, 0);
    let mut stack: Vec<(usize, u64, u64)> = match m.interrupt[i] {
        Some(Effect::Goto(q)) => vec![(usize::from(q), 0, 0)],
        _ => Vec::new(),
    };
    let mut guard = 0;
    while let Some((p, n, w)) = stack.pop() {
        guard += 1;
        if guard > 10_000 {
            break;
        }
        let (n, w) = match m.positions[p] {
            Position::StopReady { codel } => (n + 1, w + wcet(codel)),
            _ => (n, w),
        };
        best = (best.0.max(n), best.1.max(w));
        for q in m.steps(u16::try_from(p).unwrap_or(0)) {
            stack.push((usize::from(q), n, w));
        }
    }
    best
}
