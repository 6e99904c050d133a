//! `auto-terminates`: an `auto` service that can end by itself
//! (LANGUAGE.md 2.6 and 4): a codel reached from its start codel through
//! `next` outcomes has an `end` or report outcome (an absent or empty `next`
//! means `end`), or the service has no start codel at all and so completes
//! as soon as it is started.
//!
//! An `auto` service is started once by the component and is meant to run
//! permanently (a monitor, an odometry integrator); when it ends nothing
//! restarts it, so whatever it maintained silently goes stale.

use genom_model::component::{Codel, Component, Outcome, Service};
use genom_model::kinds::ServiceKind;
use genom_model::{Code, Diagnostic, Span};

use super::registry::{Applies, StaticCheck};
use super::unreachable_codel::{codel_graph, reachable_from};

/// `genom-check explain auto-terminates`.
pub const EXPLANATION: &str = r#"An `auto` service can end by itself: a codel reached from its start codel
has an `end` or report outcome in its `next` (an absent or empty `next`
means `next: end`), or the service has no start codel and completes as soon
as it is started.

Why it matters: an `auto` service is started once by the component, when
initialisation is done, and is meant to run permanently: a monitor, an
odometry integrator, a watchdog. Nothing restarts it when it ends, so the
data it maintains silently goes stale.

Example:

```
auto service Odometry {
  thread: odoTask;
  start codel { exec: odoReset(); next: integrate; }
  exec codel integrate {
    exec: odoIntegrate();
    next: integrate, end;     // auto-terminates: `end` stops the odometry
  }
}
```

Loop back to a codel instead of ending (`next: integrate;`). Ending through
inter codels after an interruption is not reported: that is a request, not
the service ending by itself. If the service is meant to end, remove
`auto` and have a client request it."#;

/// Where an `auto` service ends by itself: a span and its label.
pub type EndPoint = (Span, String);

/// An `auto` service that ends at some reachable codels.
pub fn ends_by_itself(service: &str, span: Span, ends: &[EndPoint]) -> Diagnostic {
    let mut d = Diagnostic::new(
        Code::AutoTerminates,
        format!("auto service `{service}` can end by itself"),
        span,
        "an `auto` service is meant to run permanently",
    );
    for (span, label) in ends {
        d = d.with_label(*span, label.clone());
    }
    d.with_help(
        "nothing restarts an `auto` service once it has ended: loop back to a codel instead of \
         ending, or remove `auto` if the service is meant to end",
    )
}

/// An `auto` service without a start codel.
pub fn no_start(service: &str, span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::AutoTerminates,
        format!("auto service `{service}` has no start codel, so it ends as soon as it starts"),
        span,
        "completes at once: nothing runs on a thread",
    )
    .with_help(
        "give it a thread, a start codel and a loop of exec codels, or remove `auto` if it is an \
         attribute setter",
    )
}

/// Where a codel ends its service: each written `end` or report outcome, or
/// the codel name when its `next` is absent or empty.
fn end_points(service: &Service, codel: &Codel) -> Vec<EndPoint> {
    if codel.next.is_empty() {
        let why = if codel.next_span.is_some() {
            "ends here: an empty `next` means `next: end`"
        } else {
            "ends here: no `next` means `next: end`"
        };
        return vec![(codel.name.span, why.to_owned())];
    }
    codel
        .next
        .iter()
        .filter_map(|n| match n.outcome {
            Outcome::End => Some((n.span, "ends here".to_owned())),
            Outcome::Report(r) => {
                let name = service.reports.get(r).map_or("?", |r| r.name.as_str());
                Some((n.span, format!("ends here with report `{name}`")))
            }
            Outcome::Codel(_) => None,
        })
        .collect()
}

/// The registry's entry ([`super::STATIC_CHECKS`]).
pub const CHECK: StaticCheck = StaticCheck {
    name: "auto services",
    applies: Applies::Always,
    run: check,
    codes: &[(Code::AutoTerminates, EXPLANATION)],
};

