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
        "genom3-frontend/tests/fixtures/valid/demo.gen",
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

/// `--format sarif` on a deadlock: one result per diagnostic with its rule,
/// level and region, the trace as a code flow of as many steps, and rules
/// listed once each with their `explain` text.
#[test]
fn sarif_carries_every_diagnostic_its_rule_and_its_trace() {
    let file = "tests/fixtures/invalid/deadlock.circular-delays.gen";
    let (status, sarif) = genom_check(&["--format", "sarif", file]);
    assert_eq!(status, 1);
    let (_, json) = genom_check(&["--format", "json", file]);
    let log: serde_json::Value = serde_json::from_str(&sarif).expect("SARIF is JSON");
    let doc: serde_json::Value = serde_json::from_str(&json).expect("JSON");
    assert_eq!(log["version"], "2.1.0");
    let run = &log["runs"][0];
    let results = run["results"].as_array().expect("results");
    let diagnostics = doc["files"][0]["diagnostics"]
        .as_array()
        .expect("diagnostics");
    assert_eq!(results.len(), diagnostics.len());
    for (r, d) in results.iter().zip(diagnostics) {
        assert_eq!(r["ruleId"], d["code"]);
        let region = &r["locations"][0]["physicalLocation"]["region"];
        assert_eq!(
            (&region["startLine"], &region["startColumn"]),
            (&d["line"], &d["column"])
        );
        let rule =
            &run["tool"]["driver"]["rules"][r["ruleIndex"].as_u64().expect("index") as usize];
        assert_eq!(rule["id"], d["code"]);
        assert!(
            rule["help"]["text"]
                .as_str()
                .is_some_and(|t| t.contains("# `"))
        );
    }
    let deadlock = results
        .iter()
        .find(|r| r["ruleId"] == "deadlock")
        .expect("a deadlock");
    assert_eq!(deadlock["level"], "error");
    let flow = deadlock["codeFlows"][0]["threadFlows"][0]["locations"]
        .as_array()
        .expect("flow");
    let trace = diagnostics
        .iter()
        .find(|d| d["code"] == "deadlock")
        .expect("deadlock")["trace"]
        .as_array()
        .expect("trace")
        .len();
    assert_eq!(flow.len(), trace);
}

/// The SARIF log validates against the official SARIF 2.1.0 schema (OASIS
/// `sarif-schema-2.1.0.json`, given by `SARIF_SCHEMA` when the tests are
/// built), on a deadlock with its trace, errors with related labels, and a
/// clean file.
#[test]
#[cfg_attr(
    not(genom_sarif_schema),
    ignore = "needs SARIF_SCHEMA=path/to/sarif-schema-2.1.0.json when the tests are built"
)]
fn sarif_validates_against_the_sarif_2_1_0_schema() {
    let path = std::env::var("SARIF_SCHEMA").expect("SARIF_SCHEMA");
    let schema: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).expect("schema")).expect("JSON");
    let validator = jsonschema::validator_for(&schema).expect("a valid schema");
    for file in [
        "tests/fixtures/invalid/deadlock.circular-delays.gen",
        "tests/fixtures/invalid/duplicate-definition.two-services.gen",
        "specs/pilot.gen",
    ] {
        let (_, sarif) = genom_check(&["--format", "sarif", file]);
        let log: serde_json::Value = serde_json::from_str(&sarif).expect("JSON");
        let errors: Vec<String> = validator.iter_errors(&log).map(|e| e.to_string()).collect();
        assert!(errors.is_empty(), "{file}: {errors:#?}");
    }
    // The validator does reject what the schema forbids.
    let (_, sarif) = genom_check(&["--format", "sarif", "specs/pilot.gen"]);
    let mut log: serde_json::Value = serde_json::from_str(&sarif).expect("JSON");
    log["runs"][0]["results"][0]["level"] = "fatal".into();
    assert!(!validator.is_valid(&log));
}
