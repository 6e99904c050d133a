//! `bad-next`, `bad-on-inter` and `ambiguous-name`: the transition rules of
//! codels (LANGUAGE.md 2.7). `next` names codels of the same service, its
//! reports or `end`; `on-inter` names an inter codel and is not allowed on
//! control and inter codels; a name may not be both a codel and a report.

use genom_model::{Code, Diagnostic, Span};

/// `genom-check explain bad-next`.
pub const EXPLANATION_BAD_NEXT: &str = r#"A `next` outcome that is not allowed: the control codel (it only accepts or
rejects a request, so it has no `next` and is never a target), a codel of
another service, or the same outcome twice.

Why it matters: `next` is the state machine of the service; an outcome the
engine cannot follow would leave the service stuck.

Example:

```
service move {
  control codel { exec: check(); next: goto; }   // bad-next: control codels have no next
  exec codel goto { exec: go(); next: control; } // bad-next: the control codel is not a state
}
```

`next: ;` (or no `next`) means `next: end;`."#;

/// `genom-check explain bad-on-inter`.
pub const EXPLANATION_BAD_ON_INTER: &str = r#"An `on-inter` that is not allowed: on a control codel (it runs before the
service exists), on an inter codel (a stopping service is not interrupted
again), or naming a codel that is not an inter codel.

Why it matters: `on-inter` says how to clean up when the service is
interrupted at that codel; it must lead to cleanup code.

Example:

```
inter codel stop { exec: halt(); on-inter: stop; }   // bad-on-inter
exec codel goto { exec: go(); on-inter: goto; }      // bad-on-inter: `goto` is not an inter codel
```"#;

/// `genom-check explain ambiguous-name`.
pub const EXPLANATION_AMBIGUOUS_NAME: &str = r#"A name that is both a codel and a report of the same service, or a codel
named `end`.

Why it matters: in `next: X;` the engine could not tell whether to go to
codel `X` or to end the service with report `X`; `end` always means
successful termination.

Example:

```
service move {
  report: stop;
  inter codel stop { exec: halt(); }   // ambiguous-name: `stop` is also a report
}
```"#;

/// `next` on a control codel.
pub fn next_on_control(span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::BadNext,
        "a control codel has no `next`",
        span,
        "not allowed on a control codel",
    )
    .with_help(
        "the control codel only accepts the request or rejects it with a report; remove `next`",
    )
}

/// A `next` entry naming the control codel.
pub fn next_to_control(span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::BadNext,
        "`next` cannot go to the control codel",
        span,
        "the control codel is not a state",
    )
    .with_help("`next` names start, exec or inter codels of the service, its reports, or `end`")
}

/// A `next` entry naming a codel of another service.
pub fn next_to_other_service(name: &str, span: Span, owner: &str, owner_span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::BadNext,
        format!("`{name}` is a codel of service `{owner}`, not of this service"),
        span,
        "codel of another service",
    )
    .with_label(owner_span, format!("`{name}` is defined in `{owner}`"))
    .with_help("a service's codels can only go to codels of the same service")
}

/// The same outcome listed twice.
pub fn next_twice(name: &str, second: Span, first: Span) -> Diagnostic {
    Diagnostic::new(
        Code::BadNext,
        format!("`{name}` is listed twice in `next`"),
        second,
        "listed again",
    )
    .with_label(first, "first listed here")
}

/// `on-inter` on a control or inter codel.
pub fn on_inter_not_allowed(kind: &str, span: Span) -> Diagnostic {
    let why = if kind == "inter" {
        "a stopping service is not interrupted again"
    } else {
        "the control codel runs before the service instance exists"
    };
    Diagnostic::new(
        Code::BadOnInter,
        format!("`on-inter` is not allowed on {kind} codels"),
        span,
        "not allowed here",
    )
    .with_help(format!("remove it: {why}"))
}

/// `on-inter` naming a codel that is not an inter codel.
pub fn on_inter_not_inter(name: &str, kind: &str, span: Span, target: Span) -> Diagnostic {
    Diagnostic::new(
        Code::BadOnInter,
        format!(
            "`on-inter` must name an inter codel, and `{name}` is {} {kind} codel",
            article(kind)
        ),
        span,
        "not an inter codel",
    )
    .with_label(target, format!("`{name}` is declared here"))
    .with_help("declare the cleanup as `inter codel NAME { ... }`")
}

