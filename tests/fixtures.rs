//! Snapshot tests over `tests/fixtures/{valid,invalid}/*.gen`: each
//! snapshot holds the fixture's source and the rendered report (colour off,
//! width 100). Valid fixtures must have no error and no warning; each invalid
//! fixture is named after the code it must produce (`CODE.what.gen`).

#![allow(clippy::expect_used)] // test support code outside #[test] functions

mod common;

use genom_model::Severity;

fn snapshot_text(path: &std::path::Path, report: &str) -> String {
    let source = std::fs::read_to_string(path).expect("fixture is readable");
    format!("{source}\n----- report -----\n{report}")
}

#[test]
fn valid_fixtures_have_no_errors_or_warnings() {
    insta::glob!("fixtures/valid/*.gen", |path| {
        let result = common::check(path);
        let report = common::render(path, &result);
        assert!(
            common::codes(&result, Severity::Warning).is_empty(),
            "{report}"
        );
        insta::assert_snapshot!(snapshot_text(path, &report));
    });
}

#[test]
fn invalid_fixtures_report_the_code_they_are_named_after() {
    insta::glob!("fixtures/invalid/*.gen", |path| {
        let result = common::check(path);
        let report = common::render(path, &result);
        let expected = common::expected_code(path);
        assert!(
            result.diagnostics.iter().any(|d| d.code == expected),
            "{} should report `{expected}`:\n{report}",
            path.display()
        );
        insta::assert_snapshot!(snapshot_text(path, &report));
    });
}

#[test]
fn every_file_in_specs_checks_clean() {
    insta::glob!("../specs", "*.gen", |path| {
        let result = common::check(path);
        let report = common::render(path, &result);
        assert!(
            common::codes(&result, Severity::Warning).is_empty(),
            "{report}"
        );
    });
}
