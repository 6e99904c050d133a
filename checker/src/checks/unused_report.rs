//! `unused-report`: a report declared by a service that nothing can produce
//! (LANGUAGE.md 2.6, 2.7 and 4): no codel of the service lists it in `next`,
//! and the service has no control codel (a control codel may reject a
//! request with any of the service's reports, so with one every report is
//! producible).
//!
//! Reports are the service's failure interface: clients write code to
//! handle each of them. One that can never be sent is misleading, and often
//! the sign of a `next` entry that was forgotten.

use genom_model::component::{Component, Outcome, Service};
use genom_model::{Code, Diagnostic, Dialect, Span};

use super::registry::{Applies, StaticCheck};

/// `genom-check explain unused-report`.
pub const EXPLANATION: &str = r#"A report that the service can never end with: no codel of the service lists
it in `next`, and the service has no control codel.

Why it matters: the `report:` list is the service's failure interface, and
clients write handlers for each report. A report that can never be sent is
misleading documentation, and usually the sign of a forgotten `next` entry
(the failure is detected but the codel does not end with it).

Example:

```
service move {
  thread: motionTask;
  report: TOO_FAR_AWAY, BLOCKED;     // unused-report: BLOCKED
  start codel { exec: plan(); next: goto, TOO_FAR_AWAY; }
  exec codel goto { exec: go(); next: goto, end; }
}
```

A control codel may reject a request with any of the service's reports, so
a service with a control codel never has an unused report."#;

/// A report that no codel produces.
pub fn unused(service: &str, report: &str, span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::UnusedReport,
        format!("report `{report}` of service `{service}` is never produced"),
        span,
        "no codel ends with it",
    )
    .with_help(format!(
        "no codel lists `{report}` in its `next` and the service has no control codel to reject \
         a request with it; add it to the `next` of the codel that detects the failure, or remove \
         it"
    ))
}

/// Whether some codel of `service` lists report `index` in its `next`.
fn produced(c: &Component, service: &Service, index: usize) -> bool {
    service.codels.iter().any(|&id| {
        c.codels[id]
            .next
            .iter()
            .any(|n| n.outcome == Outcome::Report(index))
    })
}

/// The registry's entry ([`super::STATIC_CHECKS`]).
pub const CHECK: StaticCheck = StaticCheck {
    name: "unused reports",
    applies: Applies::Only(Dialect::Gen),
    run: check,
    codes: &[(Code::UnusedReport, EXPLANATION)],
};

/// Reports every report of a service without control codel that no codel
/// lists in `next`.
///
/// Not run on GenoM3 components (`checks::run` registers it for the
/// dialect only): their codels throw exceptions from their C
/// code (`genom_throw_…`), which the `.gen` file does not show, so a declared
/// exception that no `yield` names may still be thrown.
pub fn check(c: &Component) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for service in c.services.values() {
        // A `next` naming nothing may be a misspelt report: not unused.
        if service.control.is_some() || service.unresolved_next {
            continue;
        }
        for (index, report) in service.reports.iter().enumerate() {
            if !produced(c, service, index) {
                out.push(unused(&service.name.name, &report.name, report.span));
            }
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
            .filter(|d| d.code == Code::UnusedReport)
            .collect()
    }

    const FORGOTTEN: &str = "service move {
  thread: main;
  report: TOO_FAR, BLOCKED;
  start codel { exec: plan(); next: goto, TOO_FAR; }
  exec codel goto { exec: go(); next: goto, end; }
}
";

    const USED: &str = "service move {
  thread: main;
  report: TOO_FAR, BLOCKED;
  start codel { exec: plan(); next: goto, TOO_FAR; }
  exec codel goto { exec: go(); next: goto, end, BLOCKED; }
}
";

    #[test]
    fn a_report_no_next_lists_is_unused() {
        let s = src(FORGOTTEN);
        let d = found(&s);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(
            d[0].message,
            "report `BLOCKED` of service `move` is never produced"
        );
        let span = d[0].labels[0].span;
        assert_eq!(&s[span.start as usize..span.end as usize], "BLOCKED");
        assert_eq!(d[0].labels[0].message, "no codel ends with it");
    }

    #[test]
    fn every_report_listed_in_some_next_is_used() {
        assert_eq!(testing::count(&src(USED), Code::UnusedReport), 0);
    }

    #[test]
    fn a_control_codel_can_produce_any_report() {
        let s = src("service set {
  report: BAD_VALUE, OTHER;
  control codel { exec: check(); }
}
service move {
  thread: main;
  report: BLOCKED;
  control codel { exec: check(); }
  start codel { exec: go(); next: end; }
}
");
        assert_eq!(testing::count(&s, Code::UnusedReport), 0);
    }

    #[test]
    fn a_service_without_codels_cannot_produce_its_reports() {
        let s = src("service get {\n  report: NOPE;\n}\n");
        assert_eq!(testing::count(&s, Code::UnusedReport), 1);
    }

    #[test]
    fn a_misspelt_report_in_next_is_not_also_an_unused_report() {
        let typo = src(&USED.replace("end, BLOCKED;", "end, BLOKED;"));
        assert_eq!(testing::count(&typo, Code::UnknownReport), 1);
        assert_eq!(testing::count(&typo, Code::UnusedReport), 0);
        // Another service's unused report is still reported.
        let both = format!("{typo}{}", FORGOTTEN.replace("move", "turn"));
        assert_eq!(testing::count(&both, Code::UnusedReport), 1);
    }

    #[test]
    fn a_report_named_end_is_one_error_not_also_unused() {
        let s = src(
            "service move {\n  thread: main;\n  report: end, OK;\n  start codel { exec: go(); next: OK; }\n}\n",
        );
        assert_eq!(testing::codes(&s), [Code::AmbiguousName]);
        let d = testing::check(&s).diagnostics;
        assert_eq!(d[0].message, "a report cannot be named `end`");
    }

    #[test]
    fn report() {
        insta::assert_snapshot!(testing::render(&src(FORGOTTEN)));
    }
}