/// A name that is both a codel and a report.
pub fn codel_and_report(name: &str, codel: Span, report: Span) -> Diagnostic {
    Diagnostic::new(
        Code::AmbiguousName,
        format!("`{name}` is both a codel and a report of this service"),
        codel,
        "a codel",
    )
    .with_label(report, "a report")
    .with_help("rename the codel or the report so that `next` is unambiguous")
}

/// A codel named `end`.
pub fn codel_named_end(span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::AmbiguousName,
        "a codel cannot be named `end`",
        span,
        "`end` means successful termination",
    )
    .with_help("rename the codel")
}

fn article(word: &str) -> &'static str {
    if word.starts_with(['a', 'e', 'i', 'o', 'u']) {
        "an"
    } else {
        "a"
    }
}

#[cfg(test)]
mod tests {
    use genom_model::{Code, Span};

    use crate::CheckResult;
    use crate::testing::{self, HEADER};

    /// Every diagnostic of `code` in `src`, as
    /// ``line:col `primary text` + line:col `label text`...: message``.
    fn found(src: &str, code: Code) -> Vec<String> {
        let r = testing::check(src);
        r.diagnostics
            .iter()
            .filter(|d| d.code == code)
            .map(|d| {
                let spans: Vec<String> = d.labels.iter().map(|l| at(&r, l.span)).collect();
                format!("{}: {}", spans.join(" + "), d.message)
            })
            .collect()
    }

    fn at(r: &CheckResult, span: Span) -> String {
        let (line, col) = r
            .sources
            .locate(span)
            .and_then(|l| Some(r.sources.file(l.file)?.line_col(l.offset)))
            .unwrap_or_default();
        format!("{line}:{col} `{}`", r.sources.slice(span))
    }

    /// A service `move` on thread `main` with report `TOO_FAR` and `codels`.
    fn service(codels: &str) -> String {
        format!("{HEADER}service move {{\n  thread: main;\n  report: TOO_FAR;\n{codels}}}\n")
    }

    fn none_of(src: &str, code: Code) {
        assert_eq!(testing::count(src, code), 0, "{}", testing::render(src));
    }

    #[test]
    fn next_on_a_control_codel() {
        let s = service(
            "  control codel { exec: check(); next: goto; }\n  start codel { exec: go(); next: goto; }\n  exec codel goto { exec: go(); }\n",
        );
        assert_eq!(
            found(&s, Code::BadNext),
            ["6:34 `next`: a control codel has no `next`"]
        );
        none_of(
            &service(
                "  control codel { exec: check(); }\n  start codel { exec: go(); next: goto; }\n  exec codel goto { exec: go(); }\n",
            ),
            Code::BadNext,
        );
    }

    #[test]
    fn next_to_the_control_codel() {
        let s = service(
            "  control codel { exec: check(); }\n  start codel { exec: go(); next: control, end; }\n",
        );
        assert_eq!(
            found(&s, Code::BadNext),
            ["7:35 `control`: `next` cannot go to the control codel"]
        );
        none_of(
            &service(
                "  control codel { exec: check(); }\n  start codel { exec: go(); next: end; }\n",
            ),
            Code::BadNext,
        );
    }

    #[test]
    fn next_to_a_codel_of_another_service() {
        let s = format!(
            "{HEADER}service turn {{\n  thread: main;\n  start codel {{ exec: turn(); next: spin; }}\n  exec codel spin {{ exec: spin(); }}\n}}\n\
             service move {{\n  thread: main;\n  start codel {{ exec: go(); next: spin; }}\n}}\n"
        );
        assert_eq!(
            found(&s, Code::BadNext),
            [
                "10:35 `spin` + 6:14 `spin`: `spin` is a codel of service `turn`, not of this service"
            ]
        );
        // Not also reported as an unknown codel.
        assert_eq!(testing::count(&s, Code::UnknownCodel), 0);
    }

    #[test]
    fn an_outcome_listed_twice() {
        let s = service(
            "  start codel { exec: go(); next: goto, TOO_FAR, goto, TOO_FAR; }\n  exec codel goto { exec: go(); next: end, end; }\n",
        );
        assert_eq!(
            found(&s, Code::BadNext),
            [
                "6:50 `goto` + 6:35 `goto`: `goto` is listed twice in `next`",
                "6:56 `TOO_FAR` + 6:41 `TOO_FAR`: `TOO_FAR` is listed twice in `next`",
                "7:44 `end` + 7:39 `end`: `end` is listed twice in `next`",
            ]
        );
        none_of(
            &service(
                "  start codel { exec: go(); next: goto, TOO_FAR; }\n  exec codel goto { exec: go(); next: end, goto; }\n",
            ),
            Code::BadNext,
        );
    }

