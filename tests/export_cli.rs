//! `genom-check export`: refusal of unverified components (exit 1 with the
//! diagnostics, nothing written), `--allow-unverified`, `-o` with companion
//! files, usage errors (exit 2), determinism, and the JSON report of a
//! refused export (docs/exports.md).

#![allow(clippy::expect_used)] // test support code outside #[test] functions

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use genom_check::CheckOptions;
use genom_export::{ExportInput, Exported, Format, Verification};
use genom_parser::FsLoader;
use predicates::prelude::*;
use serde_json::Value;

const PILOT: &str = "specs/pilot.gen";
const DEADLOCK: &str = "tests/fixtures/invalid/deadlock.circular-delays.gen";
const SYNTAX: &str = "tests/fixtures/invalid/syntax.several-errors.gen";

fn genom_check() -> Command {
    let mut cmd = Command::cargo_bin("genom-check").expect("binary is built");
    cmd.env_remove("NO_COLOR").env("TERM", "xterm");
    cmd
}

/// Runs the command and returns (exit status, stdout, stderr).
fn run(args: &[&str]) -> (i32, String, String) {
    let out = genom_check().args(args).output().expect("runs");
    (
        out.status.code().expect("exit status"),
        String::from_utf8(out.stdout).expect("UTF-8 stdout"),
        String::from_utf8(out.stderr).expect("UTF-8 stderr"),
    )
}

/// A human report without its summary line (which carries the check's
/// duration) and the `explain` hint after it.
fn without_summary(report: &str) -> &str {
    let mut trimmed = report.trim_end_matches('\n');
    if let Some((body, last)) = trimmed.rsplit_once('\n') {
        if last.starts_with("For more information") {
            trimmed = body;
        }
    }
    trimmed.rsplit_once('\n').map_or("", |(body, _)| body)
}

/// What the library exports for `path`, verified as the CLI verifies it.
fn library_export(format: Format, path: &str) -> Result<Exported, genom_export::ExportError> {
    let result = genom_check::check_file(Path::new(path), &FsLoader, &CheckOptions::new())
        .expect("readable");
    let verification = Verification::of(
        result.component.as_ref(),
        &result.diagnostics,
        result.statistics.as_ref(),
        env!("CARGO_PKG_VERSION"),
    );
    let input = ExportInput {
        component: result.component.as_ref().expect("a component"),
        sources: &result.sources,
        verification: &verification,
    };
    genom_export::export(format, &input)
}

/// Where the CLI writes a companion file: `model.xml` + `.q` → `model.q`.
fn companion(path: &Path, suffix: &str) -> PathBuf {
    path.with_extension(suffix.trim_start_matches('.'))
}

#[test]
fn a_component_with_errors_is_refused_with_the_diagnostics_and_nothing_written() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("gripper.json");
    let out_arg = out.to_str().expect("UTF-8 path");
    let (code, stdout, stderr) = run(&["export", "config", DEADLOCK, "-o", out_arg]);
    assert_eq!(code, 1, "{stderr}");
    let (check_code, check_stdout, _) = run(&["check", DEADLOCK]);
    assert_eq!(check_code, 1);
    assert!(stdout.contains("deadlock"), "{stdout}");
    assert_eq!(without_summary(&stdout), without_summary(&check_stdout));
    assert!(
        stdout.contains(&format!("{DEADLOCK}: 1 error")),
        "the summary is printed: {stdout}"
    );
    assert_eq!(
        stderr,
        format!(
            "error: refusing to export `{DEADLOCK}`: 1 error (deadlock) \
             (use --allow-unverified to export it marked unverified)\n"
        )
    );
    assert!(!out.exists(), "nothing is written");
    assert_eq!(std::fs::read_dir(dir.path()).expect("dir").count(), 0);
}

#[test]
fn every_format_refuses_an_unverified_component() {
    for format in Format::ALL {
        let (code, stdout, stderr) = run(&["export", format.name(), DEADLOCK]);
        assert_eq!(code, 1, "{}: {stderr}", format.name());
        assert!(stderr.starts_with("error: refusing to export"), "{stderr}");
        assert!(!stdout.contains("<?xml") && !stdout.contains("\"format\""));
    }
}

