//! Resource limits through the CLI: `--max-states`, `--timeout` and
//! `--max-memory` each end in the `incomplete` verdict (exit 1) naming the
//! limit and the properties left unproven, never in a clean summary; and
//! huge inputs, generated here (never committed), either verify or stop
//! cleanly on a limit, never crash. See docs/limits.md.

#![allow(clippy::expect_used, clippy::print_stderr)] // test support code

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use assert_cmd::Command;
use serde_json::Value;

use crate::common;

fn genom_check() -> Command {
    let mut cmd = Command::cargo_bin("genom-check").expect("binary is built");
    cmd.env("NO_COLOR", "1");
    cmd
}

/// A component with tens of thousands of reachable states (seven services,
/// timed): far more than the tiny limits used here.
const BIG: &str = "specs/arm.gen";

/// Its services, all of which a state or time limit leaves unproven.
const ARM_SERVICES: &str =
    "`Calibrate`, `Monitor`, `MoveJoints`, `Brake`, `SetLimits`, `ClearFault`, `GetState`";

/// The memory limit bounds the process's heap; an exploration's storage is
/// freed before the next: `GetState`, which shares no rule with the
/// others, is explored on its own after the large cluster and fits.
const ARM_SERVICES_BUT_GETSTATE: &str =
    "`Calibrate`, `Monitor`, `MoveJoints`, `Brake`, `SetLimits`, `ClearFault`";

/// Runs `genom-check --format json` with `args` on `file`; returns the exit
/// status and the file's JSON report.
fn check_json(args: &[&str], file: &Path) -> (Option<i32>, Value) {
    let out = genom_check()
        .args(["--format", "json"])
        .args(args)
        .arg(file)
        .output()
        .expect("runs");
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "stdout is one JSON document ({e}); exit {:?}, stderr:\n{}",
            out.status.code(),
            String::from_utf8_lossy(&out.stderr)
        )
    });
    (out.status.code(), doc["files"][0].clone())
}

/// The diagnostics of a JSON file report with this code.
fn with_code<'a>(file: &'a Value, code: &str) -> Vec<&'a Value> {
    file["diagnostics"]
        .as_array()
        .expect("diagnostics")
        .iter()
        .filter(|d| d["code"] == code)
        .collect()
}

/// Asserts the `incomplete` verdict for `limit`: exit 1, exactly one
/// `incomplete` error naming the limit and every service as unproven, the
/// statistics marked incomplete, and no negative claim (dead service,
/// unreachable codel) about what was not explored.
fn assert_incomplete(args: &[&str], limit: &str, services: &str) {
    let (code, file) = check_json(args, Path::new(BIG));
    assert_eq!(code, Some(1), "{file:#}");
    let incomplete = with_code(&file, "incomplete");
    assert_eq!(incomplete.len(), 1, "{file:#}");
    let d = incomplete[0];
    assert_eq!(d["severity"], "error");
    assert_eq!(d["line"], 30, "points at the component name");
    let message = d["message"].as_str().expect("message");
    let help = d["help"].as_str().expect("help");
    if message.ends_with("during the static checks") {
        // The limit passed before the static checks were done: none of the
        // behaviour was explored, and the help says what was not checked.
        assert_eq!(
            message,
            format!("verification is incomplete: the {limit} was reached during the static checks")
        );
        assert!(help.contains("every behavioural property"), "{help}");
        assert!(file["statistics"].is_null(), "{file:#}");
    } else {
        assert_eq!(
            message,
            format!("verification is incomplete: the {limit} was reached")
        );
        // What is left, then (issue 32) what the run spent.
        let left = format!(
            "left unproven: deadlock and starvation freedom, unbounded interrupts, dead \
             services and codel reachability for services {services}; "
        );
        assert!(help.starts_with(&left), "{help}");
        assert!(help.contains("raise the limit to finish"), "{help}");
        assert!(help.contains("Stopped after "), "{help}");
        assert_eq!(file["statistics"]["complete"], false, "{file:#}");
    }
    for code in ["dead-service", "unreachable-codel"] {
        assert!(
            with_code(&file, code).is_empty(),
            "{code} claimed: {file:#}"
        );
    }
}

