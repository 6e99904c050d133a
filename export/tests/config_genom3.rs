//! The `config` export of GenoM3 components: snapshots of the runtime
//! configuration of timing and semantics fixtures, its validation against
//! the committed JSON Schema (kept in sync with the Rust types), and the
//! facts it must carry: the response times the check computed, the WCET
//! file's SHA-256 and the instance bound the verdicts rest on, what each
//! codel locks, and which properties are proven.
//!
//! To update the committed schema after changing the types, run
//! `UPDATE_SCHEMA=1 cargo test -p genom-export --test config_genom3`.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

mod common;

use std::path::{Path, PathBuf};

use genom_checker::CheckOptions;
use genom_export::config;
use serde_json::Value;
use sha2::{Digest, Sha256};

const SCHEMA_PATH: &str = "schema/genom3-runtime-config.schema.json";

/// Fixtures that verify, with their WCET files.
const TIMED: [&str; 4] = [
    "response/r1_paused_chain",
    "response/r4_validate_and_codel",
    "timing/f10_restart_fixed",
    "timing/f1b_chain_paused",
];

fn fixture(name: &str, ext: &str) -> PathBuf {
    Path::new("../tests/fixtures/genom3").join(format!("{name}.{ext}"))
}

/// The check of a GenoM3 file (with its WCET file, if any) with response
/// times, and its configuration as the CLI exports it (even unverified,
/// as `--allow-unverified` does).
fn export(path: &Path, wcet: Option<&Path>, includes: &[PathBuf]) -> (common::CheckResult, String) {
    let options = CheckOptions::new().response_times(wcet.is_some());
    let result = common::check_genom3(path, includes, wcet, &options);
    let text = common::export_config_as_cli(&result);
    (result, text)
}

fn timed_doc(name: &str) -> (common::CheckResult, Value) {
    let wcet = fixture(name, "wcet");
    let (result, text) = export(&fixture(name, "gen"), Some(&wcet), &[]);
    (result, serde_json::from_str(&text).expect("valid JSON"))
}

fn service<'a>(doc: &'a Value, name: &str) -> &'a Value {
    doc["services"]
        .as_array()
        .expect("services")
        .iter()
        .find(|s| s["name"] == name)
        .expect("the service is listed")
}

#[test]
fn genom3_config_of_the_fixtures() {
    for name in TIMED {
        let wcet = fixture(name, "wcet");
        let (_, text) = export(&fixture(name, "gen"), Some(&wcet), &[]);
        let stem = name.replace('/', "__");
        insta::assert_snapshot!(format!("genom3__{stem}"), text);
    }
    let (_, text) = export(&fixture("semantics/f6_interrupt_stop", "gen"), None, &[]);
    insta::assert_snapshot!("genom3__untimed__f6_interrupt_stop", text);
}

#[test]
fn committed_genom3_schema_is_up_to_date() {
    common::schema_is_up_to_date(
        SCHEMA_PATH,
        &config::genom3_schema(),
        "config_genom3",
        "config/genom3_document.rs",
    );
}

fn validator() -> jsonschema::Validator {
    common::validator(SCHEMA_PATH)
}

fn assert_valid(validator: &jsonschema::Validator, doc: &Value, what: &str) {
    let errors: Vec<String> = validator
        .iter_errors(doc)
        .map(|e| format!("{} at {}", e, e.instance_path()))
        .collect();
    assert!(errors.is_empty(), "{what}: {errors:#?}");
}

#[test]
fn every_genom3_config_validates_and_the_schema_rejects_malformed_ones() {
    let validator = validator();
    for name in TIMED {
        let (_, doc) = timed_doc(name);
        assert_valid(&validator, &doc, name);
        assert_eq!(doc["format"], "genom-check/genom3-runtime-config");
        assert_eq!(doc["verified"], Value::Bool(true), "{name}");
    }
    let (_, good) = timed_doc("response/r4_validate_and_codel");
    let mut bad = good.clone();
    bad["services"][1]["response_time"]["status"] = Value::String("fast".into());
    assert!(!validator.is_valid(&bad), "a status is one of five");
    let mut bad = good.clone();
    bad["assumptions"]["wcet_file"]["sha256"] = Value::String("cafe".into());
    assert!(!validator.is_valid(&bad), "a malformed hash is rejected");
    let mut bad = good;
    bad["tasks"][0]["codels"] = serde_json::json!([{ "function": "f" }]);
    assert!(!validator.is_valid(&bad), "a codel has states and locks");
}

#[test]
fn response_times_are_the_checks_and_the_hand_computed_one() {
    for name in TIMED {
        let (result, doc) = timed_doc(name);
        assert!(!result.response_times.is_empty(), "{name}: computed");
        for r in &result.response_times {
            let entry = &service(&doc, &r.service)["response_time"];
            assert_eq!(entry["status"], r.worst.status(), "{name} {}", r.service);
            assert_eq!(
                entry["worst_ns"].as_u64(),
                r.worst.ns(),
                "{name} {}",
                r.service
            );
        }
    }
    // The fixture's comment: validate 1 ms + lock wait 4 ms + codel 1 ms.
    let (_, doc) = timed_doc("response/r4_validate_and_codel");
    let set = &service(&doc, "set")["response_time"];
    assert_eq!(set["status"], "exact");
    assert_eq!(set["worst_ns"].as_u64(), Some(6_000_000));
    // An activity that pauses forever never replies.
    assert_eq!(
        service(&doc, "watch")["response_time"]["status"],
        "unbounded"
    );
    // Without a WCET file nothing is timed.
    let (_, text) = export(&fixture("semantics/f6_interrupt_stop", "gen"), None, &[]);
    let untimed: Value = serde_json::from_str(&text).expect("JSON");
    for s in untimed["services"].as_array().expect("services") {
        assert_eq!(s["response_time"], Value::Null, "{}", s["name"]);
    }
    assert_eq!(untimed["assumptions"]["wcet_file"], Value::Null);
    assert_eq!(untimed["assumptions"]["max_instances"], Value::Null);
}

