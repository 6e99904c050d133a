//! The `promela` export of GenoM3 components (GenoM3's untimed semantics):
//! on every GenoM3 fixture of the semantics and timing folders, the model is
//! deterministic (two exports are byte-identical), names every activity,
//! task state and service by a marker, and is valid Promela (`spin -a`
//! accepts it, when `spin` is installed; `GENOM_REQUIRE_SPIN=1` makes its
//! absence a failure).

#![allow(clippy::expect_used, clippy::print_stderr)] // test support code

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::CheckResult;
use genom_checker::CheckOptions;
use genom_export::{ExportInput, Format, Verification};

const STUBS: &str = "../tests/fixtures/genom3/include";

/// The GenoM3 fixtures, sorted.
fn fixtures() -> Vec<PathBuf> {
    let mut out = Vec::new();
    for dir in [
        "../tests/fixtures/genom3/semantics",
        "../tests/fixtures/genom3/timing",
    ] {
        let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
            .expect("fixture folder")
            .map(|e| e.expect("entry").path())
            .filter(|p| p.extension().is_some_and(|x| x == "gen"))
            .collect();
        v.sort();
        out.extend(v);
    }
    assert!(out.len() >= 15, "{out:?}");
    out
}

fn check(path: &Path) -> CheckResult {
    let include_dirs = [PathBuf::from(STUBS)];
    let options = CheckOptions::new().behaviour(false);
    common::check_genom3(path, &include_dirs, None, &options)
}

fn promela(result: &CheckResult) -> String {
    let component = result
        .component
        .as_ref()
        .unwrap_or_else(|| panic!("no component: {:#?}", result.diagnostics));
    let verification = Verification {
        verified: true,
        tool_version: "0.0.0-test".to_owned(),
        ..Verification::default()
    };
    let input = ExportInput {
        component,
        sources: &result.sources,
        verification: &verification,
    };
    genom_export::export(Format::Promela, &input)
        .expect("exports")
        .main
}

#[test]
fn the_genom3_model_is_deterministic_and_names_every_state_and_service() {
    for path in fixtures() {
        let result = check(&path);
        let first = promela(&result);
        assert_eq!(first, promela(&check(&path)), "{}", path.display());
        assert!(
            first.starts_with("/* GenoM3's untimed semantics"),
            "{}",
            path.display()
        );
        let c = result.component.as_ref().expect("a component");
        let g = c.genom3.as_deref().expect("GenoM3");
        let activities = c.services.values().any(|s| s.thread.is_some());
        for s in c.services.values() {
            // `abort_activity` succeeds only on an instance: with no
            // activity it never does (f7_attribute_copy, f9_fifo).
            if s.name.name == "abort_activity" && !activities {
                continue;
            }
            let accepted = format!("service `{}` is accepted */", s.name.name);
            let starts = format!("service `{}` starts */", s.name.name);
            assert!(
                first.contains(&accepted) || first.contains(&starts),
                "{}: no marker for `{}`",
                path.display(),
                s.name.name
            );
        }
        for info in &g.codels {
            let codel = &c.codels[info.codel];
            if codel.kind == genom_model::kinds::CodelKind::Control {
                continue;
            }
            let owner = &c.services[codel.service].name.name;
            let marker = format!(
                "codel `{}` of activity `{owner}` (state `{}`) runs */",
                info.fsm.function.name, codel.name.name
            );
            assert!(first.contains(&marker), "{}: {marker}", path.display());
        }
        for task in &g.tasks {
            let name = &c.threads[task.thread].name.name;
            for fsm in &task.codels {
                for state in &fsm.states {
                    let marker = format!(
                        "codel `{}` of task `{name}` (state `{}`) runs */",
                        fsm.function.name, state.name
                    );
                    assert!(first.contains(&marker), "{}: {marker}", path.display());
                }
            }
        }
    }
}

#[test]
fn spin_accepts_the_genom3_model() {
    let present = Command::new("spin")
        .arg("-V")
        .output()
        .is_ok_and(|o| o.status.success());
    if !present {
        let required = std::env::var("GENOM_REQUIRE_SPIN").is_ok_and(|v| v == "1");
        assert!(!required, "GENOM_REQUIRE_SPIN=1 but `spin` is missing");
        eprintln!("note: `spin` not installed: syntax check of the GenoM3 model skipped");
        return;
    }
    let dir = tempfile::tempdir().expect("temporary directory");
    for path in fixtures() {
        let model = promela(&check(&path));
        let file = dir.path().join("model.pml");
        std::fs::write(&file, &model).expect("written");
        let out = Command::new("spin")
            .args(["-a", "-o3", "model.pml"])
            .current_dir(dir.path())
            .output()
            .expect("spin runs");
        let text = String::from_utf8_lossy(&out.stdout).into_owned()
            + &String::from_utf8_lossy(&out.stderr);
        assert!(
            out.status.success() && !text.contains("error"),
            "{}: spin -a failed:\n{text}\n{model}",
            path.display()
        );
        assert!(dir.path().join("pan.c").is_file(), "{}", path.display());
        std::fs::remove_file(dir.path().join("pan.c")).expect("removed");
    }
}
