//! `--engine explicit|symbolic|auto` on the command line: the explicit and
//! the symbolic engine give the same diagnostics on every behavioural
//! fixture, the statistics (`decided_by`) name the engine that decided each
//! part, timed components are decided with zones whatever the option, and
//! contradictory options are usage errors.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

use std::path::Path;

use assert_cmd::Command;
use serde_json::Value;

fn genom_check() -> Command {
    let mut cmd = Command::cargo_bin("genom-check").expect("binary is built");
    cmd.env_remove("NO_COLOR").env("TERM", "xterm");
    cmd
}

/// The JSON report of `check --engine ENGINE FILE`.
fn report(engine: &str, file: &Path) -> Value {
    let out = genom_check()
        .args(["--format", "json", "--engine", engine])
        .arg(file)
        .output()
        .expect("runs");
    serde_json::from_slice(&out.stdout).expect("one JSON document")
}

/// Each diagnostic's code, line, column and message.
fn diagnostics(doc: &Value) -> Vec<String> {
    doc["files"][0]["diagnostics"]
        .as_array()
        .map(|ds| {
            ds.iter()
                .map(|d| {
                    format!(
                        "{} {}:{} {}",
                        d["code"], d["line"], d["column"], d["message"]
                    )
                })
                .collect()
        })
        .unwrap_or_default()
}

/// The `method` of each `decided_by` entry.
fn methods(doc: &Value) -> Vec<String> {
    doc["files"][0]["statistics"]["decided_by"]
        .as_array()
        .map(|ds| ds.iter().map(|d| d["method"].to_string()).collect())
        .unwrap_or_default()
}

/// The behavioural fixtures: deadlocks, starvations, unbounded interrupts,
/// dead services and unreachable codels.
fn behavioural_fixtures() -> Vec<std::path::PathBuf> {
    let prefixes = [
        "deadlock.",
        "starvation.",
        "unbounded-interrupt.",
        "dead-service.",
        "unreachable-codel.",
    ];
    let mut files: Vec<_> = std::fs::read_dir("tests/fixtures/invalid")
        .expect("fixtures")
        .filter_map(|e| Some(e.ok()?.path()))
        .filter(|p| {
            let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
            prefixes.iter().any(|x| name.starts_with(x)) && name.ends_with(".gen")
        })
        .collect();
    files.sort();
    files
}

#[test]
fn explicit_and_symbolic_engines_agree_on_every_behavioural_fixture() {
    let files = behavioural_fixtures();
    assert!(files.len() >= 10, "only {} fixtures", files.len());
    let mut symbolic_parts = 0usize;
    for file in &files {
        let explicit = report("explicit", file);
        let symbolic = report("symbolic", file);
        assert_eq!(
            diagnostics(&explicit),
            diagnostics(&symbolic),
            "{}",
            file.display()
        );
        assert!(!diagnostics(&explicit).is_empty(), "{}", file.display());
        assert!(
            !methods(&explicit).iter().any(|m| m == "\"symbolic\""),
            "{}: --engine explicit used the symbolic engine",
            file.display()
        );
        // Timed fixtures are decided with zones, and a component whose
        // initialisation never succeeds has nothing after it.
        symbolic_parts += usize::from(methods(&symbolic).iter().any(|m| m == "\"symbolic\""));
        let engines = symbolic["files"][0]["statistics"]["decided_by"][0]["engine"].clone();
        assert!(engines.is_string(), "{}: {engines}", file.display());
    }
    assert!(
        symbolic_parts >= files.len() * 2 / 3,
        "{symbolic_parts} of {} decided symbolically",
        files.len()
    );
}

#[test]
fn the_human_summary_says_when_the_symbolic_engine_decided() {
    let file = "tests/fixtures/invalid/deadlock.circular-delays.gen";
    let out = genom_check()
        .args(["--engine", "symbolic", file])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(1));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains(" ms, symbolic)"), "{text}");
    let out = genom_check()
        .args(["--engine", "explicit", file])
        .output()
        .expect("runs");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("transitions, ") && !text.contains("symbolic"),
        "{text}"
    );
}

#[test]
fn timed_components_are_decided_with_zones() {
    let file = Path::new("tests/fixtures/valid/three-codels-in-30ms.gen");
    for engine in ["auto", "symbolic"] {
        let doc = report(engine, file);
        assert_eq!(methods(&doc), ["\"zones\""], "--engine {engine}");
        assert_eq!(
            doc["files"][0]["statistics"]["decided_by"][0]["engine"],
            "zones"
        );
    }
}

#[test]
fn contradictory_or_unknown_engines_are_usage_errors() {
    let file = "specs/pilot.gen";
    let out = genom_check()
        .args(["--engine", "symbolic", "--no-reduction", file])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--engine explicit --no-reduction"));
    genom_check()
        .args(["--engine", "bdd", file])
        .assert()
        .code(2);
    genom_check()
        .args(["--engine", "explicit", "--no-reduction", file])
        .assert()
        .code(0);
}
