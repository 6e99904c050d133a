//! `missing-on-inter` (advice): a start or exec codel without `on-inter` in
//! a service that something can interrupt: some service (itself included)
//! lists it in `stops`, or it has its own `max-time` watchdog
//! (LANGUAGE.md 2.7 and 3).
//!
//! Interrupted at such a codel, the service ends at once with `INTERRUPTED`
//! (or `TIMEOUT`) without running any cleanup: a motor keeps its last
//! command, a device stays open. It is advice because ending at once is
//! sometimes exactly what is wanted (a codel that only reads).

use std::collections::BTreeMap;

use genom_model::component::{Component, ServiceId};
use genom_model::kinds::CodelKind;
use genom_model::{Code, Diagnostic, Dialect, Span};

use super::registry::{Applies, StaticCheck};

/// `genom-check explain missing-on-inter`.
pub const EXPLANATION: &str = r#"A start or exec codel has no `on-inter`, and its service can be interrupted:
some service lists it in `stops` (a self-stopping service is interrupted by
its own next request), or it has a `max-time` enforced by the watchdog.

Why it matters: a service interrupted while at a codel without `on-inter`
ends at once with `INTERRUPTED` (`TIMEOUT` for the watchdog) and runs no
cleanup code. Whatever the codel left behind stays as it is: a wheel keeps
its last velocity reference, a camera keeps streaming, a gripper keeps
squeezing.

Example:

```
service move {
  thread: motionTask;
  stops: move;                                  // a new goal interrupts the old one
  start codel { exec: plan(); on-inter: stop; next: goto; }
  exec codel goto { exec: go(); next: goto, end; }   // missing-on-inter
  inter codel stop { exec: brake(); }
}
```

Add `on-inter: stop;` to `goto`. This is advice: ending at once is fine for
a codel that changes nothing outside the component."#;

/// What makes a service interruptible.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Interrupter<'a> {
    /// Service `by` lists it in `stops`, at this span.
    Stops {
        /// The stopping service.
        by: &'a str,
        /// Whether it is the service itself.
        itself: bool,
        /// The `stops` reference.
        span: Span,
    },
    /// Its own `max-time`, at this span.
    MaxTime(Span),
}

/// An interruptible start or exec codel without `on-inter`.
pub fn missing(service: &str, codel: &str, span: Span, why: Interrupter<'_>) -> Diagnostic {
    let d = Diagnostic::new(
        Code::MissingOnInter,
        format!("codel `{codel}` of service `{service}` can be interrupted but has no `on-inter`"),
        span,
        "no cleanup codel if interrupted here",
    );
    let (d, reply) = match why {
        Interrupter::Stops {
            itself: true, span, ..
        } => (
            d.with_label(span, format!("a new request of `{service}` interrupts it")),
            "`INTERRUPTED`",
        ),
        Interrupter::Stops { by, span, .. } => (
            d.with_label(span, format!("a request of `{by}` interrupts it")),
            "`INTERRUPTED`",
        ),
        Interrupter::MaxTime(span) => (
            d.with_label(span, "the watchdog interrupts it after this"),
            "`TIMEOUT`",
        ),
    };
    d.with_help(format!(
        "interrupting `{service}` while at `{codel}` ends it at once with {reply}, without any \
         cleanup; add `on-inter: NAME;` naming an inter codel that leaves things in a safe state"
    ))
}

/// What makes each service interruptible: the first service (in order)
/// that lists it in `stops`, else its own `max-time`. One pass over every
/// `stops` list, not one per service.
fn interrupters(c: &Component) -> BTreeMap<ServiceId, Interrupter<'_>> {
    let mut out = BTreeMap::new();
    for (id, s) in c.services.iter() {
        for r in &s.stops {
            out.entry(r.id).or_insert(Interrupter::Stops {
                by: s.name.name.as_str(),
                itself: id == r.id,
                span: r.span,
            });
        }
    }
    for (id, s) in c.services.iter() {
        if let Some(m) = s.max_time {
            out.entry(id).or_insert(Interrupter::MaxTime(m.span));
        }
    }
    out
}

/// The registry's entry ([`super::STATIC_CHECKS`]).
pub const CHECK: StaticCheck = StaticCheck {
    name: "on-inter cleanup",
    applies: Applies::Only(Dialect::Gen),
    run: check,
    codes: &[(Code::MissingOnInter, EXPLANATION)],
};