#[test]
fn an_incomplete_check_is_refused() {
    // `--engine explicit`: by default the symbolic engine would finish
    // what the state limit stopped.
    let args = [
        "export",
        "config",
        PILOT,
        "--max-states",
        "2",
        "--engine",
        "explicit",
    ];
    let (code, stdout, stderr) = run(&args);
    assert_eq!(code, 1);
    assert!(stdout.contains("incomplete"), "{stdout}");
    assert!(
        stderr.contains("refusing to export `specs/pilot.gen`: 1 error (incomplete) ("),
        "{stderr}"
    );
}

#[test]
fn deny_warnings_refuses_a_component_with_warnings() {
    const WARNED: &str = "tests/fixtures/invalid/unreachable-codel.orphan-codel.gen";
    let (code, stdout, _) = run(&["export", "config", WARNED]);
    assert_eq!(code, 0, "a warning alone does not refuse");
    let doc: Value = serde_json::from_str(&stdout).expect("JSON");
    assert_eq!(doc["verified"], Value::Bool(true));
    let (code, stdout, stderr) = run(&["export", "--deny", "warnings", "config", WARNED]);
    assert_eq!(code, 1);
    assert!(stdout.contains("unreachable-codel"), "{stdout}");
    assert!(
        stderr.contains("1 warning (denied by --deny warnings)"),
        "{stderr}"
    );
    let (code, stdout, stderr) = run(&[
        "export",
        "--deny",
        "warnings",
        "--allow-unverified",
        "config",
        WARNED,
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("warning: exporting"), "{stderr}");
    let doc: Value = serde_json::from_str(&stdout).expect("JSON");
    assert_eq!(doc["verified"], Value::Bool(true), "no error: verified");
}

#[test]
fn allow_unverified_writes_an_export_marked_unverified() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("gripper.json");
    let out_arg = out.to_str().expect("UTF-8 path");
    let (code, stdout, stderr) = run(&[
        "export",
        "config",
        DEADLOCK,
        "--allow-unverified",
        "-o",
        out_arg,
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(stdout, "", "the report goes to stderr");
    assert!(stderr.contains("deadlock"), "the diagnostics: {stderr}");
    assert!(
        stderr.contains(&format!(
            "warning: exporting `{DEADLOCK}` unverified: 1 error (deadlock)"
        )),
        "{stderr}"
    );
    let doc: Value =
        serde_json::from_str(&std::fs::read_to_string(&out).expect("written")).expect("JSON");
    assert_eq!(doc["verified"], Value::Bool(false));
    assert_eq!(
        doc["verification"]["error_codes"],
        serde_json::json!(["deadlock"])
    );
    assert_eq!(doc["verification"]["properties"], serde_json::json!([]));
}

#[test]
fn allow_unverified_on_stdout_keeps_stdout_the_export() {
    let (code, stdout, stderr) = run(&["export", "config", DEADLOCK, "--allow-unverified"]);
    assert_eq!(code, 0, "{stderr}");
    let doc: Value = serde_json::from_str(&stdout).expect("stdout is only the JSON export");
    assert_eq!(doc["verified"], Value::Bool(false));
    assert!(stderr.contains("warning: exporting"), "{stderr}");
}

#[test]
fn a_file_without_component_is_refused_even_with_allow_unverified() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("x.json");
    let out_arg = out.to_str().expect("UTF-8 path");
    let (code, stdout, stderr) = run(&[
        "export",
        "config",
        SYNTAX,
        "--allow-unverified",
        "-o",
        out_arg,
    ]);
    assert_eq!(code, 1);
    assert!(stdout.contains("× expected"), "{stdout}");
    assert_eq!(
        stderr,
        format!("error: `{SYNTAX}` has no component to export\n")
    );
    assert!(!out.exists());
}

#[test]
fn a_verified_export_prints_only_its_verdict_on_stderr() {
    let (code, stdout, stderr) = run(&["export", "config", PILOT]);
    assert_eq!(code, 0);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with(&format!("{PILOT}: 0 errors, 0 warnings")),
        "{stderr}"
    );
    let doc: Value = serde_json::from_str(&stdout).expect("JSON");
    assert_eq!(doc["verified"], Value::Bool(true));
    assert_eq!(doc["verification"]["source"]["path"], PILOT);
}

