//! Worst-case response times (LANGUAGE.md dialect) and `--deadline`: the
//! exact worst cases of small components computed by hand (the fixtures of
//! `tests/fixtures/response/` say how), exact margins (a deadline equal to
//! the worst case is met, one nanosecond less is missed), `unbounded`,
//! `incomplete` under a state limit; every `deadline-miss` trace is checked
//! by the independent timing checker (`tests/timed_trace/mod.rs`) and by
//! the untimed replay (`genom_checker::replay`). Then the CLI: the table,
//! JSON `response_times`, `--deadline` and its usage errors.

#![allow(clippy::expect_used, clippy::unwrap_used)]

use crate::common;

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use gen_frontend::FsLoader;
use genom_check::{CheckOptions, CheckResult};
use genom_model::{Bound, Code, Diagnostic, Trace};
use genom_oracles::replay::replay;
use genom_oracles::timed_trace::{TimedClaim, check_timed};
use serde_json::Value;

const MS: u64 = 1_000_000;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from("tests/fixtures/response").join(name)
}

fn check_with(path: &Path, options: &CheckOptions) -> CheckResult {
    let options = options.clone().response_times(true);
    genom_check::check_file(path, &FsLoader, &options).expect("fixture is readable")
}

/// The worst case of each service, by name.
fn worst(result: &CheckResult) -> Vec<(String, Bound)> {
    result
        .response_times
        .iter()
        .map(|r| (r.service.clone(), r.worst))
        .collect()
}

fn misses(result: &CheckResult) -> Vec<&Diagnostic> {
    result
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::DeadlineMiss)
        .collect()
}

/// Checks a `deadline-miss` trace: every step's timing by the independent
/// checker, an instance of `service` without reply strictly after its
/// acknowledgment plus `deadline`, and the events by the untimed replay.
fn check_miss_trace(result: &CheckResult, trace: &Trace, service: &str, deadline: u64) {
    let c = common::component(result);
    let lines: Vec<String> = trace.steps.iter().map(|s| s.text.clone()).collect();
    let end = check_timed(c, trace, TimedClaim::PastDeadline(service, deadline))
        .unwrap_or_else(|e| panic!("timing checker: {e}\n{}", lines.join("\n")));
    let ack = end.late_ack_ns.expect("an acknowledged instance");
    assert!(end.last_ns > ack + deadline, "{}", lines.join("\n"));
    replay(c, trace).unwrap_or_else(|e| panic!("untimed replay: {e}\n{}", lines.join("\n")));
}

#[test]
fn hand_computed_worst_cases() {
    let cases: &[(&str, &[(&str, Bound)])] = &[
        ("three-codels.gen", &[("Move", Bound::Exact(34 * MS))]),
        (
            "interrupted.gen",
            &[
                ("Halt", Bound::Exact(11 * MS)),
                ("Move", Bound::Exact(41 * MS)),
            ],
        ),
        (
            "unbounded.gen",
            &[
                ("Park", Bound::Unbounded),
                ("Ping", Bound::Exact(13 * MS)),
                ("Track", Bound::Unbounded),
            ],
        ),
        ("watchdog-loop.gen", &[("Spin", Bound::Exact(51 * MS))]),
    ];
    for (name, expected) in cases {
        let result = check_with(&fixture(name), &CheckOptions::new());
        let want: Vec<(String, Bound)> = expected
            .iter()
            .map(|(s, b)| ((*s).to_owned(), *b))
            .collect();
        assert_eq!(worst(&result), want, "{name}");
    }
}

