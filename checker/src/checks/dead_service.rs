//! `dead-service`: a service that no execution can ever start (for a service
//! without start codel: ever accept).

use genom_model::component::{Component, ServiceId};
use genom_model::{Code, Diagnostic, Trace};

use super::registry::Explained;
use crate::dialect::Analysis;

/// `genom-check explain dead-service`.
pub const EXPLANATION: &str = r#"A service that no execution of the component can ever start (a service
without start codel: that no execution can accept). Every request is
rejected, or the acknowledged instance stays pending forever.

Why it matters: the service is useless as described; clients always get
`NOT_INITIALIZED`, `FORBIDDEN` or no reply at all. Typical causes: an `init`
service that can never succeed, an `auto` service that `forbids` it, or a
permanent service that `delays` it. The trace shows a request and why it
fails. Its codels are not reported as unreachable (this error covers them).

Example:

```
auto service monitor { thread: t; forbids: calibrate; start codel { exec: m(); next: start; } }
service calibrate { thread: t; start codel { exec: c(); } }    // dead-service: always FORBIDDEN
```"#;

/// The codes of this verdict, for the registry ([`super::VERDICTS`]).
pub const CODES: &[Explained] = &[(Code::DeadService, EXPLANATION)];

/// `service` never starts, because of `reason`.
pub fn dead_service(c: &Component, service: ServiceId, reason: &str, trace: Trace) -> Diagnostic {
    let s = &c.services[service];
    let mut d = Diagnostic::new(
        Code::DeadService,
        format!("service `{}` can never start", s.name.name),
        s.name.span,
        "no execution starts this service",
    )
    .with_help(reason.to_owned());
    for (_, t) in c
        .services
        .iter()
        .filter(|(t, ts)| *t != service && ts.forbids.iter().any(|r| r.id == service))
    {
        if let Some(r) = t.forbids.iter().find(|r| r.id == service) {
            d = d.with_label(r.span, format!("`{}` forbids it", t.name.name));
        }
    }
    d.with_trace(trace)
}

/// One diagnostic per service proven never to start.
pub fn check(c: &Component, analysis: &Analysis) -> Vec<Diagnostic> {
    analysis
        .dead
        .iter()
        .map(|b| dead_service(c, b.service, &b.reason, b.trace.clone()))
        .collect()
}
