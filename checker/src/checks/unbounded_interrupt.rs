//! `unbounded-interrupt`: an interrupted service that may never end because
//! its inter codels loop.

use genom_model::component::{Component, ServiceId};
use genom_model::{Code, Diagnostic, Trace};

use super::registry::Explained;
use crate::dialect::Analysis;

/// `genom-check explain unbounded-interrupt`.
pub const EXPLANATION: &str = r#"A service instance that, once interrupted, may never end: the inter codels
it runs can loop forever. A stopping service is not interrupted again, so
nothing can stop it any more, and whoever waits for it (a new instance of
a self-stopping service, a service that `stops` it) waits forever.

Why it matters: interruption is the way to stop a service safely; cleanup
must terminate. The trace reaches the interrupted instance and ends with
the loop that can repeat forever.

Example:

```
service move {
  thread: t; stops: move;
  start codel { exec: go(); on-inter: brake; next: start; }
  inter codel brake { exec: slow(); next: brake; }      // unbounded-interrupt: no way out
}
```

Give the inter codels a path to `end` (or a report)."#;

/// The codes of this verdict, for the registry ([`super::VERDICTS`]).
pub const CODES: &[Explained] = &[(Code::UnboundedInterrupt, EXPLANATION)];

/// `service` may never end once interrupted.
pub fn unbounded_interrupt(c: &Component, service: ServiceId, trace: Trace) -> Diagnostic {
    let s = &c.services[service];
    let mut d = Diagnostic::new(
        Code::UnboundedInterrupt,
        format!(
            "`{}` may never end once interrupted: its inter codels can loop forever",
            s.name.name
        ),
        s.name.span,
        "interrupted instances may never end",
    );
    for &k in &s.codels {
        let codel = &c.codels[k];
        if codel.kind == genom_model::kinds::CodelKind::Inter
            && codel
                .next
                .iter()
                .any(|n| matches!(n.outcome, genom_model::component::Outcome::Codel(_)))
        {
            d = d.with_label(codel.name.span, "inter codel on the loop");
        }
    }
    d.with_help("give the inter codels a way to `end` (or a report): cleanup must terminate")
        .with_trace(trace)
}

/// One diagnostic per service found.
pub fn check(c: &Component, analysis: &Analysis) -> Vec<Diagnostic> {
    analysis
        .unbounded
        .iter()
        .map(|u| unbounded_interrupt(c, u.service, u.trace.clone()))
        .collect()
}