#[test]
fn the_worst_case_is_a_sharp_margin_for_every_exact_bound() {
    for name in [
        "three-codels.gen",
        "interrupted.gen",
        "unbounded.gen",
        "watchdog-loop.gen",
    ] {
        let path = fixture(name);
        let plain = check_with(&path, &CheckOptions::new());
        for (service, bound) in worst(&plain) {
            let Bound::Exact(w) = bound else { continue };
            // At the worst case: met.
            let at = check_with(&path, &CheckOptions::new().deadline_for(&service, w));
            assert!(
                misses(&at)
                    .iter()
                    .all(|d| !d.message.contains(&format!("`{service}`"))),
                "{name}: {service} meets {w} ns"
            );
            // One nanosecond less: missed, with a trace that shows it.
            let below = check_with(&path, &CheckOptions::new().deadline_for(&service, w - 1));
            let found: Vec<&Diagnostic> = misses(&below)
                .into_iter()
                .filter(|d| d.message.contains(&format!("`{service}`")))
                .collect();
            assert_eq!(found.len(), 1, "{name}: {service} misses {} ns", w - 1);
            let trace = found[0]
                .trace
                .as_ref()
                .expect("a deadline-miss has a trace");
            check_miss_trace(&below, trace, &service, w - 1);
        }
    }
}

#[test]
fn the_worst_case_of_the_worked_example_is_its_max_time() {
    // docs/timing.md's worked example: clean at max-time 12 ms, so no
    // execution is later; `max-time-exceeded` at 11999999 ns, so one is.
    let valid = common::valid("worst-case-equals-max-time.gen");
    let result = check_with(&common::relative(&valid), &CheckOptions::new());
    assert_eq!(worst(&result), [("Step".to_owned(), Bound::Exact(12 * MS))]);
}

#[test]
fn an_interrupted_instance_misses_its_deadline_through_its_cleanup() {
    let path = fixture("interrupted.gen");
    let result = check_with(&path, &CheckOptions::new().deadline_for("Move", 35 * MS));
    let found = misses(&result);
    assert_eq!(found.len(), 1);
    assert_eq!(
        found[0].message,
        "`Move` can reply later than its deadline of 35ms: worst-case response time 41ms"
    );
    let trace = found[0].trace.as_ref().expect("a trace");
    assert!(
        trace
            .steps
            .iter()
            .any(|s| s.event == genom_model::Event::Interrupt),
        "only an interrupted instance is that late"
    );
    check_miss_trace(&result, trace, "Move", 35 * MS);
}

#[test]
fn an_unbounded_service_misses_any_deadline_with_a_lasso() {
    let path = fixture("unbounded.gen");
    let options = CheckOptions::new()
        .deadline_for("Track", 3_600_000 * MS)
        .deadline_for("Ping", 13 * MS);
    let result = check_with(&path, &options);
    let found = misses(&result);
    assert_eq!(found.len(), 1, "Ping meets 13 ms");
    assert!(
        found[0]
            .message
            .contains("worst-case response time unbounded")
    );
    let trace = found[0].trace.as_ref().expect("a trace");
    assert!(trace.loop_start.is_some(), "the loop that never replies");
    let c = common::component(&result);
    check_timed(c, trace, TimedClaim::Rules).expect("a timed execution");
    replay(c, trace).expect("the untimed replay accepts it");
}

#[test]
fn a_state_limit_leaves_response_times_unknown_and_deadlines_undecided() {
    let path = fixture("three-codels.gen");
    let options = CheckOptions::new()
        .max_states(3)
        .deadline_for("Move", 50 * MS);
    let result = check_with(&path, &options);
    assert_eq!(worst(&result), [("Move".to_owned(), Bound::Unknown)]);
    assert!(misses(&result).is_empty());
    assert!(
        result
            .diagnostics
            .iter()
            .any(|d| d.code == Code::Incomplete && d.message.contains("deadline of `Move`")),
        "{:?}",
        result.diagnostics
    );
}

#[test]
fn untimed_components_have_no_response_times() {
    let result = check_with(Path::new("specs/pilot.gen"), &CheckOptions::new());
    assert!(result.component.is_some());
    assert!(result.response_times.is_empty());
}

// ------------------------------------------------------------------- CLI

fn genom_check() -> Command {
    let mut cmd = Command::cargo_bin("genom-check").expect("binary is built");
    cmd.env_remove("NO_COLOR").env("TERM", "dumb");
    cmd
}

