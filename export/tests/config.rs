//! The `config` export: snapshots of the runtime configuration of every
//! file in `specs/`, its validation against the committed JSON Schema, and
//! the schema kept in sync with the Rust types.
//!
//! To update the committed schema after changing the types, run
//! `UPDATE_SCHEMA=1 cargo test -p genom-export --test config`.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

mod common;

use std::path::Path;

use genom_checker::{CheckOptions, Engine};
use genom_export::config;
use serde_json::Value;

const SCHEMA_PATH: &str = "schema/runtime-config.schema.json";

/// Checks `path` and exports its configuration, with a verification
/// record built as the CLI builds it (a fixed tool version, so snapshots do
/// not change with releases).
fn export_config(path: &Path) -> String {
    export_with(path, &CheckOptions::new())
}

/// [`export_config`] with check options; the component is exported even
/// when unverified (as `--allow-unverified` does).
fn export_with(path: &Path, options: &CheckOptions) -> String {
    common::export_config_as_cli(&common::check_with(path, options))
}

#[test]
fn config_of_every_spec() {
    for path in common::specs() {
        let text = export_config(&path);
        let name = path
            .file_stem()
            .expect("stem")
            .to_string_lossy()
            .into_owned();
        insta::assert_snapshot!(name, text);
    }
}

#[test]
fn every_spec_is_verified_and_hashed() {
    for path in common::specs() {
        let doc: Value = serde_json::from_str(&export_config(&path)).expect("valid JSON");
        let v = &doc["verification"];
        assert_eq!(doc["verified"], Value::Bool(true), "{}", path.display());
        assert_eq!(v["error_codes"], serde_json::json!([]));
        assert_eq!(
            v["source"]["path"],
            Value::String(path.to_string_lossy().into_owned())
        );
        let text = std::fs::read(&path).expect("readable");
        let sha = v["source"]["sha256"].as_str().expect("hash");
        assert_eq!(sha.len(), 64);
        // The same file hashed by the system tool, when there is one.
        let tool = std::process::Command::new("sha256sum").arg(&path).output();
        if let Ok(out) = tool.as_ref().map(|o| (o.status.success(), &o.stdout)) {
            if out.0 {
                let line = String::from_utf8_lossy(out.1).into_owned();
                assert_eq!(
                    line.split_whitespace().next(),
                    Some(sha),
                    "{}",
                    path.display()
                );
            }
        }
        assert!(!text.is_empty());
    }
}

#[test]
fn export_is_deterministic() {
    let path = Path::new("../specs/mobileBase.gen");
    assert_eq!(export_config(path), export_config(path));
}

#[test]
fn committed_schema_is_up_to_date() {
    common::schema_is_up_to_date(
        SCHEMA_PATH,
        &config::schema(),
        "config",
        "config/document.rs",
    );
}

fn validator() -> jsonschema::Validator {
    common::validator(SCHEMA_PATH)
}

#[test]
fn every_spec_config_validates_against_the_schema() {
    let validator = validator();
    for path in common::specs() {
        let doc: Value = serde_json::from_str(&export_config(&path)).expect("valid JSON");
        let errors: Vec<String> = validator
            .iter_errors(&doc)
            .map(|e| format!("{} at {}", e, e.instance_path()))
            .collect();
        assert!(errors.is_empty(), "{}: {errors:#?}", path.display());
    }
}

#[test]
fn the_schema_rejects_malformed_documents() {
    let validator = validator();
    let path = Path::new("../specs/pilot.gen");
    let good: Value = serde_json::from_str(&export_config(path)).expect("valid JSON");
    assert!(validator.is_valid(&good));

    let mut bad = good.clone();
    bad["verification"]["source"]["sha256"] = Value::String("not a hash".into());
    assert!(!validator.is_valid(&bad), "a malformed hash is rejected");

    let mut bad = good.clone();
    bad["threads"][0]["period_ns"] = Value::String("1s".into());
    assert!(
        !validator.is_valid(&bad),
        "a period must be an integer or null"
    );

    let mut bad = good;
    bad["codels"][0]["next"] = serde_json::json!([{ "outcome": "jump" }]);
    assert!(
        !validator.is_valid(&bad),
        "outcomes are codel, report or end"
    );
}

/// The parsed config of a file (relative to this crate).
fn doc(path: &str) -> Value {
    serde_json::from_str(&export_config(Path::new(path))).expect("valid JSON")
}

/// The `property` or `property:subject` keys of the proven properties.
fn properties(doc: &Value) -> Vec<String> {
    doc["verification"]["properties"]
        .as_array()
        .expect("a list")
        .iter()
        .map(|p| match p["subject"].as_str() {
            Some(s) => format!("{}:{s}", p["property"].as_str().unwrap_or_default()),
            None => p["property"].as_str().unwrap_or_default().to_owned(),
        })
        .collect()
}

const GENERAL: [&str; 5] = [
    "static-semantics",
    "deadlock-free",
    "no-starvation",
    "every-service-can-start",
    "interrupts-terminate",
];

fn with_general(rest: &[&str]) -> Vec<String> {
    GENERAL
        .iter()
        .chain(rest)
        .map(|s| (*s).to_owned())
        .collect()
}

#[test]
fn the_pilot_proves_no_timing_property_without_wcets() {
    let d = doc("../specs/pilot.gen");
    assert_eq!(
        properties(&d),
        with_general(&[
            "every-codel-reachable",
            "every-service-can-end",
            "no-privilege-escalation"
        ])
    );
}