#[test]
fn the_wcet_file_and_the_instance_bound_are_what_the_verdicts_rest_on() {
    let name = "response/r4_validate_and_codel";
    let (_, doc) = timed_doc(name);
    let wcet = fixture(name, "wcet");
    let bytes = std::fs::read(&wcet).expect("readable");
    let digest: String = Sha256::digest(&bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    let file = &doc["assumptions"]["wcet_file"];
    assert_eq!(file["sha256"], Value::String(digest));
    assert_eq!(
        file["path"],
        Value::String(wcet.to_string_lossy().into_owned())
    );
    assert_eq!(doc["assumptions"]["max_instances"].as_u64(), Some(1));
    let statements = doc["assumptions"]["statements"].to_string();
    assert!(statements.contains("WCET"), "{statements}");
    // Each state carries the WCET the file gives it.
    let validate = &service(&doc, "set")["validate"];
    assert_eq!(validate["states"][0]["name"], "validate");
    assert_eq!(validate["states"][0]["wcet_ns"].as_u64(), Some(1_000_000));
    let watch = &service(&doc, "watch")["codels"][0];
    let states: Vec<(&str, Option<u64>)> = watch["states"]
        .as_array()
        .expect("states")
        .iter()
        .map(|s| {
            (
                s["name"].as_str().unwrap_or_default(),
                s["wcet_ns"].as_u64(),
            )
        })
        .collect();
    assert_eq!(
        states,
        [("start", Some(4_000_000)), ("main", Some(4_000_000))]
    );
    assert_eq!(
        watch["yields"],
        serde_json::json!([{ "state": "main", "pause": true }])
    );
}

#[test]
fn each_codel_lists_what_it_locks() {
    let (_, doc) = timed_doc("response/r4_validate_and_codel");
    let locks = |v: &Value| v["locks"].clone();
    assert_eq!(
        locks(&service(&doc, "set")["codels"][0]),
        serde_json::json!([{ "kind": "ids", "name": "x", "writes": true }])
    );
    assert_eq!(
        locks(&service(&doc, "watch")["codels"][0]),
        serde_json::json!([{ "kind": "ids", "name": "x", "writes": false }])
    );
    // `validate r3_check(in v)` reads a parameter only: it locks nothing.
    assert_eq!(
        locks(&service(&doc, "set")["validate"]),
        serde_json::json!([])
    );
}

#[test]
fn task_overruns_are_proven_only_when_every_codel_has_a_wcet() {
    let props = |doc: &Value| -> Vec<String> {
        doc["verification"]["properties"]
            .as_array()
            .expect("a list")
            .iter()
            .map(|p| p["property"].as_str().unwrap_or_default().to_owned())
            .collect()
    };
    let (_, doc) = timed_doc("response/r4_validate_and_codel");
    assert!(props(&doc).contains(&"thread-never-overruns".to_owned()));
    assert!(props(&doc).contains(&"no-livelock".to_owned()));
    // The same component with one WCET left out: the codel counts as
    // taking no time, so no overrun is proven.
    let dir = tempfile::tempdir().expect("temp dir");
    let partial = dir.path().join("partial.wcet");
    let text = std::fs::read_to_string(fixture("response/r4_validate_and_codel", "wcet"))
        .expect("readable");
    let kept: String = text
        .lines()
        .filter(|l| !l.starts_with("set.codel"))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(&partial, kept).expect("write");
    let (_, text) = export(
        &fixture("response/r4_validate_and_codel", "gen"),
        Some(&partial),
        &[],
    );
    let doc: Value = serde_json::from_str(&text).expect("JSON");
    assert!(!props(&doc).contains(&"thread-never-overruns".to_owned()));
    assert_eq!(
        service(&doc, "set")["codels"][0]["states"][0]["wcet_ns"],
        Value::Null
    );
}

/// The corpus components with a WCET file, when the corpus is present
/// (`../shared/corpus/genom3`, next to the repository).
fn corpus(name: &str) -> Option<PathBuf> {
    let path = Path::new("../../shared/corpus/genom3")
        .join(format!("{name}-genom3"))
        .join(format!("{name}.gen"));
    path.exists().then_some(path)
}

#[test]
#[ignore = "needs the GenoM3 corpus next to the repository (../shared/corpus/genom3)"]
fn corpus_configs_validate_and_carry_response_times_and_the_wcet_digest() {
    let validator = validator();
    for name in ["uavatt", "uavpos", "uavvs"] {
        let path = corpus(name).expect("the corpus is present");
        let wcet = Path::new("../tests/fixtures/genom3/wcet").join(format!("{name}.wcet"));
        let includes = [PathBuf::from("../tests/fixtures/genom3/include")];
        let (result, text) = export(&path, Some(&wcet), &includes);
        let doc: Value = serde_json::from_str(&text).expect("JSON");
        assert_valid(&validator, &doc, name);
        assert!(
            doc["assumptions"]["wcet_file"]["sha256"].is_string(),
            "{name}"
        );
        assert!(!result.response_times.is_empty(), "{name}");
        let timed = doc["services"]
            .as_array()
            .expect("services")
            .iter()
            .filter(|s| !s["response_time"].is_null())
            .count();
        assert_eq!(timed, result.response_times.len(), "{name}");
    }
}
