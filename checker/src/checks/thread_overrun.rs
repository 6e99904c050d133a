//! `thread-overrun`: a reachable period whose codels (with lock waits) are
//! not finished when the thread wakes up again; found by the timed engine,
//! with a timed trace.

use genom_model::component::Component;
use genom_model::render::human::format_ns;
use genom_model::{Code, Diagnostic};

use crate::timed::TimedFacts;

/// `genom-check explain thread-overrun`.
pub const EXPLANATION: &str = r#"A periodic thread can wake up while codels of its previous period are
still unfinished: the codels of all the services it runs in one period
(one codel per active service, in acknowledgment order), plus the time
they wait for locks held by other threads, can take longer than the period.

Why it matters: a real-time thread that overruns misses its deadline; the
servo loops it runs are late. The timed trace shows the requests that make
these services active together, every wake-up and codel with its instant,
and the wake-up that finds work unfinished.

Example:

```
thread servo { period: 10ms; }
service a { thread: servo; start codel { exec: fa(); max-time: 6ms; next: start; } }
service b { thread: servo; start codel { exec: fb(); max-time: 6ms; next: start; } }
// a and b active together: 12ms of codels in a 10ms period.
```

Make the services exclusive (`stops`, `forbids`), shorten the codels, or
run one of them on another thread. A codel without `max-time` counts as
taking no time (see `missing-wcet`)."#;

/// One diagnostic per thread that can overrun.
pub fn check(c: &Component, facts: &TimedFacts) -> Vec<Diagnostic> {
    let over_codel: Vec<_> = c
        .codels
        .values()
        .filter_map(|k| {
            let t = c.services[k.service].thread?.id;
            let p = c.threads[t].period?;
            (k.wcet?.ns > p.ns).then_some(t)
        })
        .collect();
    facts
        .overruns
        .iter()
        .filter(|o| !over_codel.contains(&o.thread))
        .map(|o| {
            let t = &c.threads[o.thread];
            let period = t.period.map_or(0, |p| p.ns);
            let mut d = Diagnostic::new(
                Code::ThreadOverrun,
                format!("thread `{}` can overrun its {} period", t.name.name, format_ns(period)),
                t.name.span,
                "its codels of one period can take longer than the period",
            )
            .with_help("make the services it runs together exclusive, shorten their codels, or move one to another thread");
            if let Some(p) = t.period {
                d = d.with_label(p.span, "the period");
            }
            d.with_trace(o.trace.clone())
        })
        .collect()
}
