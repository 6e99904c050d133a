//! Tests of the `codel_transitions` diagnostics, which the front-end raises while
//! resolving (`gen_frontend::checks::codel_transitions`), through the whole check.

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