/// Reports every `auto` service that can end by itself.
pub fn check(c: &Component) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for service in c.services.values() {
        if service.kind != ServiceKind::Auto {
            continue;
        }
        let name = &service.name;
        let Some(start) = service.start else {
            out.push(no_start(&name.name, name.span));
            continue;
        };
        let reached = reachable_from(&codel_graph(c, service, false), start);
        let ends: Vec<EndPoint> = service
            .codels
            .iter()
            .filter(|id| reached.contains(id))
            .flat_map(|&id| end_points(service, &c.codels[id]))
            .collect();
        if !ends.is_empty() {
            out.push(ends_by_itself(&name.name, name.span, &ends));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use genom_model::{Code, Diagnostic};

    use crate::testing;

    fn src(body: &str) -> String {
        format!("{}{body}", testing::HEADER)
    }

    fn found(src: &str) -> Vec<Diagnostic> {
        testing::check(src)
            .diagnostics
            .into_iter()
            .filter(|d| d.code == Code::AutoTerminates)
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

    const ENDING: &str = "auto service Odometry {
  thread: main;
  report: LOST;
  start codel { exec: reset(); next: integrate; }
  exec codel integrate { exec: integrate(); next: integrate, fix, end; }
  exec codel fix { exec: fix(); next: integrate, LOST; }
}
";

    const LOOPING: &str = "auto service Odometry {
  thread: main;
  report: LOST;
  start codel { exec: reset(); next: integrate; }
  exec codel integrate { exec: integrate(); next: integrate, fix; }
  exec codel fix { exec: fix(); next: integrate; }
}
";

    #[test]
    fn end_and_report_outcomes_are_labelled() {
        let s = src(ENDING);
        let d = found(&s);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].message, "auto service `Odometry` can end by itself");
        let l = labels(&s, &d[0]);
        assert_eq!(
            l,
            [
                (
                    "Odometry".into(),
                    "an `auto` service is meant to run permanently".into()
                ),
                ("end".into(), "ends here".into()),
                ("LOST".into(), "ends here with report `LOST`".into()),
            ]
        );
    }

    #[test]
    fn a_permanent_loop_does_not_end() {
        assert_eq!(testing::count(&src(LOOPING), Code::AutoTerminates), 0);
    }

    #[test]
    fn an_absent_or_empty_next_is_an_implicit_end() {
        let s = src("auto service watch {
  thread: main;
  start codel { exec: init(); next: a, b; }
  exec codel a { exec: go(); }
  exec codel b { exec: go(); next: ; }
}
");
        let d = found(&s);
        assert_eq!(d.len(), 1);
        let l = labels(&s, &d[0]);
        assert_eq!(l.len(), 3);
        assert_eq!(
            l[1],
            ("a".into(), "ends here: no `next` means `next: end`".into())
        );
        assert_eq!(
            l[2],
            (
                "b".into(),
                "ends here: an empty `next` means `next: end`".into()
            )
        );
    }

    #[test]
    fn ending_after_an_interruption_or_from_unreachable_codels_is_not_reported() {
        let s = src("auto service watch {
  thread: main;
  stops: watch;
  start codel { exec: init(); on-inter: stop; next: loop; }
  exec codel loop { exec: go(); on-inter: stop; next: loop; }
  inter codel stop { exec: halt(); next: end; }
  exec codel never { exec: go(); next: end; }
}
");
        assert_eq!(testing::count(&s, Code::AutoTerminates), 0);
    }

    #[test]
    fn an_auto_service_without_start_codel_completes_at_once() {
        let s = src("auto service setup {\n  control codel { exec: check(); }\n}\n");
        let d = found(&s);
        assert_eq!(d.len(), 1);
        assert_eq!(
            d[0].message,
            "auto service `setup` has no start codel, so it ends as soon as it starts"
        );
        assert_eq!(labels(&s, &d[0])[0].0, "setup");
        let plain = src("service setup {\n  control codel { exec: check(); }\n}\n");
        assert_eq!(testing::count(&plain, Code::AutoTerminates), 0);
    }

    #[test]
    fn report() {
        insta::assert_snapshot!(testing::render(&src(ENDING)));
    }
}
