//! `codel-overrun`: a codel whose WCET is longer than the period of the
//! thread that runs it (a static check on the WCETs).

use genom_model::component::Component;
use genom_model::render::human::format_ns;
use genom_model::{Code, Diagnostic};

/// `genom-check explain codel-overrun`.
pub const EXPLANATION: &str = r#"A codel whose worst-case execution time (its `max-time`) is longer than the
period of the thread that runs it.

Why it matters: a periodic thread runs one codel of each active service per
period; a codel that may take longer than the period makes the thread
overrun (its next wake-up finds the codel still running) whatever else
happens.

Example:

```
thread servo { period: 10ms; }
service servo {
  thread: servo;
  start codel { exec: step(); max-time: 12ms; next: start; }   // codel-overrun
}
```

Split the codel into shorter steps (codels chained with `next`), or run it
on a slower or aperiodic thread."#;

/// Codels whose WCET exceeds their thread's period.
pub fn check(c: &Component) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for codel in c.codels.values() {
        let svc = &c.services[codel.service];
        let Some(t) = svc.thread.map(|t| &c.threads[t.id]) else {
            continue;
        };
        let (Some(wcet), Some(period)) = (codel.wcet, t.period) else {
            continue;
        };
        if wcet.ns > period.ns {
            out.push(
                Diagnostic::new(
                    Code::CodelOverrun,
                    format!(
                        "codel `{}::{}` may take {} but thread `{}` wakes up every {}",
                        svc.name.name,
                        codel.name.name,
                        format_ns(wcet.ns),
                        t.name.name,
                        format_ns(period.ns)
                    ),
                    wcet.span,
                    "WCET longer than the period",
                )
                .with_label(period.span, format!("period of `{}`", t.name.name))
                .with_help("split the codel into shorter codels chained with `next`, or run it on a slower thread"),
            );
        }
    }
    out
}
