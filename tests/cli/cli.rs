//! Command-line behaviour: exit statuses (LANGUAGE.md section 4), output
//! formats, options, and I/O problems that must give exit 2 without a panic.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

use assert_cmd::Command;
use predicates::prelude::*;
use serde_json::Value;

fn genom_check() -> Command {
    let mut cmd = Command::cargo_bin("genom-check").expect("binary is built");
    cmd.env_remove("NO_COLOR").env("TERM", "xterm");
    cmd
}

const INVALID: &str = "tests/fixtures/invalid/syntax.several-errors.gen";

#[test]
fn pilot_checks_clean_with_exit_zero_and_a_summary() {
    genom_check()
        .arg("specs/pilot.gen")
        .assert()
        .code(0)
        .stdout(predicate::str::contains(
            "specs/pilot.gen: 0 errors, 0 warnings",
        ));
}

#[test]
fn check_subcommand_is_the_default() {
    let plain = genom_check().arg(INVALID).output().unwrap();
    let explicit = genom_check().args(["check", INVALID]).output().unwrap();
    assert_eq!(plain.status.code(), Some(1));
    assert_eq!(plain.stdout, explicit.stdout);
    assert_eq!(explicit.status.code(), Some(1));
}

#[test]
fn errors_give_exit_one_and_every_error_is_reported() {
    let out = genom_check().arg(INVALID).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let text = String::from_utf8(out.stdout).unwrap();
    assert_eq!(text.matches("× expected").count(), 3, "{text}");
    assert!(text.contains(": 3 errors, 0 warnings, 0 advice"), "{text}");
}

#[test]
fn a_missing_file_is_exit_two_with_one_line() {
    genom_check()
        .arg("does/not/exist.gen")
        .assert()
        .code(2)
        .stderr(predicate::str::diff(
            "error: cannot read `does/not/exist.gen`: no such file\n",
        ));
}

#[test]
fn a_directory_is_exit_two() {
    genom_check()
        .arg("specs")
        .assert()
        .code(2)
        .stderr(predicate::str::contains("is a directory"));
}

#[test]
fn a_non_utf8_file_is_exit_two() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bytes.gen");
    std::fs::write(&path, [0x63, 0x6f, 0xff, 0xfe, 0x00, 0x80]).unwrap();
    genom_check()
        .arg(&path)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("not valid UTF-8"));
}

#[test]
fn one_unreadable_file_among_good_ones_still_reports_the_others() {
    let out = genom_check()
        .args(["specs/pilot.gen", "nope.gen"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stdout).contains("specs/pilot.gen: 0 errors"));
}

#[test]
fn a_megabyte_of_garbage_is_diagnosed_not_a_crash() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("garbage.gen");
    let line = "@@ }{ ;; service ::: 12ab \"x\" /* */ codel <<>> \n";
    std::fs::write(&path, line.repeat(1_000_000 / line.len())).unwrap();
    genom_check()
        .arg(&path)
        .assert()
        .code(1)
        .stdout(predicate::str::contains("syntax"));
}

#[test]
fn usage_errors_are_exit_two() {
    genom_check().assert().code(2);
    genom_check()
        .args(["--format", "xml", "specs/pilot.gen"])
        .assert()
        .code(2);
}