/// The human summary of a limited run: errors counted, `incomplete` said,
/// never the clean `0 errors`.
fn assert_human_summary_not_clean(args: &[&str]) {
    let out = genom_check().args(args).arg(BIG).output().expect("runs");
    assert_eq!(out.status.code(), Some(1));
    let text = String::from_utf8(out.stdout).expect("UTF-8");
    let summary = text
        .lines()
        .rfind(|l| l.starts_with(BIG))
        .expect("a summary line");
    // Stopped in the exploration, the figures say `incomplete`; stopped
    // during the static checks, there are no figures and the error says it.
    let in_static = text.contains("was reached during the static checks");
    assert!(summary.contains(", incomplete)") || in_static, "{summary}");
    assert!(!summary.contains(": 0 errors"), "{summary}");
    assert!(text.contains("× verification is incomplete"), "{text}");
}

#[test]
fn without_limits_the_big_component_verifies_completely() {
    // The twin of the tests below: the limits, not the component, give
    // `incomplete`.
    let (code, file) = check_json(&[], Path::new(BIG));
    assert_eq!(code, Some(0), "{file:#}");
    assert!(with_code(&file, "incomplete").is_empty());
    assert_eq!(file["statistics"]["complete"], true);
    assert!(file["statistics"]["states"].as_u64().expect("states") > 10_000);
}

#[test]
fn a_state_limit_gives_incomplete() {
    assert_incomplete(
        &["--max-states", "10"],
        "state limit (--max-states)",
        ARM_SERVICES,
    );
    assert_human_summary_not_clean(&["--max-states", "10"]);
    // The limit bounds the states stored: far fewer than the whole space.
    let (_, file) = check_json(&["--max-states", "10"], Path::new(BIG));
    let states = file["statistics"]["states"].as_u64().expect("states");
    assert!(states < 100, "{states} states stored under --max-states 10");
}

#[test]
fn a_time_limit_gives_incomplete() {
    // 1 ms is less than parsing alone takes: the limit stops the static
    // checks (or, on a faster machine, the exploration); no wall-clock
    // figure is asserted.
    assert_incomplete(
        &["--timeout", "1ms"],
        "time limit (--timeout)",
        ARM_SERVICES,
    );
    assert_human_summary_not_clean(&["--timeout", "1ms"]);
}

#[test]
fn a_memory_limit_gives_incomplete() {
    // 4 MiB: a soft bound of 2.6 MiB of heap holds the parsed spec and its
    // model (about 1 MiB) but not the 115,000 states of the large cluster.
    assert_incomplete(
        &["--max-memory", "4M"],
        "memory limit (--max-memory)",
        ARM_SERVICES_BUT_GETSTATE,
    );
    assert_human_summary_not_clean(&["--max-memory", "4M"]);
}

#[test]
fn limits_apply_to_every_file_and_static_errors_still_show() {
    // A static error is reported whatever the limits (the engines do not
    // run on a file with errors), and the limit still stops the other file.
    let out = genom_check()
        .args(["--max-states", "10", "--format", "json"])
        .arg("tests/fixtures/invalid/duplicate-definition.two-services.gen")
        .arg(BIG)
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(1));
    let doc: Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(
        with_code(&doc["files"][0], "duplicate-definition").len(),
        1,
        "{doc:#}"
    );
    assert!(with_code(&doc["files"][0], "incomplete").is_empty());
    assert_eq!(with_code(&doc["files"][1], "incomplete").len(), 1);
}

// ----------------------------------------------------------- huge inputs

