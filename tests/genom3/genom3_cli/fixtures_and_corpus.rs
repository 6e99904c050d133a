//! The front-end's fixtures and the corpus through the command line, and
//! the GenoM3 wording of reports: `explain`, termination, a static-only
//! check's component, the assumptions of timed verdicts, a stopped timed
//! exploration.

use crate::common;

use std::path::{Path, PathBuf};

use serde_json::Value;

use super::support::*;

fn fixtures(kind: &str) -> Vec<PathBuf> {
    let mut all: Vec<PathBuf> = std::fs::read_dir(format!("{FIXTURES}/{kind}"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "gen"))
        .collect();
    all.sort();
    all
}

/// Checks a front-end fixture statically as GenoM3, with the WCET side
/// file next to it if there is one.
fn check_fixture(path: &Path) -> (i32, Value) {
    let shown = path.to_string_lossy();
    let wcet = path.with_extension("wcet");
    let wcet = wcet.to_string_lossy();
    let mut args = vec!["--static-only", "--dialect", "genom3"];
    if path.with_extension("wcet").is_file() {
        args.extend(["--wcet", &wcet]);
    }
    args.push(&shown);
    json(&args)
}

#[test]
fn the_front_end_fixtures_give_their_codes_through_the_cli() {
    let invalid = fixtures("invalid");
    assert!(invalid.len() >= 20);
    for path in invalid {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let code = name.split('.').next().unwrap();
        let (status, file) = check_fixture(&path);
        let found: Vec<String> = ["error", "warning", "advice"]
            .iter()
            .flat_map(|s| codes(&file, s))
            .collect();
        assert!(found.iter().any(|c| c == code), "{name}: {found:?}");
        let errors = !codes(&file, "error").is_empty();
        assert_eq!(status, i32::from(errors), "{name}: {found:?}");
        assert_eq!(file["dialect"], "genom3");
    }
    for path in fixtures("valid") {
        let (status, file) = check_fixture(&path);
        assert_eq!(status, 0, "{}: {file:#}", path.display());
        assert!(codes(&file, "warning").is_empty(), "{file:#}");
    }
}

#[test]
fn explain_knows_the_genom3_codes() {
    let out = genom_check()
        .args(["explain", "stop-no-ether"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&out.stdout).contains("ether"));
}

#[test]
fn every_real_component_of_the_corpus_checks_without_error() {
    let Some(dir) = common::genom3_corpus() else {
        return;
    };
    let mut components: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir() && !p.ends_with("genom3"))
        .flat_map(|d| std::fs::read_dir(d).unwrap().map(|e| e.unwrap().path()))
        .filter(|p| p.extension().is_some_and(|e| e == "gen"))
        .collect();
    components.sort();
    components.push(dir.join("genom3/regress/component.gen"));
    assert!(components.len() >= 16, "{components:?}");
    for path in &components {
        let shown = path.to_string_lossy();
        let (status, file) = json(&["--static-only", "-I", STUBS, &shown]);
        assert_eq!(status, 0, "{shown}: {file:#}");
        assert_eq!(file["dialect"], "genom3", "{shown}");
        assert!(codes(&file, "warning").is_empty(), "{shown}: {file:#}");
    }
    // Interface-only files: loaded, no `missing-component`.
    for file in [
        "genom3/regress/datatypes.gen",
        "genom3/templates/common/genom.gen",
    ] {
        let path = dir.join(file);
        if !path.is_file() {
            eprintln!("SKIPPED: {} is not in the corpus", path.display());
            continue;
        }
        let shown = path.to_string_lossy();
        let (status, report) = json(&["--dialect", "genom3", "--static-only", &shown]);
        assert_eq!(status, 0, "{shown}: {report:#}");
    }
}