#[test]
fn json_output_has_the_documented_shape() {
    let out = genom_check()
        .args(["--format", "json", INVALID, "specs/pilot.gen"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let doc: Value = serde_json::from_slice(&out.stdout).expect("stdout is one JSON document");
    assert_eq!(doc["version"], 1);
    assert_eq!(doc["files"].as_array().map(Vec::len), Some(2));
    assert_eq!(doc["files"][1]["path"], "specs/pilot.gen");
    assert_eq!(
        doc["files"][1]["diagnostics"].as_array().map(Vec::len),
        Some(1)
    );
    assert_eq!(doc["files"][1]["diagnostics"][0]["code"], "missing-wcet");
    assert_eq!(doc["files"][1]["diagnostics"][0]["severity"], "advice");
    let first = &doc["files"][0]["diagnostics"][0];
    assert_eq!(first["code"], "syntax");
    assert_eq!(first["severity"], "error");
    assert_eq!(first["message"], "expected `;`, found `}`");
    assert_eq!(first["file"], INVALID);
    assert_eq!(
        (first["line"].as_u64(), first["column"].as_u64()),
        (Some(3), Some(28))
    );
    assert_eq!(first["span"]["length"], 1);
    assert_eq!(first["labels"][0]["line"], 3);
    assert!(first["help"].is_null() && first["trace"].is_null());
    assert_eq!(doc["summary"]["errors"], 3);
    assert_eq!(doc["summary"]["warnings"], 0);
    assert_eq!(doc["summary"]["advice"], 1);
}

#[test]
fn json_points_into_the_included_file() {
    let out = genom_check()
        .args([
            "--format",
            "json",
            "tests/fixtures/invalid/syntax.in-included-file.gen",
        ])
        .output()
        .unwrap();
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    let d = &doc["files"][0]["diagnostics"][0];
    assert_eq!(
        doc["files"][0]["path"],
        "tests/fixtures/invalid/syntax.in-included-file.gen"
    );
    assert_eq!(d["file"], "tests/fixtures/invalid/cycle/broken.idl");
    assert_eq!(
        (d["line"].as_u64(), d["column"].as_u64()),
        (Some(2), Some(11))
    );
}

#[test]
fn quiet_prints_no_summary() {
    genom_check()
        .args(["-q", "specs/pilot.gen"])
        .assert()
        .code(0)
        .stdout(predicate::str::is_empty());
    genom_check()
        .args(["--quiet", INVALID])
        .assert()
        .code(1)
        .stdout(
            predicate::str::contains("expected").and(predicate::str::contains("3 errors").not()),
        );
}

#[test]
fn deny_warnings_keeps_a_clean_file_at_zero() {
    genom_check()
        .args(["--deny", "warnings", "specs/pilot.gen"])
        .assert()
        .code(0);
    genom_check()
        .args(["--deny", "errors", "specs/pilot.gen"])
        .assert()
        .code(2);
}

#[test]
fn colour_follows_the_option_and_no_color() {
    let ansi = predicate::str::contains("\u{1b}[");
    genom_check()
        .args(["--color", "always", INVALID])
        .assert()
        .stdout(ansi.clone());
    genom_check()
        .args(["--color", "never", INVALID])
        .assert()
        .stdout(ansi.clone().not());
    // Not a terminal: `auto` means no colour.
    genom_check()
        .args(["--color", "auto", INVALID])
        .assert()
        .stdout(ansi.clone().not());
    genom_check()
        .env("NO_COLOR", "1")
        .arg(INVALID)
        .assert()
        .stdout(ansi.not());
}

#[test]
fn version_and_help() {
    genom_check()
        .arg("--version")
        .assert()
        .code(0)
        .stdout(predicate::str::starts_with(format!(
            "genom-check {}",
            env!("CARGO_PKG_VERSION")
        )));
    genom_check()
        .arg("--help")
        .assert()
        .code(0)
        .stdout(predicate::str::contains("Examples:"));
}

#[test]
fn explain_prints_the_code_and_rejects_unknown_ones() {
    genom_check()
        .args(["explain", "include-cycle"])
        .assert()
        .code(0)
        .stdout(predicate::str::starts_with("# `include-cycle` (error)"));
    genom_check()
        .args(["explain", "dedlock"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("did you mean `deadlock`?"));
}

#[test]
fn closed_stdout_is_not_a_crash() {
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("genom-check"))
        .arg(INVALID)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
    assert_eq!(out.status.code(), Some(1));
}

/// The lines `genom-check ARGS` prints on stdout.
fn stdout_lines(args: &[&str]) -> Vec<String> {
    let out = genom_check().args(args).output().unwrap();
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(str::to_owned)
        .collect()
}

#[test]
fn advice_takes_one_line_unless_verbose() {
    let short = stdout_lines(&["--color", "never", "specs/pilot.gen"]);
    let advice: Vec<&String> = short.iter().filter(|l| l.starts_with("☞ ")).collect();
    assert_eq!(advice.len(), 1, "{short:#?}");
    assert!(
        advice[0].starts_with("☞ missing-wcet: 4 codels without WCET")
            && advice[0].ends_with("(specs/pilot.gen:19:3)"),
        "{short:#?}"
    );
    assert!(
        short
            .iter()
            .any(|l| l.contains("`--verbose` shows it in full"))
    );
    let full = stdout_lines(&["--color", "never", "--verbose", "specs/pilot.gen"]);
    let text = full.join("\n");
    assert!(text.contains("`moveDistance::goto` has no WCET"), "{text}");
    assert!(text.contains("left unproven: overruns of thread `motionTask`"));
    assert!(!text.contains("`--verbose` shows it in full"));
    let quiet = stdout_lines(&["--quiet", "specs/pilot.gen"]);
    assert!(quiet.is_empty(), "{quiet:#?}");
    genom_check()
        .args(["--quiet", "--verbose", "specs/pilot.gen"])
        .assert()
        .code(2);
}

#[test]
fn a_clean_component_takes_a_few_lines() {
    let mut files: Vec<std::path::PathBuf> = std::fs::read_dir("specs")
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "gen"))
        .collect();
    files.push("tests/fixtures/genom3/timing/f10_restart_fixed.gen".into());
    files.push("tests/fixtures/genom3/semantics/f3_permanent.gen".into());
    for path in files {
        let shown = path.to_string_lossy().into_owned();
        let lines = stdout_lines(&["--color", "never", &shown]);
        assert!(
            lines.iter().all(|l| !l.contains('×') && !l.contains('⚠')),
            "{shown} is clean: {lines:#?}"
        );
        assert!(
            lines.len() <= 15,
            "{shown}: {} lines\n{lines:#?}",
            lines.len()
        );
    }
}

