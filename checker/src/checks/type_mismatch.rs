//! Tests of the `type_mismatch` diagnostics, which the front-end raises while
//! resolving (`gen_frontend::checks::type_mismatch`), through the whole check.

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

    const TYPES: &str = "module geo {\n  enum mode { RUN, STOP };\n  typedef struct pose { double x; double y; } pose;\n};\n\
                         typedef geo::mode mode_t;\ntypedef double meters;\nconst long N = 3;\n";

    /// `TYPES` (lines 3-9), then `member` alone in an ids block on line 10.
    fn member(member: &str) -> Vec<String> {
        found(
            &format!("{HEADER}{TYPES}ids d {{ {member}; }}\n"),
            Code::TypeMismatch,
        )
    }

    fn fits(member: &str) {
        let src = format!("{HEADER}{TYPES}ids d {{ {member}; }}\n");
        assert!(testing::codes(&src).is_empty(), "{}", testing::render(&src));
    }

    #[test]
    fn a_string_for_a_double() {
        assert_eq!(
            member("double speed := \"fast\""),
            ["10:25 `\"fast\"`: expected a value of type `double`, found `\"fast\"`"]
        );
        fits("double speed := 1.5");
        fits("double speed := 2");
        fits("double speed := -1.5e-3");
    }

    #[test]
    fn a_float_for_a_long_and_a_number_for_a_boolean() {
        assert_eq!(
            member("long count := 1.5"),
            ["10:23 `1.5`: expected a value of type `long`, found `1.5`"]
        );
        assert_eq!(
            member("boolean on := 1"),
            ["10:23 `1`: expected a value of type `boolean`, found `1`"]
        );
        fits("long count := -15");
        fits("boolean on := TRUE");
        fits("boolean on := false");
    }

    #[test]
    fn integers_out_of_range() {
        assert_eq!(
            member("octet level := 256"),
            ["10:24 `256`: `256` is out of range for `octet`"]
        );
        assert_eq!(
            member("short s := -32769"),
            ["10:20 `-32769`: `-32769` is out of range for `short`"]
        );
        assert_eq!(
            member("unsigned long u := -1"),
            ["10:28 `-1`: `-1` is out of range for `unsigned long`"]
        );
        let r = testing::check(&format!("{HEADER}{TYPES}ids d {{ octet level := 256; }}\n"));
        assert_eq!(
            r.diagnostics[0].help.as_deref(),
            Some("`octet` holds values from 0 to 255")
        );
        fits("octet level := 255");
        fits("short s := -32768");
        fits("unsigned long u := 4294967295");
        fits("unsigned long long big := 0xFFFFFFFFFFFFFFFF");
    }

    #[test]
    fn an_integer_too_large_for_any_type_is_quoted_as_written() {
        let digits = format!("1{}", "0".repeat(99));
        assert_eq!(
            member(&format!("long x := {digits}")),
            [format!(
                "10:19 `{digits}`: `{digits}` is out of range for `long`"
            )]
        );
    }

    #[test]
    fn floating_point_values_out_of_range() {
        assert_eq!(
            member("double y := 1e999"),
            ["10:21 `1e999`: `1e999` is out of range for `double`"]
        );
        assert_eq!(
            member("float f := 1e300"),
            ["10:20 `1e300`: `1e300` is out of range for `float`"]
        );
        assert_eq!(
            member("float f := -4e38"),
            ["10:20 `-4e38`: `-4e38` is out of range for `float`"]
        );
        let r = testing::check(&format!("{HEADER}{TYPES}ids d {{ float f := 1e300; }}\n"));
        assert_eq!(
            r.diagnostics[0].help.as_deref(),
            Some("`float` holds finite values of magnitude up to 3.4028234663852886e38")
        );
        fits("double y := 1e300");
        fits("float f := 3.4e38");
        fits("float f := -3.4e38");
        fits("double y := 1e-999");
    }

    #[test]
    fn a_string_longer_than_its_bound() {
        assert_eq!(
            member("string<4> name := \"hello\""),
            ["10:27 `\"hello\"`: 5 characters do not fit in `string<4>` (at most 4)"]
        );
        fits("string<5> name := \"hello\"");
        fits("string name := \"as long as one likes\"");
    }

    #[test]
    fn an_array_or_sequence_literal_too_long() {
        assert_eq!(
            member("double gains[2] := { 1.0, 2.0, 3.0 }"),
            ["10:28 `{ 1.0, 2.0, 3.0 }`: 3 elements do not fit in `double[2]` (at most 2)"]
        );
        assert_eq!(
            member("sequence<long, 2> ids := { 1, 2, 3 }"),
            ["10:34 `{ 1, 2, 3 }`: 3 elements do not fit in `sequence<long, 2>` (at most 2)"]
        );
        fits("double gains[N] := { 1.0, 2.0, N }");
        fits("double gains[2] := { 1.0 }");
        fits("sequence<long> ids := { 1, 2, 3, 4, 5 }");
    }

    #[test]
    fn a_struct_initialiser_naming_an_unknown_field() {
        assert_eq!(
            member("geo::pose p := { x := 1.0, z := 2.0 }"),
            ["10:36 `z`: `geo::pose` has no field `z`"]
        );
        let r = testing::check(&format!(
            "{HEADER}{TYPES}ids d {{ geo::pose p := {{ xx := 1.0 }}; }}\n"
        ));
        assert_eq!(r.diagnostics[0].help.as_deref(), Some("did you mean `x`?"));
        fits("geo::pose p := { x := 1.0 }");
        fits("geo::pose p := {}");
        fits("geo::pose p[2] := { {}, { y := 1.0 } }");
        fits("double gains[2] := {}");
        fits("geo::pose p { y := 2.0; }");
    }

    #[test]
    fn a_composite_for_a_scalar_and_a_scalar_for_a_struct() {
        assert_eq!(
            member("double speed := { 1.0 }"),
            ["10:25 `{ 1.0 }`: expected a value of type `double`, found a list of values"]
        );
        assert_eq!(
            member("geo::pose p := 1.0"),
            ["10:24 `1.0`: expected a value of type `geo::pose`, found `1.0`"]
        );
    }

    #[test]
    fn a_wrong_enum_value() {
        assert_eq!(
            member("geo::mode m := WALK"),
            ["10:24 `WALK`: `WALK` is not a value of `geo::mode`"]
        );
        let r = testing::check(&format!(
            "{HEADER}{TYPES}ids d {{ geo::mode m := WALK; }}\n"
        ));
        assert_eq!(
            r.diagnostics[0].help.as_deref(),
            Some("`geo::mode` has `RUN`, `STOP`")
        );
    }

    #[test]
    fn enum_values_qualified_or_not_and_through_an_alias() {
        fits("geo::mode m := RUN");
        fits("geo::mode m := geo::RUN");
        fits("geo::mode m := ::geo::STOP");
        fits("mode_t m := STOP");
        fits("mode_t m := geo::STOP");
    }

    #[test]
    fn an_unqualified_value_is_looked_up_in_its_own_enum_first() {
        // `RUN` is also a value of the top-level enum `gait`; initialising a
        // `geo::mode` it means `geo::RUN`.
        let src = format!(
            "{HEADER}{TYPES}enum gait {{ WALK, RUN }};\nids d {{ geo::mode m := RUN; gait g := RUN; }}\n"
        );
        assert!(testing::codes(&src).is_empty(), "{}", testing::render(&src));
        let qualified =
            format!("{HEADER}{TYPES}enum gait {{ WALK, RUN }};\nids d {{ gait g := geo::RUN; }}\n");
        assert_eq!(
            found(&qualified, Code::TypeMismatch),
            ["11:19 `geo::RUN`: `geo::RUN` is not a value of `gait`"]
        );
    }

    #[test]
    fn typedef_aliases_take_the_values_of_their_type() {
        fits("meters distance := 1.5");
        assert_eq!(
            member("meters distance := TRUE"),
            ["10:28 `TRUE`: expected a value of type `meters`, found `true`"]
        );
    }

    #[test]
    fn constants_are_values() {
        fits("long count := N");
        fits("octet small := N");
        let src =
            format!("{HEADER}{TYPES}const long BIG = N * 100;\nids d {{ octet small := BIG; }}\n");
        assert_eq!(
            found(&src, Code::TypeMismatch),
            ["11:24 `BIG`: `300` is out of range for `octet`"]
        );
    }

    #[test]
    fn an_array_bound_must_be_a_positive_integer_constant() {
        let src =
            format!("{HEADER}const double HALF = 0.5;\nids d {{ double a[HALF]; double b[0]; }}\n");
        assert_eq!(
            found(&src, Code::TypeMismatch),
            [
                "4:18 `HALF`: expected a value of type `positive integer constant`, found `0.5`",
                "4:34 `0`: expected a value of type `positive integer constant`, found `0`",
            ]
        );
    }

    const ITEMS: &str = "typedef struct state_t { double x; } state_t;\ntypedef state_t alias_t;\n\
                         export out { state_t state; }\nimport in { double target; }\n";

    #[test]
    fn a_service_import_or_export_declared_with_another_type() {
        let src = format!(
            "{HEADER}{ITEMS}service s {{\n  export: double state;\n  import: state_t target;\n}}\n"
        );
        assert_eq!(
            found(&src, Code::TypeMismatch),
            [
                "8:11 `double` + 5:22 `state`: `state` is declared `double` here but the data item is `state_t`",
                "9:11 `state_t` + 6:20 `target`: `target` is declared `state_t` here but the data item is `double`",
            ]
        );
        let ok = format!(
            "{HEADER}{ITEMS}service s {{\n  export: alias_t state;\n  import: double target;\n}}\n"
        );
        assert!(testing::codes(&ok).is_empty(), "{}", testing::render(&ok));
    }

    #[test]
    fn snapshot() {
        let src = format!(
            "{HEADER}{TYPES}ids d {{\n  octet level := 300;\n  geo::pose p {{ x := 1.0; z := 2.0; }}\n  geo::mode m := WALK;\n}}\n"
        );
        insta::assert_snapshot!(testing::render(&src));
    }
}
