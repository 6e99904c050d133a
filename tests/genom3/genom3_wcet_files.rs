//! The WCET side files written for real components of the GenoM3 corpus
//! (`tests/fixtures/genom3/wcet/`, see docs/genom3.md, "WCET files for the
//! corpus") load against their component: no entry is a `bad-wcet`, no
//! `missing-wcet` advice is left, and every codel, the tasks' permanent
//! codels included (which `missing-wcet` does not look at), has a WCET.
//! And `wcet-template` writes, for every fixture and corpus component, a
//! file `--wcet` accepts unchanged, and which gives every codel a WCET once
//! its `?` are filled in.

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
const FILES: [(&str, &str); 8] = [
    ("nhfc.wcet", "nhfc-genom3/nhfc.gen"),
    ("uavatt.wcet", "uavatt-genom3/uavatt.gen"),
    ("rmp440.wcet", "infuse_rmp440-genom3/rmp440.gen"),
    ("uavpos.wcet", "uavpos-genom3/uavpos.gen"),
    ("uavvs.wcet", "uavvs-genom3/uavvs.gen"),
    ("T265.wcet", "T265-genom3/T265.gen"),
    ("maneuver.wcet", "maneuver-genom3/maneuver.gen"),
    ("rotorcraft.wcet", "rotorcraft-genom3/rotorcraft.gen"),
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
        let (without, permanent) = codels_without_wcet(&c);
        assert!(without.is_empty(), "{}: {without:?}", wcet.display());
        assert!(permanent > 0, "{}", path.display());
    }
}

/// The codels without WCET (services' codels as `OWNER.STATE`, then the
/// tasks' permanent codels as `task T codel f`), and how many permanent
/// codels there are.
fn codels_without_wcet(c: &genom_model::component::Component) -> (Vec<String>, usize) {
    let mut without: Vec<String> = c
        .codels
        .values()
        .filter(|k| k.wcet.is_none())
        .map(|k| format!("{}.{}", c.services[k.service].name.name, k.name.name))
        .collect();
    let g = c.genom3.as_ref().unwrap();
    let mut permanent = 0;
    for task in &g.tasks {
        for codel in &task.codels {
            permanent += 1;
            if codel.wcet.is_none() {
                let name = &c.threads[task.thread].name.name;
                without.push(format!("task {name} codel {}", codel.function.name));
            }
        }
    }
    (without, permanent)
}

/// Loads `path` with the WCET file `wcet`; its component and the
/// `bad-wcet` diagnostics.
fn load_with(path: &Path, wcet: &Path) -> (genom_model::component::Component, usize) {
    let options = Genom3Options {
        include_dirs: vec![PathBuf::from(STUBS)],
        use_env_include_path: false,
        wcet_file: Some(wcet.to_owned()),
        ..Genom3Options::default()
    };
    let out = genom3_frontend::load(path, &options).unwrap();
    let bad = out
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::BadWcet)
        .count();
    (out.component.unwrap(), bad)
}

fn template_of(path: &Path) -> std::process::Output {
    Command::cargo_bin("genom-check")
        .expect("binary is built")
        .env_remove("GENOM_INCLUDE_PATH")
        .args(["wcet-template", "-I", STUBS])
        .arg(path)
        .output()
        .unwrap()
}

#[test]
fn a_wcet_template_is_accepted_as_is_and_filled_in_gives_every_codel_a_wcet() {
    let mut files: Vec<PathBuf> = Vec::new();
    for dir in ["semantics", "timing", "response"] {
        let dir = Path::new("tests/fixtures/genom3").join(dir);
        let mut found: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "gen"))
            .collect();
        found.sort();
        files.extend(found);
    }
    if let Some(corpus) = common::genom3_corpus() {
        let mut found: Vec<PathBuf> = std::fs::read_dir(&corpus)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|d| d.is_dir() && !d.ends_with("genom3"))
            .flat_map(|d| std::fs::read_dir(d).unwrap().map(|e| e.unwrap().path()))
            .filter(|p| p.extension().is_some_and(|x| x == "gen"))
            .collect();
        found.sort();
        files.extend(found);
    }
    let temp = tempfile::tempdir().unwrap();
    let (template, filled) = (temp.path().join("t.wcet"), temp.path().join("f.wcet"));
    for path in &files {
        let out = template_of(path);
        let interface = String::from_utf8_lossy(&out.stderr).contains("has no component");
        if out.status.code() == Some(1) && interface {
            continue;
        }
        assert_eq!(out.status.code(), Some(0), "{}: {out:?}", path.display());
        let text = String::from_utf8(out.stdout).unwrap();
        std::fs::write(&template, &text).unwrap();
        let (c, bad) = load_with(path, &template);
        assert_eq!(
            bad,
            0,
            "{}: the template as written\n{text}",
            path.display()
        );
        let (without, permanent) = codels_without_wcet(&c);
        let all = c.codels.len() + permanent;
        assert_eq!(without.len(), all, "{}: `?` gives no WCET", path.display());
        let lines: Vec<String> = text
            .lines()
            .map(|l| l.replacen("  ?    #", "  1us  #", 1))
            .collect();
        std::fs::write(&filled, lines.join("\n")).unwrap();
        let (c, bad) = load_with(path, &filled);
        assert_eq!(bad, 0, "{}", path.display());
        let (without, _) = codels_without_wcet(&c);
        assert!(
            without.is_empty(),
            "{}: {without:?}\n{text}",
            path.display()
        );
    }
    assert!(files.len() >= 40, "{} files", files.len());
}

#[test]
fn a_wcet_template_is_refused_for_the_dialect_and_never_written_over_an_input() {
    let out = template_of(Path::new("specs/pilot.gen"));
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("own `wcet:`"));
    let temp = tempfile::tempdir().unwrap();
    let copy = temp.path().join("f6.gen");
    std::fs::copy(
        "tests/fixtures/genom3/semantics/f6_interrupt_stop.gen",
        &copy,
    )
    .unwrap();
    let before = std::fs::read(&copy).unwrap();
    let out = Command::cargo_bin("genom-check")
        .unwrap()
        .args(["wcet-template", "-o"])
        .arg(&copy)
        .arg(&copy)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    assert_eq!(
        std::fs::read(&copy).unwrap(),
        before,
        "the input is unchanged"
    );
    let written = temp.path().join("f6.wcet");
    let out = Command::cargo_bin("genom-check")
        .unwrap()
        .args(["wcet-template", "-o"])
        .arg(&written)
        .arg(&copy)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(
        std::fs::read_to_string(&written)
            .unwrap()
            .contains("servo.start")
    );
}