/// Runs `genom-check ARGS` under a pseudo-terminal (util-linux `script`),
/// returning what the terminal showed; `None` without `script`, or when
/// it could not give genom-check a terminal (no report came out).
fn on_a_terminal(args: &[&str]) -> Option<String> {
    let bin = assert_cmd::cargo::cargo_bin("genom-check");
    let mut line = bin.to_string_lossy().into_owned();
    for a in args {
        line.push(' ');
        line.push_str(a);
    }
    let out = std::process::Command::new("script")
        .args(["-qec", &line, "/dev/null"])
        .output()
        .ok()?;
    let shown = String::from_utf8_lossy(&out.stdout).into_owned();
    shown.contains("incomplete").then_some(shown)
}

#[test]
fn a_long_check_shows_progress_on_a_terminal_only() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.gen");
    let generated = genom_check()
        .args([
            "generate",
            "--seed",
            "3",
            "--services",
            "14",
            "--threads",
            "4",
        ])
        .args(["--codels", "4", "--density", "0.5"])
        .output()
        .unwrap();
    std::fs::write(&path, &generated.stdout).unwrap();
    let file = path.to_string_lossy().into_owned();
    let long = ["--no-reduction", "--timeout", "3s", file.as_str()];
    let Some(shown) = on_a_terminal(&long) else {
        eprintln!("SKIPPED: no pseudo-terminal (util-linux `script` missing or failing)");
        return;
    };
    assert!(
        shown.contains("genom-check: checking") && shown.contains(" states, "),
        "{shown}"
    );
    assert!(
        shown.contains("stops at 10,000,000 states or 3s"),
        "{shown}"
    );
    assert!(shown.contains("\x1b[2K"), "the line is erased: {shown}");
    let json = on_a_terminal(&[
        "--format",
        "json",
        "--no-reduction",
        "--timeout",
        "3s",
        &file,
    ])
    .unwrap_or_default();
    assert!(!json.contains("genom-check: checking"), "{json}");
    let piped = genom_check().args(long).output().unwrap();
    assert!(!String::from_utf8_lossy(&piped.stderr).contains("checking"));
}