/// `services` independent services of `codels` start/exec codels each on
/// `threads` threads, one line per attribute. Every `ids` member is used by
/// one service; each service stops itself, and every tenth one also stops
/// its predecessor (clusters of ten). Returns the text.
fn huge_component(services: usize, codels: usize, threads: usize) -> String {
    let mut out = String::from("component huge {\n  category: default;\n  lang: C;\n}\n\n");
    out.push_str("ids data {\n");
    for i in 0..services {
        let _ = writeln!(out, "  double m{i};");
    }
    out.push_str("}\n\n");
    for t in 0..threads {
        let _ = writeln!(out, "thread t{t} {{\n  period: 10ms;\n}}\n");
    }
    for i in 0..services {
        let _ = writeln!(out, "service S{i} {{\n  thread: t{};", i % threads);
        let _ = writeln!(out, "  input: data.m{i} := 0.0 \"target\";");
        if i % 10 == 9 {
            let _ = writeln!(out, "  stops: S{i}, S{};", i - 1);
        } else {
            let _ = writeln!(out, "  stops: S{i};");
        }
        for k in 0..codels {
            let kind = if k == 0 { "start codel" } else { "exec codel" };
            let name = if k == 0 {
                String::new()
            } else {
                format!(" c{k}")
            };
            let next = if k + 1 < codels {
                format!("c{}, ", k + 1)
            } else {
                String::new()
            };
            let _ = writeln!(out, "  {kind}{name} {{");
            let _ = writeln!(out, "    exec: f{i}_{k}(data.m{i});");
            let _ = writeln!(out, "    update: data.m{i};");
            let _ = writeln!(out, "    on-inter: halt;");
            let _ = writeln!(out, "    next: {next}end;");
            out.push_str("  }\n");
        }
        out.push_str("  inter codel halt {\n");
        let _ = writeln!(out, "    exec: h{i}(data.m{i});\n    next: ;\n  }}\n}}\n");
    }
    out
}

/// Checks a generated file with limits; asserts a clean stop (exit 0 with
/// a complete clean summary, or exit 1 with `incomplete` and/or
/// behavioural verdicts only) and returns the statistics line.
fn check_huge(name: &str, text: &str) -> String {
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join(name);
    std::fs::write(&path, text).expect("written");
    let lines = text.lines().count();
    let started = Instant::now();
    let (code, file) = check_json(&["--max-states", "100000", "--timeout", "20s"], &path);
    let elapsed = started.elapsed();
    let errors = common::error_codes(&file);
    let stats = &file["statistics"];
    let figures = format!(
        "{name}: {lines} lines, exit {code:?}, {} states, complete {}, {:.1} s, errors {errors:?}",
        stats["states"],
        stats["complete"],
        elapsed.as_secs_f64()
    );
    eprintln!("{figures}");
    // The engines ran, or a limit stopped the static checks before them
    // (a loaded machine): a clean stop either way.
    let static_stop = errors == ["incomplete"] && stats.is_null();
    assert!(stats.is_object() || static_stop, "{figures}");
    if static_stop {
        return figures;
    }
    match code {
        Some(0) => assert!(errors.is_empty() && stats["complete"] == true, "{figures}"),
        Some(1) => {
            let incomplete = errors.contains(&"incomplete");
            assert_eq!(incomplete, stats["complete"] == false, "{figures}");
            let behavioural = [
                "incomplete",
                "deadlock",
                "starvation",
                "dead-service",
                "unbounded-interrupt",
                "codel-overrun",
                "thread-overrun",
                "max-time-exceeded",
                "unreachable-codel",
            ];
            assert!(errors.iter().all(|c| behavioural.contains(c)), "{figures}");
        }
        other => panic!("crash or usage error: exit {other:?}; {figures}"),
    }
    figures
}

#[test]
fn a_100000_line_component_verifies_or_stops_cleanly() {
    // 1,300 services of 12 codels: 107,940 lines.
    let text = huge_component(1_300, 12, 8);
    assert!(text.lines().count() >= 100_000, "{}", text.lines().count());
    check_huge("lines.gen", &text);
}

#[test]
fn a_10000_service_component_verifies_or_stops_cleanly() {
    let text = huge_component(10_000, 1, 16);
    assert_eq!(text.matches("\nservice ").count(), 10_000);
    check_huge("services.gen", &text);
}

#[test]
fn a_huge_single_cluster_stops_cleanly_on_its_limits() {
    // 2,000 generated services linked by rules into one large cluster:
    // every state has thousands of successors. The limits must still stop
    // the exploration (within a state's expansion).
    let mut config = genom_generate::GeneratorConfig::new(7, 2_000);
    config.codels_per_service = 10;
    config.threads = 4;
    let text = genom_generate::generate(&config);
    let figures = check_huge("cluster.gen", &text);
    assert!(figures.contains("complete false"), "{figures}");
}
