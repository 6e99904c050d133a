//! Tests of the `service_structure` diagnostics, which the front-end raises while
//! resolving (`gen_frontend::checks::service_structure`), through the whole check.

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

    fn src(body: &str) -> String {
        format!("{HEADER}{body}")
    }

    fn none_of(body: &str, code: Code) {
        let src = src(body);
        assert_eq!(testing::count(&src, code), 0, "{}", testing::render(&src));
    }

    #[test]
    fn missing_start_when_the_service_names_a_thread() {
        let s = src("service move {\n  thread: main;\n  control codel { exec: check(); }\n}\n");
        assert_eq!(
            found(&s, Code::MissingStart),
            ["3:9 `move` + 4:3 `thread`: service `move` has no start codel"]
        );
        none_of(
            "service move {\n  control codel { exec: check(); }\n}\n",
            Code::MissingStart,
        );
    }

    #[test]
    fn missing_start_when_the_service_has_exec_or_inter_codels() {
        let s = src(
            "service move {\n  exec codel goto { exec: go(); }\n}\nservice halt {\n  inter codel stop { exec: stop(); }\n}\n",
        );
        assert_eq!(
            found(&s, Code::MissingStart),
            [
                "3:9 `move` + 4:14 `goto`: service `move` has no start codel",
                "6:9 `halt` + 7:15 `stop`: service `halt` has no start codel",
            ]
        );
        none_of(
            "service move {\n  thread: main;\n  start codel { exec: go(); next: goto; }\n  exec codel goto { exec: go(); }\n}\n",
            Code::MissingStart,
        );
    }

    #[test]
    fn a_service_without_codels_needs_no_start() {
        none_of(
            "ids state { double speed; }\nservice get { output: state.speed; }\n",
            Code::MissingStart,
        );
        none_of(
            "ids state { double speed; }\nservice get { output: state.speed; }\n",
            Code::MissingThread,
        );
    }

    #[test]
    fn missing_thread_names_a_declared_thread_in_its_help() {
        let s = src("service move {\n  start codel { exec: go(); }\n}\n");
        assert_eq!(
            found(&s, Code::MissingThread),
            ["3:9 `move` + 4:3 `start`: service `move` has a start codel but no thread"]
        );
        let r = testing::check(&s);
        assert_eq!(
            r.diagnostics[0].help.as_deref(),
            Some("name the thread that runs it, e.g. `thread: main;`")
        );
        none_of(
            "service move {\n  thread: main;\n  start codel { exec: go(); }\n}\n",
            Code::MissingThread,
        );
    }

    #[test]
    fn missing_thread_without_any_thread_declared() {
        let s = "component t { lang: C; }\nservice move { start codel { exec: go(); } }\n";
        assert_eq!(testing::codes(s), [Code::MissingThread]);
        let r = testing::check(s);
        assert_eq!(
            r.diagnostics[0].help.as_deref(),
            Some("declare a thread (`thread t { period: 10ms; }`) and name it with `thread: t;`")
        );
    }

    #[test]
    fn an_unknown_thread_is_not_also_a_missing_thread() {
        let s = src("service move {\n  thread: mian;\n  start codel { exec: go(); }\n}\n");
        assert_eq!(testing::codes(&s), [Code::UnknownThread]);
    }

    #[test]
    fn multiple_init_labels_the_first_init_service() {
        let s = src(
            "init service setup { doc: \"a\"; }\nservice move { doc: \"b\"; }\ninit service calibrate { doc: \"c\"; }\ninit service home { doc: \"d\"; }\n",
        );
        assert_eq!(
            found(&s, Code::MultipleInit),
            [
                "5:14 `calibrate` + 3:14 `setup`: `calibrate` is another init service (the first is `setup`)",
                "6:14 `home` + 3:14 `setup`: `home` is another init service (the first is `setup`)",
            ]
        );
        none_of(
            "init service setup { doc: \"a\"; }\nauto service move { doc: \"b\"; }\nservice calibrate { doc: \"c\"; }\n",
            Code::MultipleInit,
        );
    }

    #[test]
    fn a_service_named_init_is_not_an_init_service() {
        none_of(
            "init service setup { doc: \"a\"; }\nservice init { doc: \"b\"; }\n",
            Code::MultipleInit,
        );
    }

    #[test]
    fn two_start_codels_or_two_control_codels() {
        let s = src(
            "service move {\n  thread: main;\n  control codel { exec: a(); }\n  start codel { exec: b(); }\n  start codel { exec: b(); }\n  control codel { exec: a(); }\n}\n",
        );
        assert_eq!(
            found(&s, Code::DuplicateCodelKind),
            [
                "7:3 `start` + 6:3 `start`: service `move` has two start codels",
                "8:3 `control` + 5:3 `control`: service `move` has two control codels",
            ]
        );
        none_of(
            "service move {\n  thread: main;\n  control codel { exec: a(); }\n  start codel { exec: b(); }\n}\n\
             service turn {\n  thread: main;\n  control codel { exec: a(); }\n  start codel { exec: b(); }\n}\n",
            Code::DuplicateCodelKind,
        );
    }

    #[test]
    fn snapshot() {
        let s = src(
            "init service setup {\n  start codel { exec: init(); }\n}\ninit service calibrate {\n  thread: main;\n  control codel { exec: a(); }\n  control codel { exec: b(); }\n}\n",
        );
        insta::assert_snapshot!(testing::render(&s));
    }
}
