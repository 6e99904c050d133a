//! Tests of the `invalid_attribute` diagnostics, which the front-end raises while
//! resolving (`gen_frontend::checks::invalid_attribute`), through the whole check.

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

    fn invalid(body: &str) -> Vec<String> {
        found(&format!("{HEADER}{body}"), Code::InvalidAttribute)
    }

    fn valid(body: &str) {
        let src = format!("{HEADER}{body}");
        assert_eq!(
            testing::count(&src, Code::InvalidAttribute),
            0,
            "{}",
            testing::render(&src)
        );
    }

    #[test]
    fn period_in_a_service_is_not_allowed() {
        let body = "service move {\n  period: 10ms;\n  control codel { exec: check(); }\n}\n";
        assert_eq!(
            invalid(body),
            ["4:3 `period`: `period` is not allowed in a service"]
        );
        let r = testing::check(&format!("{HEADER}{body}"));
        assert_eq!(
            r.diagnostics[0].help.as_deref(),
            Some(
                "a service takes `doc`, `thread`, `report`, `max-time`, `credential`, `stops`, \
                 `delays`, `forbids`, `input`, `output`, `import`, `export`"
            )
        );
        valid("service move {\n  max-time: 10ms;\n  control codel { exec: check(); }\n}\n");
    }

    #[test]
    fn thread_in_a_codel_and_next_in_a_thread_are_not_allowed() {
        let body = "thread t { period: 1s; next: end; }\n\
                    service move {\n  thread: main;\n  start codel { exec: go(); thread: main; }\n}\n";
        assert_eq!(
            invalid(body),
            [
                "3:24 `next`: `next` is not allowed in a thread",
                "6:29 `thread`: `thread` is not allowed in a codel",
            ]
        );
        valid("service move {\n  thread: main;\n  start codel { exec: go(); }\n}\n");
    }

    #[test]
    fn credentials_belong_to_the_component_only() {
        assert_eq!(
            invalid("service move { credentials: a < b; }\n"),
            ["3:16 `credentials`: `credentials` is not allowed in a service"]
        );
    }

    #[test]
    fn an_attribute_given_twice() {
        let body = "service move {\n  thread: main;\n  doc: \"a\";\n  thread: main;\n  start codel { exec: go(); next: end; next: end; }\n}\n";
        assert_eq!(
            invalid(body),
            [
                "6:3 `thread` + 4:3 `thread`: `thread` is given twice",
                "7:40 `next` + 7:29 `next`: `next` is given twice",
            ]
        );
        valid(
            "service move {\n  thread: main;\n  doc: \"a\";\n  start codel { exec: go(); next: end; }\n}\n",
        );
    }

    #[test]
    fn non_positive_period_max_time_and_stack() {
        let body = "thread a { period: 0ms; stack: 0; }\nthread b { period: -1s; }\n\
                    service move {\n  thread: main;\n  max-time: 0s;\n  start codel { exec: go(); max-time: -5us; }\n}\n";
        assert_eq!(
            invalid(body),
            [
                "3:20 `0ms`: `period` must be positive, not `0ms`",
                "3:32 `0`: `stack` must be positive, not `0`",
                "4:20 `-1s`: `period` must be positive, not `-1s`",
                "7:13 `0s`: `max-time` must be positive, not `0s`",
                "8:39 `-5us`: `max-time` must be positive, not `-5us`",
            ]
        );
        valid(
            "thread a { period: 1ns; stack: 1; }\n\
             service move {\n  thread: main;\n  max-time: 1s;\n  start codel { exec: go(); max-time: 5us; }\n}\n",
        );
    }

    #[test]
    fn a_codel_without_exec() {
        let body = "service move {\n  thread: main;\n  start codel { next: goto; }\n  exec codel goto { doc: \"moves\"; }\n}\n";
        assert_eq!(
            invalid(body),
            [
                "5:3 `start`: codel `start` has no `exec`",
                "6:14 `goto`: codel `goto` has no `exec`",
            ]
        );
        valid(
            "service move {\n  thread: main;\n  start codel { exec: a(); next: goto; }\n  exec codel goto { exec: b(); }\n}\n",
        );
    }

    #[test]
    fn an_auto_service_input_without_default() {
        let body = "ids state { double speed := 0.0; }\n\
                    auto service watch {\n  input: double gain, state.speed, double margin := 0.1;\n}\n";
        assert_eq!(
            invalid(body),
            [
                "5:17 `gain`: input `gain` of auto service `watch` has no default",
                "5:29 `speed`: input `speed` of auto service `watch` has no default",
            ]
        );
        valid(
            "ids state { double speed := 0.0; }\n\
             auto service watch {\n  input: double gain := 1.0, state.speed := 0.5;\n}\n\
             service move {\n  input: double gain;\n}\n",
        );
    }

    #[test]
    fn the_parser_reports_unknown_names_and_fractional_nanoseconds() {
        assert_eq!(
            invalid("thread t { perod: 1s; }\nthread u { period: 0.5ns; }\n"),
            [
                "3:12 `perod`: unknown attribute `perod`",
                "4:20 `0.5ns`: duration `0.5ns` is not a whole number of nanoseconds",
            ]
        );
    }

    #[test]
    fn snapshot() {
        let src = format!(
            "{HEADER}thread fast {{ period: 0ms; }}\nservice move {{\n  period: 10ms;\n  thread: fast;\n  thread: main;\n  start codel {{ doc: \"no exec\"; }}\n}}\n"
        );
        insta::assert_snapshot!(testing::render(&src));
    }
}
