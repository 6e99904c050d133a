//! The static checks as a whole: every static code of the spec has a
//! fixture that produces it and a fenced example in its explanation, no
//! valid fixture or shipped spec produces one, and one run reports every
//! problem of a file, in source order.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

use crate::common;

use std::path::{Path, PathBuf};

use gen_frontend::GenFrontend;
use genom_check::CheckResult;
use genom_checker::checks::STATIC_CHECKS;
use genom_model::frontend::Frontend as _;
use genom_model::{Code, Severity, Span};

/// Every static code of LANGUAGE.md section 4: the resolution, structure
/// and type rules of the LANGUAGE.md front-end (the codes it explains, but
/// syntax and includes), then the codes of the checker's registered static
/// checks (`genom_checker::checks::STATIC_CHECKS`): a new check is here
/// once registered.
fn static_codes() -> Vec<Code> {
    let front = Code::ALL.iter().copied().filter(|&c| {
        GenFrontend.explanation(c).is_some()
            && !matches!(c, Code::Syntax | Code::IncludeNotFound | Code::IncludeCycle)
    });
    let checks = STATIC_CHECKS
        .iter()
        .flat_map(|c| c.codes.iter().map(|&(code, _)| code));
    front.chain(checks).collect()
}

/// Static codes without an invalid fixture: `recursive-type` is an IDL
/// type error, tested by its check's unit tests and
/// `tests/hostile/hostile.rs`.
const WITHOUT_FIXTURE: &[Code] = &[Code::RecursiveType];

/// The `.gen` files of a directory (relative to the workspace root), sorted.
fn gen_files(dir: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(common::root().join(dir))
        .expect("directory is readable")
        .map(|e| e.expect("directory entry is readable").path())
        .filter(|p| p.extension().is_some_and(|e| e == "gen"))
        .collect();
    files.sort();
    files
}

fn name(path: &Path) -> &str {
    path.file_name()
        .and_then(|n| n.to_str())
        .expect("file name is UTF-8")
}

/// 1-based line of a span's start.
fn line(result: &CheckResult, span: Span) -> usize {
    let located = result.sources.locate(span).expect("span is in a file");
    let file = result.sources.file(located.file).expect("file exists");
    file.line_col(located.offset).0
}

#[test]
fn every_static_code_has_a_fixture_that_produces_it() {
    let invalid = gen_files("tests/fixtures/invalid");
    let mut missing = Vec::new();
    for code in static_codes() {
        if WITHOUT_FIXTURE.contains(&code) {
            continue;
        }
        let prefix = format!("{code}.");
        let fixtures: Vec<&PathBuf> = invalid
            .iter()
            .filter(|p| name(p).starts_with(&prefix))
            .collect();
        if fixtures.is_empty() {
            missing.push(format!("no fixture named `{code}.*.gen`"));
        }
        for path in fixtures {
            let result = common::check(path);
            if !result.diagnostics.iter().any(|d| d.code == code) {
                let report = common::render(path, &result);
                missing.push(format!(
                    "{} does not report `{code}`:\n{report}",
                    name(path)
                ));
            }
        }
    }
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}

#[test]
fn valid_fixtures_and_specs_produce_no_static_diagnostic_but_advice() {
    let mut files = gen_files("tests/fixtures/valid");
    files.extend(gen_files("specs"));
    assert!(files.len() >= 10, "{files:?}");
    let codes = static_codes();
    let mut found = Vec::new();
    for path in &files {
        let result = common::check(path);
        let unexpected = result
            .diagnostics
            .iter()
            .any(|d| codes.contains(&d.code) && d.severity != Severity::Advice);
        if unexpected {
            found.push(common::render(path, &result));
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
}

#[test]
fn every_static_code_is_explained_with_an_example() {
    let unexplained: Vec<&str> = static_codes()
        .into_iter()
        .filter(|&code| {
            let text = genom_check::explain::explanation(code);
            text.matches("```").count() < 2
        })
        .map(Code::as_str)
        .collect();
    assert!(
        unexplained.is_empty(),
        "no fenced example in the explanation of {unexplained:?}"
    );
}

#[test]
fn many_problems_are_all_reported_in_one_run_in_source_order() {
    let path = common::root().join("tests/fixtures/invalid/unknown-data.many-problems.gen");
    let result = common::check(&path);
    let found: Vec<(Code, usize)> = result
        .diagnostics
        .iter()
        .map(|d| (d.code, line(&result, d.span())))
        .collect();
    assert_eq!(
        found,
        [
            (Code::TypeMismatch, 10),
            (Code::TypeMismatch, 11),
            (Code::UnknownType, 12),
            (Code::InvalidAttribute, 17),
            (Code::UnknownThread, 20),
            (Code::UnknownService, 22),
            (Code::UnknownCredential, 23),
            (Code::UnknownData, 25),
            (Code::UnknownCodel, 26),
            (Code::UnknownData, 29),
            (Code::UnknownReport, 30),
        ],
        "{}",
        common::render(&path, &result)
    );
    let starts: Vec<u32> = result.diagnostics.iter().map(|d| d.span().start).collect();
    assert!(starts.is_sorted(), "{starts:?}");
    let mut codes: Vec<Code> = found.iter().map(|&(c, _)| c).collect();
    codes.sort();
    codes.dedup();
    assert!(codes.len() >= 8, "{codes:?}");
}

#[test]
fn each_problem_of_the_many_is_labelled_with_its_text() {
    let path = common::root().join("tests/fixtures/invalid/unknown-data.many-problems.gen");
    let result = common::check(&path);
    let texts: Vec<&str> = result
        .diagnostics
        .iter()
        .map(|d| result.sources.slice(d.span()))
        .collect();
    assert_eq!(
        texts,
        [
            "\"zero\"",
            "256",
            "DEMO_STATE",
            "0ms",
            "motionTsk",
            "moveDistanse",
            "amdin",
            "distRf",
            "stp",
            "stat",
            "TOO_FAR",
        ]
    );
}
