//! Snapshot tests over `tests/fixtures/{valid,invalid}/*.gen`: each snapshot
//! holds the fixture's source and its rendered diagnostics (colour off,
//! width 100). Valid fixtures have no error and no warning; each invalid
//! fixture is named after the code it must produce (`CODE.what.gen`). A
//! `NAME.wcet` next to a fixture is loaded as its WCET side file.

#![allow(clippy::expect_used, clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use genom_model::{Code, Severity};
use genom_render::human::{HumanOptions, render_diagnostic};
use genom3_frontend::{FsLoader, Genom3Return, Loader, add_wcet_file, load_with};

/// Loads a fixture by its path relative to the crate (stable in snapshots).
fn load_fixture(path: &Path) -> Genom3Return {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let relative: PathBuf = path.strip_prefix(root).unwrap_or(path).to_path_buf();
    let text = FsLoader.load(path).expect("fixture is readable");
    let mut out = load_with(&relative, text, &[], &FsLoader);
    let wcet = path.with_extension("wcet");
    if wcet.is_file() {
        let text = std::fs::read_to_string(&wcet).expect("wcet is readable");
        add_wcet_file(&mut out, &relative.with_extension("wcet"), text);
    }
    out
}

fn render(out: &Genom3Return) -> String {
    out.diagnostics
        .iter()
        .map(|d| {
            format!(
                "{}\n",
                render_diagnostic(&out.sources, d, HumanOptions::default())
            )
        })
        .collect()
}

fn snapshot_text(path: &Path, report: &str) -> String {
    let source = std::fs::read_to_string(path).expect("fixture is readable");
    format!("{source}\n----- report -----\n{report}")
}

#[test]
fn valid_fixtures_have_no_errors_or_warnings() {
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).unwrap();
    insta::glob!("fixtures/valid/*.gen", |path| {
        let out = load_fixture(path);
        let report = render(&out);
        assert!(
            out.diagnostics
                .iter()
                .all(|d| d.severity == Severity::Advice),
            "{report}"
        );
        insta::assert_snapshot!(snapshot_text(path, &report));
    });
}

#[test]
fn invalid_fixtures_report_the_code_they_are_named_after() {
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).unwrap();
    insta::glob!("fixtures/invalid/*.gen", |path| {
        let out = load_fixture(path);
        let report = render(&out);
        let name = path.file_name().unwrap().to_string_lossy();
        let expected: Code = name
            .split('.')
            .next()
            .unwrap()
            .parse()
            .expect("named after a code");
        assert!(
            out.diagnostics.iter().any(|d| d.code == expected),
            "{} should report `{expected}`:\n{report}",
            path.display()
        );
        insta::assert_snapshot!(snapshot_text(path, &report));
    });
}

#[test]
fn demo_lowers_into_the_model() {
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).unwrap();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/valid/demo.gen");
    let out = load_fixture(&path);
    let c = out.component.as_ref().expect("a component");
    let g = c.genom3.as_deref().expect("genom3 facts");
    assert_eq!(c.name.name, "demo");
    assert_eq!(c.version.as_deref(), Some("1.2"));
    // Tasks are threads; the period is the constant expression with units.
    let main = c.thread_named("main").expect("task main");
    assert_eq!(c.threads[main].period.map(|d| d.ns), Some(5_000_000));
    assert_eq!(c.threads[main].priority, 200);
    assert_eq!(c.threads[main].stack, Some(64 * 1024));
    let io = c.thread_named("io").expect("task io");
    let io_task = g.tasks.iter().find(|t| t.thread == io).expect("io facts");
    assert!(io_task.codels[0].is_async);
    assert_eq!(io_task.delay.map(|d| d.ns), Some(1_000_000));
    // Services: attributes and functions are control-only, activities run
    // on their task with one codel per state.
    let mv = c.service_named("move").expect("activity move");
    assert_eq!(c.services[mv].thread.map(|r| r.id), Some(main));
    let states: Vec<&str> = c.services[mv]
        .codels
        .iter()
        .map(|&k| c.codels[k].name.name.as_str())
        .collect();
    assert_eq!(states, ["validate", "start", "run", "again", "stop"]);
    assert!(c.services[mv].start.is_some() && c.services[mv].control.is_some());
    let reports: Vec<&str> = c.services[mv]
        .reports
        .iter()
        .map(|r| r.name.as_str())
        .collect();
    assert_eq!(reports, ["demo::e_busy", "geom::out_of_range"]);
    // `pause::` is recorded, `ether` ends.
    let start = c.services[mv].start.unwrap();
    let info = g.codels.iter().find(|i| i.codel == start).unwrap();
    assert!(info.fsm.yields[0].pause);
    // Built-in genom services and provided interfaces are inlined.
    assert!(c.service_named("kill").is_some());
    assert!(c.service_named("calibrate").is_some());
    assert_eq!(g.remotes.len(), 1);
    // `uses` flips port directions: motor's `in command` is our output.
    let command = g.ports.iter().find(|p| p.name.name == "command").unwrap();
    assert!(command.is_out);
    // An output port a codel writes is published after it (`update`).
    let track = c.service_named("track").unwrap();
    let track_start = c.services[track].start.unwrap();
    let published: Vec<&str> = c.codels[track_start]
        .update
        .iter()
        .map(|d| d.text.as_str())
        .collect();
    assert_eq!(published, ["position"]);
    assert!(c.codels[c.services[mv].start.unwrap()].update.is_empty());
    assert_eq!(c.services[track].exports.len(), 1);
    // ids blocks merge into one structure.
    let ids: Vec<_> = c.structures.values().filter(|s| s.name == "ids").collect();
    assert_eq!(ids.len(), 1);
    // WCETs from the side file.
    let run = c.codel_named(mv, "run").unwrap();
    assert_eq!(c.codels[run].wcet.map(|d| d.ns), Some(1_500_000));
    assert_eq!(io_task.codels.len(), 1);
    let main_task = g.tasks.iter().find(|t| t.thread == main).unwrap();
    let wait = main_task
        .codels
        .iter()
        .find(|k| k.states[0].name == "wait")
        .unwrap();
    assert_eq!(wait.wcet.map(|d| d.ns), Some(300_000));
    // Constants are evaluated.
    let max = c
        .constants
        .iter()
        .find(|k| k.name == "geom::max_points")
        .unwrap();
    assert_eq!(max.value, Some(genom_model::component::Value::Int(16)));
}

#[test]
fn interface_only_files_have_no_component_and_no_error() {
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).unwrap();
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/valid/interface-only.gen");
    let out = load_fixture(&path);
    assert!(out.is_interface_only);
    assert!(out.component.is_none());
    assert!(
        out.diagnostics
            .iter()
            .all(|d| d.code != Code::MissingComponent)
    );
}
