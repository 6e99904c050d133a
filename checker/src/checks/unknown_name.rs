//! Tests of the `unknown_name` diagnostics, which the front-end raises while
//! resolving (`gen_frontend::checks::unknown_name`), through the whole check.

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

    /// The help of every diagnostic of `code` in `src`.
    fn helps(src: &str, code: Code) -> Vec<String> {
        let r = testing::check(src);
        r.diagnostics
            .iter()
            .filter(|d| d.code == code)
            .map(|d| d.help.clone().unwrap_or_default())
            .collect()
    }

    fn src(body: &str) -> String {
        format!("{HEADER}{body}")
    }

    fn none_of(body: &str, code: Code) {
        let src = src(body);
        assert_eq!(testing::count(&src, code), 0, "{}", testing::render(&src));
    }

    const TYPES: &str = "typedef struct DEMO_STATE_STR { double position; double speed; } DEMO_STATE_STR;\n\
                         module geo { typedef struct Pose { double x; double y; } Pose; struct Twist { Pose p; geo::Pose q; }; };\n";

    #[test]
    fn unknown_type_suggests_the_closest_name() {
        let s = src(&format!("{TYPES}ids state {{ DEMO_STATE state; }}\n"));
        assert_eq!(
            found(&s, Code::UnknownType),
            ["5:13 `DEMO_STATE`: unknown type `DEMO_STATE`"]
        );
        assert_eq!(
            helps(&s, Code::UnknownType),
            ["did you mean `DEMO_STATE_STR`?"]
        );
        none_of(
            &format!("{TYPES}ids state {{ DEMO_STATE_STR state; }}\n"),
            Code::UnknownType,
        );
    }

    #[test]
    fn a_module_type_resolves_from_inside_its_module_but_not_outside() {
        // `Pose` inside `geo` (in `Twist`) is fine; outside it must be
        // qualified, and the help names the qualified type.
        let s = src(&format!("{TYPES}ids state {{ Pose pose; }}\n"));
        assert_eq!(
            found(&s, Code::UnknownType),
            ["5:13 `Pose`: unknown type `Pose`"]
        );
        assert_eq!(helps(&s, Code::UnknownType), ["did you mean `geo::Pose`?"]);
        none_of(
            &format!("{TYPES}ids state {{ geo::Pose a; ::geo::Pose b; geo::Twist c; }}\n"),
            Code::UnknownType,
        );
    }

    #[test]
    fn an_absolute_name_does_not_look_into_modules() {
        let s = src("module geo { typedef long T; module inner { typedef ::T U; }; };\n");
        assert_eq!(
            found(&s, Code::UnknownType),
            ["3:53 `::T`: unknown type `::T`"]
        );
        assert_eq!(helps(&s, Code::UnknownType), ["did you mean `geo::T`?"]);
        none_of(
            "module geo { typedef long T; module inner { typedef T U; typedef ::geo::T V; }; };\n",
            Code::UnknownType,
        );
    }

    const DATA: &str = "typedef struct DEMO_STATE_STR { double position; double speed; } DEMO_STATE_STR;\n\
                        ids demoIds { double distRef; DEMO_STATE_STR state; double gains[3]; }\n\
                        export demoExport { DEMO_STATE_STR state; }\n";

    fn codel_args(args: &str) -> String {
        src(&format!(
            "{DATA}service move {{\n  input: double speed;\n  control codel {{ exec: check({args}); }}\n}}\n"
        ))
    }

    #[test]
    fn unknown_data_root_suggests_a_block_or_a_parameter() {
        let s = codel_args("demoIDs.distRef, sped");
        assert_eq!(
            found(&s, Code::UnknownData),
            [
                "8:31 `demoIDs`: unknown data `demoIDs`",
                "8:48 `sped`: unknown data `sped`",
            ]
        );
        assert_eq!(
            helps(&s, Code::UnknownData),
            ["did you mean `demoIds`?", "did you mean `speed`?"]
        );
        none_of(
            &codel_args("demoIds.distRef, speed")[HEADER.len()..],
            Code::UnknownData,
        );
    }

    #[test]
    fn unknown_field_suggests_the_closest_field() {
        let s = codel_args("demoIds.distRf, demoIds.state.posiion");
        assert_eq!(
            found(&s, Code::UnknownData),
            [
                "8:39 `distRf`: `demoIds` has no field `distRf`",
                "8:61 `posiion`: `DEMO_STATE_STR` has no field `posiion`",
            ]
        );
        assert_eq!(
            helps(&s, Code::UnknownData),
            ["did you mean `distRef`?", "did you mean `position`?"]
        );
        none_of(
            &codel_args("demoIds.distRef, demoIds.state.position")[HEADER.len()..],
            Code::UnknownData,
        );
    }

    #[test]
    fn a_field_of_a_scalar_is_unknown() {
        let s = codel_args("demoIds.distRef.value");
        assert_eq!(
            found(&s, Code::UnknownData),
            ["8:47 `value`: `double` has no field `value`"]
        );
        assert_eq!(helps(&s, Code::UnknownData), ["`double` has no fields"]);
    }

    #[test]
    fn bad_index_out_of_bounds_or_on_a_non_array() {
        let s = codel_args("demoIds.gains[3], demoIds.distRef[0]");
        assert_eq!(
            found(&s, Code::UnknownData),
            [
                "8:45 `3`: cannot index `double[3]` with [3]: the index must be below 3",
                "8:65 `0`: cannot index `double` with [0]: it is not an array or sequence",
            ]
        );
        none_of(
            &codel_args("demoIds.gains[2], demoIds.gains[0]")[HEADER.len()..],
            Code::UnknownData,
        );
    }

    #[test]
    fn an_export_block_without_item_or_with_an_unknown_item() {
        let s = codel_args("demoExport, demoExport.stat");
        assert_eq!(
            found(&s, Code::UnknownData),
            [
                "8:31 `demoExport`: `demoExport` is an export block, not a data item",
                "8:54 `stat`: unknown export item `demoExport.stat`",
            ]
        );
        assert_eq!(
            helps(&s, Code::UnknownData),
            [
                "name one of its items: `demoExport.state`",
                "did you mean `demoExport.state`?"
            ]
        );
        none_of(
            &codel_args("demoExport.state, demoExport.state.speed")[HEADER.len()..],
            Code::UnknownData,
        );
    }

    #[test]
    fn a_parameter_of_another_service_is_not_visible() {
        let body = format!(
            "{DATA}service other {{ input: double gain; }}\nservice move {{\n  control codel {{ exec: check(gain); }}\n}}\n"
        );
        let s = src(&body);
        assert_eq!(
            found(&s, Code::UnknownData),
            [
                "8:31 `gain` + 6:31 `gain`: `gain` is a parameter of service `other`, not of this service"
            ]
        );
        none_of(
            &format!(
                "{DATA}service other {{ input: double gain; }}\nservice move {{\n  input: double gain;\n  control codel {{ exec: check(gain); }}\n}}\n"
            ),
            Code::UnknownData,
        );
    }

    #[test]
    fn a_parameter_must_refer_into_an_ids_block() {
        let s = src(&format!(
            "{DATA}service move {{ input: demoExport.state; output: demoIds.distRef; }}\n"
        ));
        assert_eq!(
            found(&s, Code::UnknownData),
            ["6:23 `demoExport.state`: `demoExport.state` is not an ids member"]
        );
        assert_eq!(
            helps(&s, Code::UnknownData),
            ["declare it as `TYPE name`, or refer into an `ids` block (`demoIds`)"]
        );
    }

    #[test]
    fn a_service_import_or_export_names_an_item() {
        let s = src(&format!(
            "{DATA}service move {{ export: DEMO_STATE_STR stat; import: DEMO_STATE_STR state; }}\n"
        ));
        assert_eq!(
            found(&s, Code::UnknownData),
            [
                "6:39 `stat`: unknown export item `stat`",
                "6:68 `state`: unknown import item `state`",
            ]
        );
        assert_eq!(
            helps(&s, Code::UnknownData),
            ["did you mean `state`?", "no import item is declared here"]
        );
    }

    #[test]
    fn unknown_constant_in_a_value() {
        let s = src("const double MAX = 1.0;\nids limits { double speed := MAXX; }\n");
        assert_eq!(
            found(&s, Code::UnknownData),
            ["4:30 `MAXX`: unknown constant `MAXX`"]
        );
        assert_eq!(helps(&s, Code::UnknownData), ["did you mean `MAX`?"]);
        none_of(
            "const double MAX = 1.0;\nids limits { double speed := MAX; }\n",
            Code::UnknownData,
        );
    }

    #[test]
    fn unknown_thread() {
        let s = src("service move {\n  thread: mian;\n  start codel { exec: go(); }\n}\n");
        assert_eq!(
            found(&s, Code::UnknownThread),
            ["4:11 `mian`: unknown thread `mian`"]
        );
        assert_eq!(helps(&s, Code::UnknownThread), ["did you mean `main`?"]);
        none_of(
            "service move {\n  thread: main;\n  start codel { exec: go(); }\n}\n",
            Code::UnknownThread,
        );
    }

    #[test]
    fn unknown_service_in_stops_delays_and_forbids() {
        let s = src(
            "service move { stops: mvoe; delays: turn; forbids: halt; }\nservice turn { doc: \"\"; }\n",
        );
        assert_eq!(
            found(&s, Code::UnknownService),
            [
                "3:23 `mvoe`: unknown service `mvoe`",
                "3:52 `halt`: unknown service `halt`",
            ]
        );
        assert_eq!(
            helps(&s, Code::UnknownService),
            ["did you mean `move`?", "known services: `move`, `turn`"]
        );
        none_of(
            "service move { stops: move; delays: turn; forbids: turn; }\nservice turn { doc: \"\"; }\n",
            Code::UnknownService,
        );
    }

    const MOVE: &str = "service move {\n  thread: main;\n  report: TOO_FAR;\n";

    #[test]
    fn unknown_codel_in_next_suggests_a_codel_of_the_service() {
        let s = src(&format!(
            "{MOVE}  start codel {{ exec: go(); next: goto; }}\n  exec codel gotoo {{ exec: go(); next: TOO_FAR; }}\n}}\n"
        ));
        assert_eq!(
            found(&s, Code::UnknownCodel),
            ["6:35 `goto`: unknown codel `goto`"]
        );
        assert_eq!(helps(&s, Code::UnknownCodel), ["did you mean `gotoo`?"]);
        none_of(
            &format!(
                "{MOVE}  start codel {{ exec: go(); next: goto; }}\n  exec codel goto {{ exec: go(); next: TOO_FAR; }}\n}}\n"
            ),
            Code::UnknownCodel,
        );
    }

    #[test]
    fn unknown_inter_codel_in_on_inter() {
        let s = src(&format!(
            "{MOVE}  start codel {{ exec: go(); on-inter: stp; next: TOO_FAR; }}\n  inter codel stop {{ exec: halt(); }}\n}}\n"
        ));
        assert_eq!(
            found(&s, Code::UnknownCodel),
            ["6:39 `stp`: unknown inter codel `stp`"]
        );
        assert_eq!(helps(&s, Code::UnknownCodel), ["did you mean `stop`?"]);
        none_of(
            &format!(
                "{MOVE}  start codel {{ exec: go(); on-inter: stop; next: TOO_FAR; }}\n  inter codel stop {{ exec: halt(); }}\n}}\n"
            ),
            Code::UnknownCodel,
        );
    }

    #[test]
    fn unknown_report_in_next() {
        let s = src(&format!(
            "{MOVE}  start codel {{ exec: go(); next: TOO_FAR_AWAY; }}\n}}\n"
        ));
        assert_eq!(
            found(&s, Code::UnknownReport),
            ["6:35 `TOO_FAR_AWAY`: unknown report `TOO_FAR_AWAY`"]
        );
        assert_eq!(helps(&s, Code::UnknownReport), ["did you mean `TOO_FAR`?"]);
        none_of(
            &format!("{MOVE}  start codel {{ exec: go(); next: TOO_FAR; }}\n}}\n"),
            Code::UnknownReport,
        );
    }

    #[test]
    fn unknown_credential() {
        let s = "component t { lang: C; credentials: guest < operator < expert; }\n\
                 service move { credential: oprator; }\n";
        assert_eq!(
            found(s, Code::UnknownCredential),
            ["2:28 `oprator`: unknown credential `oprator`"]
        );
        assert_eq!(
            helps(s, Code::UnknownCredential),
            ["did you mean `operator`?"]
        );
        let default = "component t { lang: C; }\nservice move { credential: user; }\n";
        assert_eq!(testing::count(default, Code::UnknownCredential), 0);
        let not_default = "component t { lang: C; credentials: guest < expert; }\nservice move { credential: user; }\n";
        assert_eq!(testing::count(not_default, Code::UnknownCredential), 1);
    }

    #[test]
    fn snapshot() {
        let s = src(&format!(
            "{DATA}service move {{\n  thread: mian;\n  input: double speed;\n  start codel {{ exec: go(demoIds.distRf, sped); }}\n}}\n"
        ));
        insta::assert_snapshot!(testing::render(&s));
    }
}