    #[test]
    fn on_inter_on_a_control_or_an_inter_codel() {
        let s = service(
            "  control codel { exec: check(); on-inter: stop; }\n  start codel { exec: go(); on-inter: stop; next: end; }\n  inter codel stop { exec: halt(); on-inter: stop; }\n",
        );
        assert_eq!(
            found(&s, Code::BadOnInter),
            [
                "6:34 `on-inter`: `on-inter` is not allowed on control codels",
                "8:36 `on-inter`: `on-inter` is not allowed on inter codels",
            ]
        );
        let r = testing::check(&s);
        let helps: Vec<&str> = r
            .diagnostics
            .iter()
            .filter(|d| d.code == Code::BadOnInter)
            .filter_map(|d| d.help.as_deref())
            .collect();
        assert_eq!(
            helps,
            [
                "remove it: the control codel runs before the service instance exists",
                "remove it: a stopping service is not interrupted again",
            ]
        );
        none_of(
            &service(
                "  control codel { exec: check(); }\n  start codel { exec: go(); on-inter: stop; next: end; }\n  inter codel stop { exec: halt(); }\n",
            ),
            Code::BadOnInter,
        );
    }

    #[test]
    fn on_inter_naming_a_codel_that_is_not_an_inter_codel() {
        let s = service(
            "  control codel { exec: check(); }\n  start codel { exec: go(); on-inter: goto; next: goto; }\n  exec codel goto { exec: go(); on-inter: start; }\n  exec codel home { exec: go(); on-inter: control; }\n",
        );
        assert_eq!(
            found(&s, Code::BadOnInter),
            [
                "7:39 `goto` + 8:14 `goto`: `on-inter` must name an inter codel, and `goto` is an exec codel",
                "8:43 `start` + 7:3 `start`: `on-inter` must name an inter codel, and `start` is a start codel",
                "9:43 `control` + 6:3 `control`: `on-inter` must name an inter codel, and `control` is a control codel",
            ]
        );
    }

    #[test]
    fn a_codel_named_like_a_report() {
        let s = format!(
            "{HEADER}service move {{\n  thread: main;\n  report: stop, BLOCKED;\n  start codel {{ exec: go(); on-inter: stop; next: BLOCKED; }}\n  inter codel stop {{ exec: halt(); }}\n}}\n"
        );
        assert_eq!(
            found(&s, Code::AmbiguousName),
            ["7:15 `stop` + 5:11 `stop`: `stop` is both a codel and a report of this service"]
        );
        // A report of another service may share a codel's name.
        let other = format!(
            "{HEADER}service turn {{ report: stop; control codel {{ exec: check(); }} }}\n\
             service move {{\n  thread: main;\n  start codel {{ exec: go(); on-inter: stop; }}\n  inter codel stop {{ exec: halt(); }}\n}}\n"
        );
        none_of(&other, Code::AmbiguousName);
    }

    #[test]
    fn a_codel_named_end() {
        let s = service(
            "  start codel { exec: go(); next: end; }\n  exec codel end { exec: finish(); }\n",
        );
        assert_eq!(
            found(&s, Code::AmbiguousName),
            ["7:14 `end`: a codel cannot be named `end`"]
        );
        none_of(
            &service(
                "  start codel { exec: go(); next: finish; }\n  exec codel finish { exec: finish(); }\n",
            ),
            Code::AmbiguousName,
        );
    }

    #[test]
    fn keywords_are_codel_names() {
        let s = service(
            "  start codel { exec: go(); on-inter: stop; next: start, exec, stop; }\n  exec codel exec { exec: go(); on-inter: stop; next: TOO_FAR; }\n  inter codel stop { exec: halt(); }\n",
        );
        let errors: Vec<Code> = testing::check(&s)
            .diagnostics
            .iter()
            .filter(|d| d.severity == genom_model::Severity::Error)
            .map(|d| d.code)
            .collect();
        assert!(errors.is_empty(), "{}", testing::render(&s));
    }

    #[test]
    fn snapshot() {
        let s = service(
            "  control codel { exec: check(); next: start; }\n  start codel { exec: go(); on-inter: goto; next: goto, goto; }\n  exec codel goto { exec: go(); next: control; }\n",
        );
        insta::assert_snapshot!(testing::render(&s));
    }
}
