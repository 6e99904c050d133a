//! `starvation`: a pending instance that can wait forever on a running
//! instance that may never end: an `auto` service, or a codel loop with no
//! `max-time`. (An interrupted instance whose inter codels loop is
//! `unbounded-interrupt`.)

use genom_model::component::{Component, ServiceId};
use genom_model::{Code, Diagnostic, Trace};

use super::registry::Explained;
use crate::dialect::Analysis;

/// `genom-check explain starvation`.
pub const EXPLANATION: &str = r#"A pending service instance that can wait forever: it is delayed by an
instance that may never end, an `auto` service or a codel loop with no exit
and no `max-time`. (Waiting for an interrupted instance whose inter codels
loop is reported as `unbounded-interrupt` on that service.)

Why it matters: the client got an acknowledgment and waits for a final
reply that never comes. The trace ends with the loop that can repeat
forever (marked "the following steps repeat forever").

Example:

```
auto service monitor { thread: t; delays: move; start codel { exec: m(); next: start; } }
service move { thread: t; start codel { exec: go(); } }
// move is acknowledged, then waits forever: monitor never ends.
```

Give the blocking service a `max-time` (the watchdog bounds it), give its
loop an exit, or do not delay a permanent service. A waiter with its own
`max-time` does not starve: its watchdog ends it with `TIMEOUT`."#;

/// The codes of this verdict, for the registry ([`super::VERDICTS`]).
pub const CODES: &[Explained] = &[(Code::Starvation, EXPLANATION)];

/// `waiter` can wait forever for `blocker`.
pub fn starvation(
    c: &Component,
    waiter: ServiceId,
    blocker: ServiceId,
    via_delays: bool,
    trace: Trace,
) -> Diagnostic {
    let (w, b) = (&c.services[waiter], &c.services[blocker]);
    let why = if b.kind == genom_model::kinds::ServiceKind::Auto {
        "an auto service runs forever"
    } else {
        "its codels can loop forever and it has no max-time"
    };
    let mut d = Diagnostic::new(
        Code::Starvation,
        format!(
            "`{}` can wait forever for `{}`, which may never end",
            w.name.name, b.name.name
        ),
        w.name.span,
        "can stay pending forever",
    )
    .with_label(b.name.span, format!("may never end: {why}"));
    let rule = if via_delays {
        b.delays.iter().find(|r| r.id == waiter).map(|r| {
            (
                r.span,
                format!("`{}` delays `{}`", b.name.name, w.name.name),
            )
        })
    } else {
        w.stops.iter().find(|r| r.id == blocker).map(|r| {
            (
                r.span,
                format!(
                    "`{}` waits for the stopped `{}` to end",
                    w.name.name, b.name.name
                ),
            )
        })
    };
    if let Some((span, text)) = rule {
        d = d.with_label(span, text);
    }
    d.with_help(format!(
        "give `{}` a `max-time` or an exit from its loop, or do not make `{}` wait for it",
        b.name.name, w.name.name
    ))
    .with_trace(trace)
}

/// One diagnostic per (waiter, blocker) pair found.
pub fn check(c: &Component, analysis: &Analysis) -> Vec<Diagnostic> {
    analysis
        .starvations
        .iter()
        .map(|s| starvation(c, s.waiter, s.blocker, s.via_delays, s.trace.clone()))
        .collect()
}
