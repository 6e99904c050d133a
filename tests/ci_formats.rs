//! Output for CI: `--format github` (GitHub Actions workflow commands,
//! one annotation per diagnostic, the file's summary and the grand total),
//! snapshotted on a clean spec, errors, a behavioural verdict with its
//! trace, an included file and a GenoM3 component; and the grand total of
//! human output over several files. Times in summaries are masked.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

use assert_cmd::Command;

fn genom_check(args: &[&str]) -> (i32, String) {
    let out = Command::cargo_bin("genom-check")
        .expect("binary is built")
        .env("NO_COLOR", "1")
        .env_remove("GENOM_INCLUDE_PATH")
        .args(args)
        .output()
        .expect("runs");
    let stdout = String::from_utf8(out.stdout).expect("UTF-8");
    (out.status.code().expect("exited"), stdout)
}

/// `genom-check --format github FILE`, snapshotted as `name`; returns the
/// exit status and the output.
fn github_snapshot(name: &str, file: &str) -> (i32, String) {
    let (status, out) = genom_check(&["--format", "github", file]);
    snapshot(name, &out);
    (status, out)
}

/// Snapshots `stdout` with the exploration times masked.
fn snapshot(name: &str, stdout: &str) {
    insta::with_settings!({filters => vec![(r"\d+\.\d ms", "[time] ms")]}, {
        insta::assert_snapshot!(name, stdout);
    });
}

#[test]
fn github_annotations_of_a_clean_spec_errors_and_a_verdict() {
    let (status, _) = github_snapshot("github_pilot", "specs/pilot.gen");
    assert_eq!(status, 0);

    let errors = "tests/fixtures/invalid/syntax.several-errors.gen";
    let (status, out) = github_snapshot("github_syntax_errors", errors);
    assert_eq!(status, 1);
    let annotations = out.lines().filter(|l| l.starts_with("::error ")).count();
    assert!(annotations > 1, "{out}");

    let deadlock = "tests/fixtures/invalid/deadlock.circular-delays.gen";
    let (status, out) = github_snapshot("github_deadlock_trace", deadlock);
    assert_eq!(status, 1);
    // The trace rides in the annotation's text, one step a line.
    assert!(out.contains("%0Atrace:%0A  1. "), "{out}");
}

#[test]
fn github_annotations_point_into_included_files_and_genom3_components() {
    let (status, out) = genom_check(&[
        "--format",
        "github",
        "tests/fixtures/invalid/syntax.in-included-file.gen",
    ]);
    assert_eq!(status, 1);
    assert!(
        out.starts_with("::error file=tests/fixtures/invalid/cycle/broken.idl,line=2,col=11,"),
        "{out}"
    );
    let (status, out) = genom_check(&[
        "--format",
        "github",
        "--static-only",
        "parser/genom3/tests/fixtures/valid/demo.gen",
    ]);
    assert_eq!(status, 0, "{out}");
    snapshot("github_genom3", &out);
}

#[test]
fn quiet_github_output_keeps_errors_and_warnings_only() {
    let (_, out) = genom_check(&["--format", "github", "--quiet", "specs/pilot.gen"]);
    assert_eq!(out, "", "advice and summaries are left out");
}

#[test]
fn several_files_end_with_the_grand_total() {
    let (status, out) = genom_check(&[
        "--static-only",
        "specs/pilot.gen",
        "tests/fixtures/invalid/syntax.several-errors.gen",
    ]);
    assert_eq!(status, 1);
    let last = out.lines().last().expect("a last line");
    assert!(
        last.starts_with("Found ") && last.ends_with(" advice in 2 files."),
        "{last}"
    );
    // One file alone: its summary line is the total.
    let (_, out) = genom_check(&["--static-only", "specs/pilot.gen"]);
    assert!(!out.contains("Found "), "{out}");
}