/// Every format: `-o` writes the library's output and its companion files
/// byte for byte, stdout gives the same main output; a format that cannot
/// export the component fails with exit 1 and writes nothing.
#[test]
fn every_format_writes_what_the_library_exports() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut written = Vec::new();
    for format in Format::ALL {
        let path = dir.path().join(format!("pilot.{}", format.extension()));
        let path_arg = path.to_str().expect("UTF-8 path");
        let (code, _, stderr) = run(&["export", format.name(), PILOT, "-o", path_arg]);
        match library_export(format, PILOT) {
            Ok(expected) => {
                assert_eq!(code, 0, "{}: {stderr}", format.name());
                let said = format!("wrote `{}`", path.display());
                assert!(stderr.starts_with(&said), "{}: {stderr}", format.name());
                let main = std::fs::read_to_string(&path).expect("main file written");
                assert!(main == expected.main, "{}: -o differs", format.name());
                for (suffix, text) in &expected.extra {
                    let other = companion(&path, suffix);
                    let got = std::fs::read_to_string(&other)
                        .unwrap_or_else(|e| panic!("{}: {}: {e}", format.name(), other.display()));
                    assert!(&got == text, "{}: {suffix} differs", format.name());
                }
                let (code, stdout, _) = run(&["export", format.name(), PILOT]);
                assert_eq!(code, 0);
                assert!(stdout == expected.main, "{}: stdout differs", format.name());
                written.push(format);
            }
            Err(e) => {
                assert_eq!(code, 1, "{}: {stderr}", format.name());
                assert_eq!(stderr, format!("error: {e}\n"));
                assert!(!path.exists(), "{}: nothing written", format.name());
            }
        }
    }
    assert!(written.contains(&Format::Config), "{written:?}");
    assert!(written.contains(&Format::Dot), "{written:?}");
}