/// Reports every start and exec codel without `on-inter` of every
/// interruptible service with a start codel.
///
/// Not run on GenoM3 components (`checks::run` registers it for the
/// dialect only): an interrupted GenoM3 activity runs its
/// `stop` codel when it has one and otherwise ends at once; most real
/// activities have none, and advising one for every interruptible activity
/// would flood real components (21 advices on `rotorcraft.gen`).
pub fn check(c: &Component) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let interrupters = interrupters(c);
    for (id, service) in c.services.iter() {
        if service.start.is_none() {
            continue;
        }
        let Some(&why) = interrupters.get(&id) else {
            continue;
        };
        for &cid in &service.codels {
            let codel = &c.codels[cid];
            let interruptible = matches!(codel.kind, CodelKind::Start | CodelKind::Exec);
            if interruptible && codel.on_inter.is_none() {
                out.push(missing(
                    &service.name.name,
                    &codel.name.name,
                    codel.name.span,
                    why,
                ));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use genom_model::{Code, Diagnostic, Severity};

    use crate::testing;

    fn src(body: &str) -> String {
        format!("{}{body}", testing::HEADER)
    }

    fn found(src: &str) -> Vec<Diagnostic> {
        testing::check(src)
            .diagnostics
            .into_iter()
            .filter(|d| d.code == Code::MissingOnInter)
            .collect()
    }

    fn labels(src: &str, d: &Diagnostic) -> Vec<(String, String)> {
        d.labels
            .iter()
            .map(|l| {
                let text = &src[l.span.start as usize..l.span.end as usize];
                (text.to_owned(), l.message.clone())
            })
            .collect()
    }

    const SELF_STOPPING: &str = "service move {
  thread: main;
  stops: move;
  start codel { exec: plan(); on-inter: stop; next: goto; }
  exec codel goto { exec: go(); next: goto, end; }
  inter codel stop { exec: brake(); }
}
";

    const CLEANED_UP: &str = "service move {
  thread: main;
  stops: move;
  start codel { exec: plan(); on-inter: stop; next: goto; }
  exec codel goto { exec: go(); on-inter: stop; next: goto, end; }
  inter codel stop { exec: brake(); }
}
";

    #[test]
    fn a_self_stopping_service_needs_cleanup_at_every_codel() {
        let s = src(SELF_STOPPING);
        let d = found(&s);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].severity, Severity::Advice);
        assert_eq!(
            d[0].message,
            "codel `goto` of service `move` can be interrupted but has no `on-inter`"
        );
        assert_eq!(
            labels(&s, &d[0]),
            [
                ("goto".into(), "no cleanup codel if interrupted here".into()),
                (
                    "move".into(),
                    "a new request of `move` interrupts it".into()
                ),
            ]
        );
        assert!(
            d[0].help
                .as_deref()
                .is_some_and(|h| h.contains("`INTERRUPTED`"))
        );
    }

    #[test]
    fn codels_with_on_inter_are_fine() {
        assert_eq!(testing::count(&src(CLEANED_UP), Code::MissingOnInter), 0);
    }

    #[test]
    fn another_service_stopping_it_makes_it_interruptible() {
        let s = src("service move {
  thread: main;
  start codel { exec: go(); next: end; }
}
service halt {
  stops: move;
}
");
        let d = found(&s);
        assert_eq!(d.len(), 1);
        assert_eq!(labels(&s, &d[0])[0].0, "start");
        assert_eq!(
            labels(&s, &d[0])[1],
            ("move".into(), "a request of `halt` interrupts it".into())
        );
    }

    #[test]
    fn a_max_time_makes_it_interruptible() {
        let s = src("service move {
  thread: main;
  max-time: 2s;
  start codel { exec: go(); next: end; }
}
");
        let d = found(&s);
        assert_eq!(d.len(), 1);
        assert_eq!(
            labels(&s, &d[0])[1],
            ("2s".into(), "the watchdog interrupts it after this".into())
        );
        assert!(
            d[0].help
                .as_deref()
                .is_some_and(|h| h.contains("`TIMEOUT`"))
        );
    }

    #[test]
    fn a_service_nothing_interrupts_needs_no_cleanup() {
        let s = src("service move {
  thread: main;
  start codel { exec: go(); next: goto; }
  exec codel goto { exec: go(); next: end; }
}
");
        assert_eq!(testing::count(&s, Code::MissingOnInter), 0);
    }

    #[test]
    fn report() {
        insta::assert_snapshot!(testing::render(&src(SELF_STOPPING)));
    }
}
