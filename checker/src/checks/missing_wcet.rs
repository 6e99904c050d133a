//! `missing-wcet` (advice): codels without a WCET (`max-time`) are treated as
//! taking no time, so timing properties that involve them are not proven.

use genom_model::component::{Component, ServiceId, ThreadId};
use genom_model::{Code, Diagnostic};

use super::registry::{Applies, StaticCheck};

/// `genom-check explain missing-wcet`.
pub const EXPLANATION: &str = r#"Some codels have no worst-case execution time (`max-time` on the codel).
As the language reference says, such a codel is treated as taking no time:
it never causes a thread overrun or a missed max-time by itself. The advice
names the properties this leaves unproven: overruns of the periodic threads
that run those codels, and the max-time of the services that use them.

Example:

```
thread motionTask { period: 1s; }
service moveDistance {
  thread: motionTask;
  start codel { exec: start(); next: goto; }            // no max-time
  exec codel goto { exec: go(); max-time: 20ms; next: goto, end; }
}
```

Give every codel a `max-time` measured on the target, with a margin.

GenoM3 components: the WCETs come from a side file given with
`--wcet FILE` (or `[wcet]` in genom-check.toml), one `OWNER.STATE DURATION`
line per codel, where OWNER is an activity, a function or attribute (state
`validate` for its validate codel) or a task (its permanent codels):

```
track.start     1ms
track.run       6ms
track.validate  10us
driver.start    200us
```

A codel without a line is taken as running in no time, so the tasks that
run it are not proven to fit their period (`thread-overrun`) and the
response times of the services that use it are too small. Without any WCET
file the timed analysis does not run at all."#;

/// The registry's entry ([`super::STATIC_CHECKS`]).
pub const CHECK: StaticCheck = StaticCheck {
    name: "missing WCETs",
    applies: Applies::Always,
    run: check,
    codes: &[(Code::MissingWcet, EXPLANATION)],
};

/// One advice for the component, when something timing-related depends on
/// codels without WCET.
pub fn check(c: &Component) -> Vec<Diagnostic> {
    let missing = missing(c);
    let threads: Vec<String> = c
        .threads
        .iter()
        .filter(|(_, t)| t.period.is_some())
        .filter(|(id, _)| missing.iter().any(|m| m.thread == Some(*id)))
        .map(|(_, t)| format!("`{}`", t.name.name))
        .collect();
    let services: Vec<String> = c
        .services
        .iter()
        .filter(|(id, s)| s.max_time.is_some() && missing.iter().any(|m| m.service == Some(*id)))
        .map(|(_, s)| format!("`{}`", s.name.name))
        .collect();
    let Some(first) = missing
        .first()
        .filter(|_| !threads.is_empty() || !services.is_empty())
    else {
        return Vec::new();
    };
    let mut unproven = Vec::new();
    if !threads.is_empty() {
        unproven.push(format!("overruns of thread {}", threads.join(", ")));
    }
    if !services.is_empty() {
        unproven.push(format!("the max-time of {}", services.join(", ")));
    }
    let dialect = c.dialect();
    let written = dialect
        .wcet_attribute()
        .map(|a| format!(" (`{a}`)"))
        .unwrap_or_default();
    let remedy = dialect.wcet_remedy();
    let mut d = Diagnostic::new(
        Code::MissingWcet,
        format!(
            "{} without WCET{written} {} taken as running in no time",
            if missing.len() == 1 {
                "1 codel".to_owned()
            } else {
                format!("{} codels", missing.len())
            },
            if missing.len() == 1 { "is" } else { "are" }
        ),
        first.span,
        first.label.clone(),
    );
    for m in missing.iter().skip(1).take(9) {
        d = d.with_label(m.span, m.label.clone());
    }
    vec![d.with_help(format!("left unproven: {}; {remedy}", unproven.join("; ")))]
}

/// A codel without WCET.
struct Missing {
    span: genom_model::span::Span,
    label: String,
    thread: Option<ThreadId>,
    service: Option<ServiceId>,
}

/// The codels without WCET: the model's, then (GenoM3) the permanent
/// codels of the tasks, which are not model codels.
fn missing(c: &Component) -> Vec<Missing> {
    let mut out: Vec<Missing> = c
        .codels
        .values()
        .filter(|k| k.wcet.is_none())
        .map(|k| Missing {
            span: k.name.span,
            label: format!(
                "`{}::{}` has no WCET",
                c.services[k.service].name.name, k.name.name
            ),
            thread: c.services[k.service].thread.map(|t| t.id),
            service: Some(k.service),
        })
        .collect();
    for task in c.genom3.iter().flat_map(|g| g.tasks.iter()) {
        for f in task.codels.iter().filter(|f| f.wcet.is_none()) {
            let states: Vec<&str> = f.states.iter().map(|s| s.name.as_str()).collect();
            out.push(Missing {
                span: f.span,
                label: format!(
                    "task `{}`'s codel `{}` ({}) has no WCET",
                    c.threads[task.thread].name.name,
                    f.function.name,
                    states.join(", ")
                ),
                thread: Some(task.thread),
                service: None,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use genom_model::Code;

    use crate::testing::{self, HEADER};

    fn messages(src: &str) -> Vec<String> {
        testing::check(src)
            .diagnostics
            .iter()
            .filter(|d| d.code == Code::MissingWcet)
            .map(|d| d.message.clone())
            .collect()
    }

    const ONE: &str = "service s { thread: main; start codel { exec: f(); next: end; } }\n";
    const TWO: &str = "service s { thread: main; start codel { exec: f(); next: g; }\n\
                       exec codel g { exec: g(); next: end; } }\n";

    #[test]
    fn one_codel_is_singular_and_several_plural() {
        assert_eq!(
            messages(&format!("{HEADER}{ONE}")),
            ["1 codel without WCET (`max-time`) is taken as running in no time"]
        );
        assert_eq!(
            messages(&format!("{HEADER}{TWO}")),
            ["2 codels without WCET (`max-time`) are taken as running in no time"]
        );
    }

    #[test]
    fn not_given_when_errors_keep_the_timing_checks_from_running() {
        let broken = format!("{HEADER}{ONE}service t {{ thread: nowhere; }}\n");
        assert_eq!(testing::count(&broken, Code::UnknownThread), 1);
        assert!(messages(&broken).is_empty());
    }
}