#[test]
fn the_arm_proves_its_threads_and_its_bounded_service() {
    let d = doc("../specs/arm.gen");
    let got = properties(&d);
    assert_eq!(
        got[GENERAL.len()..],
        [
            "every-codel-reachable",
            "every-service-can-end",
            "auto-services-run-forever",
            "no-privilege-escalation",
            "thread-never-overruns:safetyTask",
            "thread-never-overruns:servoTask",
            "meets-max-time:Brake",
        ]
    );
    // MoveJoints and Calibrate loop without bound: only the watchdog
    // enforces their max-time, so it is not listed as met.
    assert!(!got.iter().any(|p| p.ends_with(":MoveJoints")));
    let brake = &d["verification"]["properties"][GENERAL.len() + 6];
    assert_eq!(
        brake["statement"],
        "every instance of `Brake` sends its final reply within its max-time of 500ms of its acknowledgment, without the watchdog"
    );
}

#[test]
fn timing_properties_need_every_wcet_of_the_cluster() {
    let missing = properties(&doc(
        "../tests/fixtures/invalid/missing-wcet.codel-without-wcet.gen",
    ));
    assert!(
        !missing
            .iter()
            .any(|p| p.contains("overruns") || p.contains("max-time")),
        "{missing:?}"
    );
    let all = properties(&doc("../tests/fixtures/valid/every-codel-has-wcet.gen"));
    assert!(
        all.contains(&"thread-never-overruns:motion".to_owned()),
        "{all:?}"
    );
    assert!(all.contains(&"meets-max-time:Goto".to_owned()), "{all:?}");
    let watchdog = properties(&doc(
        "../tests/fixtures/invalid/max-time-watchdog.servo-loop.gen",
    ));
    assert!(watchdog.contains(&"thread-never-overruns:motion".to_owned()));
    assert!(!watchdog.contains(&"meets-max-time:Goto".to_owned()));
}

#[test]
fn a_warning_removes_the_property_it_contradicts() {
    let got = properties(&doc(
        "../tests/fixtures/invalid/unreachable-codel.orphan-codel.gen",
    ));
    assert!(got.contains(&"deadlock-free".to_owned()));
    assert!(
        !got.contains(&"every-codel-reachable".to_owned()),
        "{got:?}"
    );
}

/// `compatibility[other].request` of `service` in `d`.
fn request(d: &Value, service: &str, other: &str) -> String {
    let s = d["services"]
        .as_array()
        .expect("services")
        .iter()
        .find(|s| s["name"] == service)
        .expect("service exists");
    s["compatibility"][other]["request"]
        .as_str()
        .expect("a request outcome")
        .to_owned()
}

#[test]
fn the_compatibility_matrix_is_resolved_in_the_order_of_section_3() {
    let d = doc("../specs/arm.gen");
    // Brake stops and forbids MoveJoints.
    assert_eq!(request(&d, "Brake", "MoveJoints"), "interrupts");
    assert_eq!(request(&d, "MoveJoints", "Brake"), "forbidden");
    // MoveJoints stops itself: a new goal replaces the current one.
    assert_eq!(request(&d, "MoveJoints", "MoveJoints"), "interrupts");
    assert_eq!(request(&d, "Brake", "Brake"), "busy");
    assert_eq!(request(&d, "Monitor", "MoveJoints"), "concurrent");
    let d = doc("../tests/fixtures/valid/delays-chain-without-back-edge.gen");
    assert_eq!(request(&d, "Grasp", "Calibrate"), "waits");
    assert_eq!(request(&d, "Calibrate", "Grasp"), "concurrent");
    assert_eq!(request(&d, "Release", "Grasp"), "waits");
    assert_eq!(request(&d, "Release", "Calibrate"), "concurrent");
}

#[test]
fn requires_init_marks_every_service_but_the_init_one() {
    let d = doc("../specs/arm.gen");
    for s in d["services"].as_array().expect("services") {
        let init = s["kind"] == "init";
        assert_eq!(s["requires_init"], Value::Bool(!init), "{}", s["name"]);
    }
    let d = doc("../specs/pilot.gen");
    assert_eq!(d["services"][0]["requires_init"], Value::Bool(false));
}

#[test]
fn an_unverified_export_is_marked_and_lists_the_error_codes() {
    let validator = validator();
    let text = export_config(Path::new(
        "../tests/fixtures/invalid/deadlock.circular-delays.gen",
    ));
    let d: Value = serde_json::from_str(&text).expect("valid JSON");
    assert_eq!(d["verified"], Value::Bool(false));
    assert_eq!(
        d["verification"]["error_codes"],
        serde_json::json!(["deadlock"])
    );
    assert_eq!(d["verification"]["properties"], serde_json::json!([]));
    assert!(d["verification"]["counts"]["errors"].as_u64() >= Some(1));
    assert!(validator.is_valid(&d));

    let text = export_with(
        Path::new("../specs/pilot.gen"),
        // The explicit engine alone: `auto` would finish symbolically.
        &CheckOptions::new().max_states(2).engine(Engine::Explicit),
    );
    let d: Value = serde_json::from_str(&text).expect("valid JSON");
    assert_eq!(d["verified"], Value::Bool(false));
    assert_eq!(d["verification"]["complete"], Value::Bool(false));
    assert_eq!(
        d["verification"]["error_codes"],
        serde_json::json!(["incomplete"])
    );
    assert!(validator.is_valid(&d));
}
