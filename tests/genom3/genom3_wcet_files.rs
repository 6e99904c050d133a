//! The WCET side files written for real components of the GenoM3 corpus
//! (`tests/fixtures/genom3/wcet/`, see docs/genom3.md, "WCET files for the
//! corpus") load against their component: no entry is a `bad-wcet`, no
//! `missing-wcet` advice is left, and every codel, the tasks' permanent
//! codels included (which `missing-wcet` does not look at), has a WCET.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::print_stderr)] // test support code; skips are said on stderr

use crate::common;

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use genom_model::Code;
use genom3_frontend::Genom3Options;
use serde_json::Value;

const STUBS: &str = "tests/fixtures/genom3/include";
const WCETS: &str = "tests/fixtures/genom3/wcet";

/// Each WCET file with its component, relative to the corpus.
const FILES: [(&str, &str); 6] = [
    ("nhfc.wcet", "nhfc-genom3/nhfc.gen"),
    ("uavatt.wcet", "uavatt-genom3/uavatt.gen"),
    ("rmp440.wcet", "infuse_rmp440-genom3/rmp440.gen"),
    ("uavpos.wcet", "uavpos-genom3/uavpos.gen"),
    ("uavvs.wcet", "uavvs-genom3/uavvs.gen"),
    ("T265.wcet", "T265-genom3/T265.gen"),
];

/// The pairs (WCET file, component) whose component is in the corpus.
fn pairs() -> Vec<(PathBuf, PathBuf)> {
    let Some(dir) = common::genom3_corpus() else {
        return Vec::new();
    };
    FILES
        .iter()
        .filter_map(|(wcet, component)| {
            let wcet = Path::new(WCETS).join(wcet);
            assert!(wcet.is_file(), "{} is missing", wcet.display());
            let path = dir.join(component);
            if path.is_file() {
                Some((wcet, path))
            } else {
                eprintln!("SKIPPED: {} is not in the corpus", path.display());
                None
            }
        })
        .collect()
}

#[test]
fn the_corpus_wcet_files_have_no_bad_entry_and_leave_no_codel_without_wcet() {
    for (wcet, path) in pairs() {
        let out = Command::cargo_bin("genom-check")
            .expect("binary is built")
            .env_remove("GENOM_INCLUDE_PATH")
            .args(["--format", "json", "--static-only", "-I", STUBS, "--wcet"])
            .arg(&wcet)
            .arg(&path)
            .output()
            .unwrap();
        let doc: Value = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
            panic!(
                "{e}: {}{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            )
        });
        let file = &doc["files"][0];
        assert_eq!(file["dialect"], "genom3", "{}", path.display());
        let codes: Vec<&str> = file["diagnostics"]
            .as_array()
            .unwrap()
            .iter()
            .map(|d| d["code"].as_str().unwrap())
            .collect();
        for code in ["bad-wcet", "missing-wcet"] {
            assert!(
                !codes.contains(&code),
                "{} with {}: {file:#}",
                path.display(),
                wcet.display()
            );
        }
    }
}

#[test]
fn the_corpus_wcet_files_give_every_codel_a_wcet() {
    for (wcet, path) in pairs() {
        let options = Genom3Options {
            include_dirs: vec![PathBuf::from(STUBS)],
            use_env_include_path: false,
            wcet_file: Some(wcet.clone()),
            ..Genom3Options::default()
        };
        let out = genom3_frontend::load(&path, &options).unwrap();
        assert!(out.is_complete(), "{}", path.display());
        assert!(
            !out.diagnostics.iter().any(|d| d.code == Code::BadWcet),
            "{}: {:#?}",
            wcet.display(),
            out.diagnostics
        );
        let c = out.component.unwrap();
        // Codels of services: activities' states, validate and function
        // codels.
        let without: Vec<String> = c
            .codels
            .values()
            .filter(|k| k.wcet.is_none())
            .map(|k| format!("{}.{}", c.services[k.service].name.name, k.name.name))
            .collect();
        assert!(without.is_empty(), "{}: {without:?}", wcet.display());
        // Permanent codels of tasks.
        let g = c.genom3.as_ref().unwrap();
        let mut permanent = 0;
        for task in &g.tasks {
            for codel in &task.codels {
                permanent += 1;
                assert!(
                    codel.wcet.is_some(),
                    "{}: task `{}`, codel `{}` has no WCET",
                    wcet.display(),
                    c.threads[task.thread].name.name,
                    codel.function.name
                );
            }
        }
        assert!(permanent > 0, "{}", path.display());
    }
}
