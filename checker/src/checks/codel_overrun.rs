//! `codel-overrun`: a codel whose WCET is longer than the period of the
//! thread that runs it (a static check on the WCETs).

use genom_model::component::Component;
use genom_model::kinds::CodelKind;
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
    // Control codels run on the control thread, not the service's thread.
    for codel in c.codels.values().filter(|k| k.kind != CodelKind::Control) {
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

#[cfg(test)]
mod tests {
    use genom_model::Code;

    use crate::testing::{self, HEADER};

    /// A service on `main` (period 10ms) with these codels.
    fn service(codels: &str) -> String {
        format!("{HEADER}service s {{\n  thread: main;\n{codels}}}\n")
    }

    #[test]
    fn a_wcet_longer_than_the_period_is_reported() {
        let src = service("  start codel { exec: f(); max-time: 10000001ns; next: end; }\n");
        let d = testing::check(&src).diagnostics;
        let overruns: Vec<_> = d.iter().filter(|d| d.code == Code::CodelOverrun).collect();
        assert_eq!(overruns.len(), 1);
        assert_eq!(
            overruns[0].message,
            "codel `s::start` may take 10000001ns but thread `main` wakes up every 10ms"
        );
    }

    #[test]
    fn a_wcet_equal_to_the_period_is_clean() {
        let src = service("  start codel { exec: f(); max-time: 10ms; next: end; }\n");
        assert_eq!(testing::count(&src, Code::CodelOverrun), 0);
    }

    #[test]
    fn a_control_codel_runs_on_the_control_thread() {
        let src = service(
            "  control codel { exec: c(); max-time: 50ms; }\n  start codel { exec: f(); max-time: 1ms; next: end; }\n",
        );
        assert_eq!(testing::count(&src, Code::CodelOverrun), 0);
    }
}