#[test]
fn the_table_follows_the_diagnostics() {
    let out = genom_check()
        .args([
            "--color",
            "never",
            "--response-times",
            "tests/fixtures/response/unbounded.gen",
        ])
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    let table = "worst-case response times (acknowledgment to final reply):\n  service  worst response  own codels\n  Park     unbounded       1ms\n  Ping     13ms            1ms\n  Track    unbounded       loops\n";
    let at = text.find(table).unwrap_or_else(|| panic!("{text}"));
    assert!(text.find("starvation").is_some_and(|d| d < at), "{text}");
    assert!(
        text[at..]
            .lines()
            .nth(6)
            .is_some_and(|l| l.starts_with("tests/fixtures/response/unbounded.gen: 1 error")),
        "{text}"
    );
}

#[test]
fn json_lists_response_times_by_service_name() {
    let out = genom_check()
        .args([
            "--format",
            "json",
            "--response-times",
            "tests/fixtures/response/interrupted.gen",
            "specs/pilot.gen",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    let times = &doc["files"][0]["response_times"];
    assert_eq!(
        times,
        &serde_json::json!([
            {"service": "Halt", "status": "exact", "worst_ns": 11_000_000, "own_ns": 0, "note": null},
            {"service": "Move", "status": "exact", "worst_ns": 41_000_000, "own_ns": 9_000_000, "note": null},
        ])
    );
    assert_eq!(doc["files"][1]["response_times"], serde_json::json!([]));
}

#[test]
fn deadline_misses_are_errors_with_their_trace() {
    let out = genom_check()
        .args([
            "--format",
            "json",
            "--deadline",
            "Move=33999999ns",
            "--deadline",
            "Move=34ms",
            "tests/fixtures/response/three-codels.gen",
        ])
        .output()
        .unwrap();
    // The last deadline of a service counts: 34 ms is met.
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    let out = genom_check()
        .args([
            "--format",
            "json",
            "--deadline",
            "Move=33999999ns",
            "tests/fixtures/response/three-codels.gen",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    let d = &doc["files"][0]["diagnostics"][0];
    assert_eq!(d["code"], "deadline-miss");
    assert_eq!(d["line"], 11, "the service's name");
    let steps = d["trace"].as_array().expect("a trace");
    let last = steps.last().unwrap();
    assert_eq!(last["event"], "violation");
    assert!(last["time_ns"].as_u64().unwrap() > 33_999_999);
}

#[test]
fn an_unknown_deadline_service_is_a_usage_error() {
    genom_check()
        .args(["--deadline", "Mvoe=10ms", "tests/fixtures/response/three-codels.gen"])
        .assert()
        .code(2)
        .stderr(predicates::str::contains(
            "--deadline: `tests/fixtures/response/three-codels.gen` has no service `Mvoe` (did you mean `Move`?)",
        ));
    genom_check()
        .args([
            "--deadline",
            "Move",
            "tests/fixtures/response/three-codels.gen",
        ])
        .assert()
        .code(2)
        .stderr(predicates::str::contains("is not `SERVICE=DURATION`"));
}

#[test]
fn explain_knows_deadline_miss() {
    genom_check()
        .args(["explain", "deadline-miss"])
        .assert()
        .code(0)
        .stdout(predicates::str::contains("# `deadline-miss` (error)"));
}

#[test]
fn response_times_are_computed_only_when_asked() {
    let out = genom_check()
        .args([
            "--format",
            "json",
            "tests/fixtures/response/interrupted.gen",
        ])
        .output()
        .unwrap();
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["files"][0]["response_times"], serde_json::json!([]));
    let text = genom_check()
        .args([
            "--color",
            "never",
            "tests/fixtures/response/interrupted.gen",
        ])
        .output()
        .unwrap();
    let text = String::from_utf8(text.stdout).unwrap();
    assert!(!text.contains("worst-case response times"), "{text}");
}
