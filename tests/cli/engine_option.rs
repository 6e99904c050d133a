//! `--engine explicit|symbolic|auto` on the command line: the explicit and
//! the symbolic engine give the same diagnostics on every behavioural
//! fixture, the statistics (`decided_by`) name the engine that decided each
//! part, timed components are decided with zones whatever the option, and
//! contradictory options are usage errors. GenoM3's untimed parts the same:
//! the kernel's symbolic sets give the explicit explorer's diagnostics and
//! traces, and `auto` finishes with them a part past the state limit.

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

/// The GenoM3 fixtures of the untimed semantics.
fn genom3_fixtures() -> Vec<std::path::PathBuf> {
    let mut files: Vec<_> = std::fs::read_dir("tests/fixtures/genom3/semantics")
        .expect("fixtures")
        .filter_map(|e| Some(e.ok()?.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "gen"))
        .collect();
    files.sort();
    files
}

/// Each diagnostic's code and the number of steps of its trace.
fn trace_lengths(doc: &Value) -> Vec<(String, usize)> {
    doc["files"][0]["diagnostics"]
        .as_array()
        .map(|ds| {
            ds.iter()
                .map(|d| {
                    let steps = d["trace"].as_array().map_or(0, Vec::len);
                    (d["code"].to_string(), steps)
                })
                .collect()
        })
        .unwrap_or_default()
}

/// The `(engine, complete)` of each `decided_by` entry.
fn decisions(doc: &Value) -> Vec<(String, bool)> {
    doc["files"][0]["statistics"]["decided_by"]
        .as_array()
        .map(|ds| {
            ds.iter()
                .map(|d| (d["engine"].to_string(), d["complete"] == true))
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

#[test]
fn genom3_parts_are_decided_by_the_engine_asked_for_with_the_same_verdicts() {
    let files = genom3_fixtures();
    assert!(files.len() >= 10, "only {} fixtures", files.len());
    let mut traces = 0;
    for file in &files {
        let explicit = report("explicit", file);
        let symbolic = report("symbolic", file);
        let name = file.display();
        assert_eq!(diagnostics(&explicit), diagnostics(&symbolic), "{name}");
        // Both breadth-first: traces as short.
        assert_eq!(trace_lengths(&explicit), trace_lengths(&symbolic), "{name}");
        traces += trace_lengths(&symbolic)
            .iter()
            .filter(|(_, n)| *n > 0)
            .count();
        let engines =
            |doc: &Value| -> Vec<String> { decisions(doc).into_iter().map(|(e, _)| e).collect() };
        assert!(
            engines(&explicit).iter().all(|e| e == "\"explicit\""),
            "{name}"
        );
        assert!(
            engines(&symbolic).iter().all(|e| e == "\"symbolic\""),
            "{name}"
        );
        let states = |doc: &Value| doc["files"][0]["statistics"]["states"].clone();
        assert_eq!(states(&explicit), states(&symbolic), "{name}");
    }
    assert!(traces >= 5, "{traces} traces compared");
}

#[test]
fn auto_finishes_a_genom3_part_past_the_state_limit_with_the_symbolic_sets() {
    let file = "tests/fixtures/genom3/semantics/f6_interrupt_stop.gen";
    let run = |engine: &str| {
        let out = genom_check()
            .args([
                "--format",
                "json",
                "--max-states",
                "10",
                "--engine",
                engine,
                file,
            ])
            .output()
            .expect("runs");
        let doc: Value = serde_json::from_slice(&out.stdout).expect("one JSON document");
        (out.status.code(), doc)
    };
    let whole = report("explicit", Path::new(file));
    // The explicit explorer alone stops at the limit and says so.
    let (_, explicit) = run("explicit");
    let codes = diagnostics(&explicit).join("\n");
    assert!(codes.contains("\"incomplete\""), "{codes}");
    assert_eq!(decisions(&explicit), [("\"explicit\"".to_owned(), false)]);
    // `auto` then explores the part with the sets: complete, the
    // verdicts of the unlimited exploration, both attempts listed, and
    // the states of both counted.
    let (status, auto) = run("auto");
    assert_eq!(diagnostics(&auto), diagnostics(&whole));
    assert_eq!(status, Some(0), "{auto:#}");
    assert_eq!(
        decisions(&auto),
        [
            ("\"explicit\"".to_owned(), false),
            ("\"symbolic\"".to_owned(), true)
        ]
    );
    let stats = &auto["files"][0]["statistics"];
    let sum: u64 = stats["decided_by"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d["states"].as_u64().unwrap())
        .sum();
    assert_eq!(stats["states"].as_u64(), Some(sum));
    assert_eq!(
        stats["decided_by"][1]["states"],
        whole["files"][0]["statistics"]["states"]
    );
}