#[test]
fn no_termination_speaks_genom3_to_a_genom3_file() {
    let (status, file) = json(&[
        "--static-only",
        "tests/fixtures/genom3/response/r3_function_lock.gen",
    ]);
    assert_eq!(status, 0);
    let found: Vec<&Value> = file["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|d| d["code"] == "no-termination")
        .collect();
    assert_eq!(found.len(), 1, "{file:#}");
    let text = found[0].to_string();
    assert!(
        text.contains("activity `watch`") && text.contains("`ether`"),
        "{text}"
    );
    assert!(
        !text.contains("`next`") && !text.contains("max-time"),
        "{text}"
    );
}

/// A static-only check of a GenoM3 file still returns its component (the
/// exports and the language server read it).
#[test]
fn a_static_only_genom3_check_keeps_its_component() {
    let options = genom_check::CheckOptions::new().behaviour(false);
    let path = Path::new("tests/fixtures/genom3/response/r1_paused_chain.gen");
    let r = genom_check::check_path(path, &genom_check::Inputs::default(), &options).unwrap();
    assert!(r.component.is_some());
    assert!(r.statistics.is_none(), "nothing was explored");
}

/// A clean or partly clean timed verdict says what it rests on: the WCET
/// file and the instance bound, in the summary, JSON, SARIF and GitHub
/// formats; an untimed check rests on neither.
#[test]
fn timed_verdicts_state_their_assumptions_in_every_format() {
    let source = "tests/fixtures/genom3/timing/f10_restart_fixed.gen";
    let wcet = "tests/fixtures/genom3/timing/f10_restart_fixed.wcet";
    let (status, file) = json(&["--wcet", wcet, source]);
    assert_eq!(status, 0);
    let all = file["assumptions"].as_array().unwrap();
    assert_eq!(all.len(), 2, "{file:#}");
    assert_eq!(all[0]["kind"], "wcet");
    assert_eq!(all[0]["file"], wcet);
    assert_eq!(all[1]["kind"], "instances");
    assert_eq!(all[1]["bound"], 1);
    assert!(
        all[1]["text"]
            .as_str()
            .unwrap()
            .contains("interrupts itself")
    );
    let (_, two) = json(&["--wcet", wcet, "--max-instances", "2", source]);
    assert_eq!(two["assumptions"][1]["bound"], 2);
    let (_, untimed) = json(&[source]);
    assert_eq!(untimed["assumptions"].as_array().unwrap().len(), 0);

    let human = genom_check()
        .args(["--wcet", wcet, source])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&human.stdout);
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with("assuming "))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(line.contains(&format!("its WCET from `{wcet}`")), "{line}");
    assert!(
        line.contains("at most 1 concurrent request of each activity"),
        "{line}"
    );

    let sarif = genom_check()
        .args(["--format", "sarif", "--wcet", wcet, source])
        .output()
        .unwrap();
    let doc: Value = serde_json::from_slice(&sarif.stdout).unwrap();
    let notes = doc["runs"][0]["invocations"][0]["toolExecutionNotifications"]
        .as_array()
        .unwrap();
    assert_eq!(notes.len(), 2);
    assert_eq!(notes[0]["level"], "note");
    assert!(
        notes[1]["message"]["text"]
            .as_str()
            .unwrap()
            .contains("concurrent request")
    );

    let github = genom_check()
        .args(["--format", "github", "--wcet", wcet, source])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&github.stdout);
    assert!(
        text.contains("assuming every codel takes at most its WCET"),
        "{text}"
    );
}

/// `explain` of the codes both languages share speaks GenoM3's words too.
#[test]
fn explain_of_shared_codes_speaks_genom3() {
    for code in [
        "thread-overrun",
        "codel-overrun",
        "incomplete",
        "missing-wcet",
    ] {
        let out = genom_check().args(["explain", code]).output().unwrap();
        assert!(out.status.success(), "{code}");
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains("GenoM3"), "{code}: {text}");
        assert!(text.contains("--wcet"), "{code}: {text}");
        assert!(text.contains("task"), "{code}: {text}");
    }
    for code in ["thread-overrun", "codel-overrun"] {
        let out = genom_check().args(["explain", code]).output().unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains("pause::"), "{code}: {text}");
    }
}

#[test]
fn a_stopped_timed_exploration_counts_the_tasks_the_bound_clears_as_proven() {
    // `fast` (100 µs, waiting at most one of `slow`'s 3.3 ms codels) is
    // cleared by the static bound of its wake-up; `slow` (three 3.3 ms
    // codels in a chain, each possibly behind `fast`'s) is not, and its
    // exploration stops at the state limit: `fast` is proven, `slow` left
    // unproven.
    let dir = tempfile::tempdir().unwrap();
    let text = "component two {
  ids { long x; };
  task fast {
    period 10 ms;
    codel<start> f_start(inout x) yield pause::start;
  };
  task slow {
    period 10 ms;
    codel<start> s_a(inout x) yield b;
    codel<b> s_b(inout x) yield c;
    codel<c> s_c(inout x) yield pause::start;
  };
};
";
    let gen_file = write(dir.path(), "two.gen", text);
    let wcet = write(
        dir.path(),
        "two.wcet",
        "fast.start 100us\nslow.start 3300us\nslow.b 3300us\nslow.c 3300us\n",
    );
    let (_, file) = json(&[
        "--wcet",
        wcet.to_str().unwrap(),
        "--max-states",
        "20",
        gen_file.to_str().unwrap(),
    ]);
    let decided = file["statistics"]["decided_by"].as_array().unwrap();
    assert!(
        decided
            .iter()
            .any(|d| d["engine"] == "bound" && d["services"] == serde_json::json!(["task fast"])),
        "{decided:#?}"
    );
    let diagnostics = file["diagnostics"].as_array().unwrap();
    let help = diagnostics
        .iter()
        .find(|d| d["code"] == "incomplete")
        .and_then(|d| d["help"].as_str())
        .expect("incomplete");
    assert!(
        help.starts_with("left unproven: whether task `slow` can overrun"),
        "{help}"
    );
    assert!(
        help.contains("Proven: task `fast` never overruns"),
        "{help}"
    );
}
