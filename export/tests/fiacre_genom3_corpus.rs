//! The `fiacre` export of the GenoM3 corpus (`../shared/corpus/genom3`,
//! next to the repository; each test says SKIPPED without it): every
//! component with a WCET file (`tests/fixtures/genom3/wcet/`) is exported
//! timed, every other one in the untimed reading, and each export parses
//! with the Fiacre reader of `genom_oracles::fiacre` and names in its
//! properties only states of its own processes; `uavatt`, `uavpos` and
//! `uavvs` are snapshot-tested.

#![allow(clippy::expect_used, clippy::print_stderr)] // test support; a skipped test says why

mod common;

use std::path::{Path, PathBuf};

use genom_checker::CheckOptions;
use genom_export::{Exported, Format};
use genom_oracles::fiacre::parse;

const CORPUS: &str = "../../shared/corpus/genom3";
const WCET: &str = "../tests/fixtures/genom3/wcet";

/// The corpus components with a WCET file.
const TIMED: [&str; 6] = ["uavatt", "uavpos", "uavvs", "nhfc", "T265", "rmp440"];

/// Every component's `.gen` file of the corpus, sorted, or `None` (said on stderr)
/// without the corpus.
fn corpus() -> Option<Vec<PathBuf>> {
    let Ok(dirs) = std::fs::read_dir(CORPUS) else {
        eprintln!("SKIPPED: the GenoM3 corpus is not at {CORPUS} (a clean clone)");
        return None;
    };
    let mut out = Vec::new();
    for d in dirs {
        let d = d.expect("an entry").path();
        let Ok(files) = std::fs::read_dir(&d) else {
            continue;
        };
        for f in files {
            let f = f.expect("an entry").path();
            // A component, not an interface included by one.
            let text = std::fs::read_to_string(&f).unwrap_or_default();
            let component = text.lines().any(|l| l.starts_with("component "));
            if f.extension().is_some_and(|e| e == "gen") && component {
                out.push(f);
            }
        }
    }
    out.sort();
    Some(out)
}

/// The component's name in [`TIMED`] (the file's stem).
fn stem(path: &Path) -> String {
    path.file_stem()
        .expect("a file name")
        .to_string_lossy()
        .into_owned()
}

/// The check of `path` (with its WCET file when it has one; bounded) and
/// its export.
fn export(path: &Path) -> (common::CheckResult, Exported) {
    let name = stem(path);
    let include = [PathBuf::from("../tests/fixtures/genom3/include")];
    let wcet = TIMED
        .contains(&name.as_str())
        .then(|| Path::new(WCET).join(format!("{name}.wcet")));
    // Only the component matters here (the export's header says what the
    // check found): the checks are bounded, which leaves nhfc's and
    // rmp440's timed explorations (some 90 s each) incomplete.
    let options = CheckOptions::new().max_states(50_000);
    let r = common::check_genom3(path, &include, wcet.as_deref(), &options);
    let e = common::export_as_cli(&r, Format::Fiacre)
        .unwrap_or_else(|e| panic!("{}: refused: {e}", path.display()));
    (r, e)
}

#[test]
fn every_corpus_component_is_exported_and_parses() {
    let Some(files) = corpus() else { return };
    let mut timed = 0;
    for path in &files {
        let what = path.display().to_string();
        let (_, e) = export(path);
        let prog = parse(&e.main).unwrap_or_else(|err| panic!("{what}: {err}"));
        let root = prog.components.last().expect("a root component");
        for p in &prog.properties {
            assert!(prog.asserts.contains(&p.name), "{what}: {}", p.name);
            let words: Vec<&str> = p.formula.split_whitespace().collect();
            for w in words.windows(6) {
                if w[0] != root.name || w[1] != "/" || w[4] != "state" {
                    continue;
                }
                let k: usize = w[2].parse().expect("an instance number");
                let proc_ = prog
                    .processes
                    .iter()
                    .find(|q| q.name == root.par[k - 1].name)
                    .expect("a process");
                assert!(proc_.states.iter().any(|s| s == w[5]), "{what}: {}", p.name);
            }
        }
        let watchers = prog
            .processes
            .iter()
            .filter(|p| p.name.starts_with("watch_"))
            .count();
        if TIMED.contains(&stem(path).as_str()) {
            assert!(e.notes.is_empty(), "{what}: timed");
            assert!(watchers > 0, "{what}: a periodic task's watcher");
            timed += 1;
        } else {
            assert!(e.main.contains("UNTIMED READING"), "{what}");
            assert!(!e.notes.is_empty(), "{what}: the untimed note");
            assert_eq!(watchers, 0, "{what}: no watcher untimed");
        }
    }
    assert_eq!(timed, TIMED.len(), "every component with a WCET file");
}

#[test]
fn snapshots_of_the_small_corpus_components() {
    let Some(files) = corpus() else { return };
    for name in ["uavatt", "uavpos", "uavvs"] {
        let path = files
            .iter()
            .find(|p| stem(p) == name)
            .expect("in the corpus");
        let (_, e) = export(path);
        // The header names the checked file by its path: keep its name.
        let text = e
            .main
            .replace(&path.display().to_string(), &format!("{name}.gen"));
        insta::assert_snapshot!(format!("fiacre_genom3_corpus__{name}"), text);
    }
}
