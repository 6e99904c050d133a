//! The `config` export: snapshots of the runtime configuration of every
//! file in `specs/`, its validation against the committed JSON Schema, and
//! the schema kept in sync with the Rust types.
//!
//! To update the committed schema after changing the types, run
//! `UPDATE_SCHEMA=1 cargo test -p genom-export --test config`.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

use std::path::{Path, PathBuf};

use genom_checker::{CheckOptions, check_file};
use genom_export::{ExportInput, Format, Verification, config};
use genom_model::Counts;
use genom_parser::FsLoader;
use serde_json::Value;

const SCHEMA_PATH: &str = "schema/runtime-config.schema.json";

/// Every `.gen` file of `specs/`, as a path relative to this crate (the
/// test's working directory), so that the hashed paths are stable.
fn specs() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir("../specs")
        .expect("specs/ is readable")
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "gen"))
        .map(|p| Path::new("../specs").join(p.file_name().expect("file name")))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no spec found");
    files
}

/// Checks `path` and exports its configuration, with a verification
/// record built as the CLI builds it (a fixed tool version, so snapshots do
/// not change with releases).
fn export_config(path: &Path) -> String {
    let result = check_file(path, &FsLoader, &CheckOptions::new()).expect("spec is readable");
    let component = result.component.as_ref().expect("spec has a component");
    let counts = Counts::of(&result.diagnostics);
    let stats = result.statistics.as_ref();
    let complete = stats.is_some_and(|s| s.complete);
    let verified = counts.errors == 0 && complete;
    let properties = if verified {
        [
            "static-semantics",
            "deadlock-freedom",
            "starvation-freedom",
            "no-dead-service",
        ]
        .iter()
        .map(|s| (*s).to_owned())
        .collect()
    } else {
        Vec::new()
    };
    let verification = Verification {
        verified,
        counts,
        states: stats.map_or(0, |s| s.states),
        transitions: stats.map_or(0, |s| s.transitions),
        complete,
        properties,
        tool_version: "0.0.0-test".to_owned(),
    };
    let input = ExportInput {
        component,
        sources: &result.sources,
        verification: &verification,
    };
    let exported = genom_export::export(Format::Config, &input).expect("config export succeeds");
    assert!(
        exported.extra.is_empty(),
        "the config export has no companion file"
    );
    exported.main
}

#[test]
fn config_of_every_spec() {
    for path in specs() {
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
    for path in specs() {
        let doc: Value = serde_json::from_str(&export_config(&path)).expect("valid JSON");
        let v = &doc["verification"];
        assert_eq!(v["verified"], Value::Bool(true), "{}", path.display());
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
    let generated = config::schema();
    if std::env::var_os("UPDATE_SCHEMA").is_some() {
        std::fs::create_dir_all("schema").expect("create schema/");
        std::fs::write(SCHEMA_PATH, &generated).expect("write the schema");
        return;
    }
    let committed = std::fs::read_to_string(SCHEMA_PATH).unwrap_or_default();
    assert!(
        committed == generated,
        "export/{SCHEMA_PATH} is out of date with the Rust types of export/src/config.rs; \
         regenerate it with `UPDATE_SCHEMA=1 cargo test -p genom-export --test config` and commit it"
    );
}

fn validator() -> jsonschema::Validator {
    let text = std::fs::read_to_string(SCHEMA_PATH).expect("committed schema is readable");
    let schema: Value = serde_json::from_str(&text).expect("schema is JSON");
    jsonschema::meta::validate(&schema).expect("schema is a valid JSON Schema");
    jsonschema::options()
        .should_validate_formats(true)
        .build(&schema)
        .expect("schema compiles")
}

#[test]
fn every_spec_config_validates_against_the_schema() {
    let validator = validator();
    for path in specs() {
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
