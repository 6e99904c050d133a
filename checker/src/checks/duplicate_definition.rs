//! Tests of the `duplicate_definition` diagnostics, which the front-end raises while
//! resolving (`gen_frontend::checks::duplicate_definition`), through the whole check.

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

    fn duplicates(body: &str) -> Vec<String> {
        found(&format!("{HEADER}{body}"), Code::DuplicateDefinition)
    }

    fn no_duplicate(body: &str) {
        let src = format!("{HEADER}{body}");
        assert_eq!(
            testing::count(&src, Code::DuplicateDefinition),
            0,
            "{}",
            testing::render(&src)
        );
    }

    #[test]
    fn two_services_with_one_name() {
        let body = "service move { doc: \"a\"; }\nservice move { doc: \"b\"; }\n";
        assert_eq!(
            duplicates(body),
            ["4:9 `move` + 3:9 `move`: the service `move` is defined twice"]
        );
        no_duplicate("service move { doc: \"a\"; }\nservice turn { doc: \"b\"; }\n");
    }

    #[test]
    fn two_threads_with_one_name() {
        assert_eq!(
            duplicates("thread main { period: 5ms; }\n"),
            ["3:8 `main` + 2:8 `main`: the thread `main` is defined twice"]
        );
        no_duplicate("thread fast { period: 5ms; }\n");
    }

    #[test]
    fn a_thread_named_control() {
        assert_eq!(
            duplicates("thread control { period: 5ms; }\n"),
            [
                "3:8 `control`: the thread `control` is the implicit control thread and cannot be declared"
            ]
        );
        no_duplicate("thread controller { period: 5ms; }\n");
    }

    #[test]
    fn a_second_component() {
        assert_eq!(
            duplicates("component other { lang: C; }\n"),
            ["3:11 `other` + 1:11 `t`: the component `other` is defined twice"]
        );
    }

    #[test]
    fn two_codels_of_one_service_but_not_of_two_services() {
        let body = "service s {\n  thread: main;\n  start codel { exec: a(); next: step; }\n  exec codel step { exec: b(); }\n  inter codel step { exec: c(); }\n}\n";
        assert_eq!(
            duplicates(body),
            ["7:15 `step` + 6:14 `step`: the codel `step` is defined twice"]
        );
        no_duplicate(
            "service s { thread: main; start codel { exec: a(); next: step; } exec codel step { exec: b(); } }\n\
             service u { thread: main; start codel { exec: a(); next: step; } exec codel step { exec: b(); } }\n",
        );
    }

    #[test]
    fn two_reports_of_one_service() {
        let body = "service s {\n  report: TOO_FAR, BLOCKED, TOO_FAR;\n  control codel { exec: check(); }\n}\n";
        assert_eq!(
            duplicates(body),
            ["4:29 `TOO_FAR` + 4:11 `TOO_FAR`: the report `TOO_FAR` is defined twice"]
        );
        no_duplicate(
            "service s { report: TOO_FAR; control codel { exec: check(); } }\n\
             service u { report: TOO_FAR; control codel { exec: check(); } }\n",
        );
    }

    #[test]
    fn types_constants_and_enum_values_in_one_module() {
        let body = "typedef struct pose { double x; } pose;\nstruct pose { double y; };\n\
                    const long N = 1;\nconst long N = 2;\nenum mode { IDLE, RUN, IDLE };\n";
        assert_eq!(
            duplicates(body),
            [
                "4:8 `pose` + 3:16 `pose`: the type `pose` is defined twice",
                "6:12 `N` + 5:12 `N`: the constant `N` is defined twice",
                "7:24 `IDLE` + 7:13 `IDLE`: the enum value `IDLE` is defined twice",
            ]
        );
    }

    #[test]
    fn one_name_in_two_modules_is_no_duplicate() {
        no_duplicate(
            "typedef struct pose { double x; } pose;\nconst long N = 1;\nenum mode { IDLE };\n\
             module geo { typedef struct pose { double x; } pose; const long N = 2; enum mode { IDLE }; };\n",
        );
    }

    #[test]
    fn an_enum_value_clashes_with_a_constant_of_its_scope() {
        assert_eq!(
            duplicates("enum mode { IDLE, RUN };\nconst long RUN = 1;\n"),
            ["4:12 `RUN` + 3:19 `RUN`: the constant `RUN` is defined twice"]
        );
    }

    #[test]
    fn two_fields_of_a_struct() {
        assert_eq!(
            duplicates("struct pose { double x; double y, x; };\n"),
            ["3:35 `x` + 3:22 `x`: the field `x` is defined twice"]
        );
        no_duplicate("struct pose { double x; double y, z; };\n");
    }

    #[test]
    fn two_members_of_an_ids_block_but_not_of_two_blocks() {
        assert_eq!(
            duplicates("ids state {\n  double speed;\n  long speed;\n}\n"),
            ["5:8 `speed` + 4:10 `speed`: the ids member `state.speed` is defined twice"]
        );
        no_duplicate("ids state { double speed; }\nids limits { double speed; }\n");
    }

    #[test]
    fn two_data_blocks() {
        assert_eq!(
            duplicates("ids state { double speed; }\nexport state { double pos; }\n"),
            ["4:8 `state` + 3:5 `state`: the data block `state` is defined twice"]
        );
    }

    #[test]
    fn two_export_items_even_in_two_blocks() {
        assert_eq!(
            duplicates("export a { double pos; }\nexport b { long pos; }\n"),
            ["4:17 `pos` + 3:19 `pos`: the export item `pos` is defined twice"]
        );
        no_duplicate("export a { double pos; }\nimport b { double pos; }\n");
    }

    #[test]
    fn two_parameters_of_one_direction() {
        let body = "ids state { double speed; }\nservice s {\n  input: double speed, state.speed;\n  output: double a, double a;\n}\n";
        assert_eq!(
            duplicates(body),
            [
                "5:30 `speed` + 5:17 `speed`: the input parameter `speed` is defined twice",
                "6:28 `a` + 6:18 `a`: the output parameter `a` is defined twice",
            ]
        );
        no_duplicate(
            "ids state { double speed; }\nservice s { input: state.speed; output: state.speed; }\n",
        );
    }

    #[test]
    fn two_credential_classes() {
        let src = "component t { lang: C; credentials: none < user < admin < user; }\n";
        assert_eq!(
            found(src, Code::DuplicateDefinition),
            ["1:59 `user` + 1:44 `user`: the credential class `user` is defined twice"]
        );
    }

    #[test]
    fn a_field_initialised_twice() {
        let body = "struct pose { double x; double y; };\nids state { pose p := { x := 1.0, x := 2.0 }; }\n";
        assert_eq!(
            duplicates(body),
            ["4:35 `x` + 4:25 `x`: the field initialiser `x` is defined twice"]
        );
    }

    #[test]
    fn snapshot() {
        let src = format!(
            "{HEADER}service move {{ doc: \"first\"; }}\nthread control {{ period: 1s; }}\nservice move {{ doc: \"second\"; }}\n"
        );
        insta::assert_snapshot!(testing::render(&src));
    }
}
