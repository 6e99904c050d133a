//! `deadlock`: a reachable state where pending instances wait on each other
//! through `delays`, so that none can ever start unless a new request
//! interrupts one (LANGUAGE.md section 3, step 7a).

use genom_model::component::{Component, ServiceId};
use genom_model::{Code, Diagnostic, Trace};

use super::registry::Explained;
use crate::dialect::Analysis;

/// `genom-check explain deadlock`.
pub const EXPLANATION: &str = r#"A reachable state where pending service instances wait on each other in a
cycle, through `delays`: each is acknowledged but cannot start because
another pending one delays it. None of them can ever start unless a new
request interrupts one; their clients wait forever.

Why it matters: this is a real execution of the component; the trace shows
the requests that lead to it.

Example:

```
service A { thread: t; delays: B; start codel { exec: a(); } }
service B { thread: t; delays: A; start codel { exec: b(); } }
service C { thread: t; delays: A; start codel { exec: c(); next: c; } }
// C runs and delays A; B is requested (pending, delayed by A's pending
// instance); when C ends, A and B delay each other forever: deadlock.
```

A cycle in which some service has a `max-time` is not a deadlock: its
watchdog ends the pending instance (with `TIMEOUT`) and the others start.
Break the cycle by removing one of the `delays`, or by making the services
exclusive with `forbids` instead."#;

/// The codes of this verdict, for the registry ([`super::VERDICTS`]).
pub const CODES: &[Explained] = &[(Code::Deadlock, EXPLANATION)];

/// A deadlock among `services`, with the `delays` entries of the cycle.
pub fn deadlock(c: &Component, services: &[ServiceId], trace: Trace) -> Diagnostic {
    let names = crate::dialect::analysis::names(c, services);
    let first = services
        .first()
        .map_or_else(Default::default, |&s| c.services[s].name.span);
    let mut d = Diagnostic::new(
        Code::Deadlock,
        format!(
            "deadlock: {} can be pending and wait on each other forever",
            names
        ),
        first,
        "pending, delayed by the others",
    );
    for &s in services {
        for r in c.services[s]
            .delays
            .iter()
            .filter(|r| services.contains(&r.id))
        {
            let delayed = &c.services[r.id].name.name;
            d = d.with_label(
                r.span,
                format!("`{}` delays `{delayed}`", c.services[s].name.name),
            );
        }
    }
    d.with_help("break the cycle: remove one of these `delays`, or use `forbids` to make the services exclusive")
        .with_trace(trace)
}

/// One diagnostic per deadlock found.
pub fn check(c: &Component, analysis: &Analysis) -> Vec<Diagnostic> {
    analysis
        .deadlocks
        .iter()
        .map(|d| deadlock(c, &d.services, d.trace.clone()))
        .collect()
}