#[test]
fn uppaal_writes_its_query_file_next_to_the_model() {
    let Ok(expected) = library_export(Format::Uppaal, PILOT) else {
        return; // not implemented in this build: covered by the loop above
    };
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("pilot.xml");
    let (code, _, stderr) = run(&[
        "export",
        "uppaal",
        PILOT,
        "-o",
        path.to_str().expect("UTF-8 path"),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let queries = std::fs::read_to_string(dir.path().join("pilot.q")).expect("pilot.q written");
    assert_eq!(expected.extra, vec![(".q".to_owned(), queries)]);
}

#[test]
fn an_unknown_format_is_a_usage_error() {
    genom_check()
        .args(["export", "graphml", PILOT])
        .assert()
        .code(2)
        .stdout("")
        .stderr(predicate::str::contains("invalid value 'graphml'"))
        .stderr(predicate::str::contains("config"));
}

#[test]
fn a_missing_file_is_a_usage_error() {
    genom_check()
        .args(["export", "config", "does/not/exist.gen"])
        .assert()
        .code(2)
        .stdout("")
        .stderr(predicate::str::diff(
            "error: cannot read `does/not/exist.gen`: no such file\n",
        ));
}

#[test]
fn an_unwritable_output_is_a_usage_error() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("no/such/dir/pilot.json");
    let (code, stdout, stderr) = run(&[
        "export",
        "config",
        PILOT,
        "-o",
        out.to_str().expect("UTF-8 path"),
    ]);
    assert_eq!(code, 2);
    assert_eq!(stdout, "");
    assert!(stderr.starts_with("error: cannot write"), "{stderr}");
}

/// Files by name with their bytes.
type Files = Vec<(String, Vec<u8>)>;

/// Every file of `dir`, sorted by name, with its bytes.
fn files_of(dir: &Path) -> Files {
    let mut out: Files = std::fs::read_dir(dir)
        .expect("dir")
        .map(|e| {
            let path = e.expect("entry").path();
            let name = path
                .file_name()
                .expect("name")
                .to_string_lossy()
                .into_owned();
            (name, std::fs::read(&path).expect("readable"))
        })
        .collect();
    out.sort();
    out
}

#[test]
fn two_runs_give_byte_identical_output() {
    for file in [PILOT, "specs/battery.gen"] {
        for format in Format::ALL {
            let runs: Vec<(Option<i32>, Files)> = (0..2)
                .map(|_| {
                    let dir = tempfile::tempdir().expect("temp dir");
                    let path = dir.path().join(format!("model.{}", format.extension()));
                    let out = genom_check()
                        .args(["export", format.name(), file, "-o"])
                        .arg(&path)
                        .output()
                        .expect("runs");
                    (out.status.code(), files_of(dir.path()))
                })
                .collect();
            assert_eq!(runs[0].0, Some(0), "{} {file}", format.name());
            assert!(!runs[0].1.is_empty());
            assert!(
                runs[0] == runs[1],
                "{} {file}: two runs differ",
                format.name()
            );
        }
    }
}

/// The JSON report with the durations removed.
fn without_times(mut doc: Value) -> Value {
    doc["summary"]["time_ms"] = Value::Null;
    for file in doc["files"].as_array_mut().expect("files") {
        if file["statistics"].is_object() {
            file["statistics"]["time_ms"] = Value::Null;
        }
    }
    doc
}

#[test]
fn a_refused_export_prints_the_json_report_with_format_json() {
    let (code, stdout, stderr) = run(&["export", "--format", "json", "config", DEADLOCK]);
    assert_eq!(code, 1);
    assert!(stderr.starts_with("error: refusing to export"), "{stderr}");
    let doc: Value = serde_json::from_str(&stdout).expect("stdout is one JSON document");
    assert_eq!(doc["version"], 1);
    let diagnostics = doc["files"][0]["diagnostics"].as_array().expect("list");
    let deadlock = diagnostics
        .iter()
        .find(|d| d["code"] == "deadlock")
        .expect("the deadlock diagnostic");
    assert_eq!(deadlock["severity"], "error");
    assert!(deadlock["trace"].as_array().is_some_and(|t| !t.is_empty()));
    let (_, check_stdout, _) = run(&["check", "--format", "json", DEADLOCK]);
    let check: Value = serde_json::from_str(&check_stdout).expect("JSON");
    assert_eq!(without_times(doc), without_times(check));
}

#[test]
fn the_documented_pilot_config_is_the_current_output() {
    let docs = std::fs::read_to_string("docs/exports.md").expect("docs/exports.md");
    let (_, after) = docs
        .split_once("<!-- pilot-config -->\n```json\n")
        .expect("the marked example");
    let (example, _) = after.split_once("\n```").expect("closed block");
    let (code, stdout, _) = run(&["export", "config", PILOT]);
    assert_eq!(code, 0);
    let mut documented: Value = serde_json::from_str(example).expect("the example is JSON");
    documented["verification"]["tool_version"] = env!("CARGO_PKG_VERSION").into();
    let current: Value = serde_json::from_str(&stdout).expect("JSON");
    assert!(
        documented == current,
        "docs/exports.md: regenerate the example with `genom-check export config specs/pilot.gen`"
    );
}

/// The formats that record the verification verdict in their output, and
/// how an unverified export says so. (`uppaal`, `tchecker`, `promela`,
/// `dot` and `svg` do not record it yet: add them here when they do.)
const MARKS: [(&str, &str); 9] = [
    ("config", "\"verified\": false"),
    ("fiacre", "NOT verified"),
    ("tina", "NOT verified"),
    ("pnml", "verified=\"false\""),
    ("uppaal", "<!-- NOT verified"),
    ("tchecker", "# NOT verified"),
    ("dot", "// NOT verified"),
    ("svg", "<!-- NOT verified"),
    ("promela", "NOT verified"),
];

#[test]
fn unverified_exports_are_marked() {
    for (format, mark) in MARKS {
        let (code, stdout, _) = run(&["export", format, DEADLOCK, "--allow-unverified"]);
        assert_eq!(code, 0, "{format}");
        assert!(stdout.contains(mark), "{format}: no `{mark}`");
        let (code, stdout, _) = run(&["export", format, PILOT]);
        assert_eq!(code, 0, "{format}");
        assert!(
            !stdout.contains(mark),
            "{format}: a verified export is marked"
        );
    }
}
