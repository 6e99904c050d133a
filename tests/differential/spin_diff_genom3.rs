//! Differential test of the GenoM3 engine against SPIN: GenoM3 components
//! (the semantics and timing fixtures, read untimed, the corpus components
//! within the state budget, four written here, and generated ones) are checked by genom-check's
//! untimed GenoM3 engine and, exported with `export promela` (GenoM3's
//! untimed semantics, written independently of the engine), by SPIN. Both
//! must give the same verdicts: the services never accepted or started
//! (`dead-service`, built-ins aside) and the codels of activities and
//! tasks that no execution runs (`unreachable-codel`).
//!
//! The corpus is `../shared/corpus/genom3` (see `tests/common`), or the
//! folder `GENOM3_CORPUS` names. `GENOM_SPIN_KEEP=DIR` keeps the models.
//!
//! Needs `spin` and `gcc` on the `PATH`. Without them the test prints a note
//! and passes, unless `GENOM_REQUIRE_SPIN=1` (CI), when it fails.

#![allow(clippy::expect_used, clippy::print_stderr)] // test support code

use super::genom3_untimed::{HAND, Ours, Verdicts, files, ours};

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use genom_export::{ExportInput, Format, Verification, export};
use genom_generate::{Genom3Config, generate_genom3};
use genom_model::component::Component;

/// Generated GenoM3 components compared (seeds 0..GENERATED, untimed).
const GENERATED: u64 = 120;
/// Worker threads (the machine's cores are shared).
const WORKERS: usize = 2;
/// SPIN's memory budget in megabytes (`-DMEMLIM`, with the DFS stack of
/// `-m` and the hash table of `-w`): a component whose state space does not
/// fit is skipped and listed.
const MEMLIM_MB: u32 = 64;

/// What happened to one component.
enum Outcome {
    /// Both sides answered.
    Compared(Box<Case>),
    /// SPIN's state space exceeded the budget.
    OverBudget(String),
    /// No component in the file (an interface).
    NoComponent,
}

/// One component, what both sides said.
struct Case {
    name: String,
    model: String,
    ours: Verdicts,
    spin: Verdicts,
    states: String,
}

fn tool_present(tool: &str, arg: &str) -> bool {
    Command::new(tool)
        .arg(arg)
        .output()
        .is_ok_and(|o| o.status.success())
}

fn run(dir: &Path, program: &str, args: &[&str]) -> (bool, String) {
    let out = Command::new(program)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the tool runs");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.success(), text)
}

fn run_ok(dir: &Path, program: &str, args: &[&str]) -> String {
    let (ok, text) = run(dir, program, args);
    assert!(ok, "{program} {args:?} failed:\n{text}");
    text
}

/// The markers of a model: `hidden byte m_N;  /* WHAT */`, N to WHAT.
fn marker_table(model: &str) -> BTreeMap<usize, String> {
    let mut out = BTreeMap::new();
    for line in model.lines() {
        let Some(rest) = line.strip_prefix("hidden byte m_") else {
            continue;
        };
        let Some((n, what)) = rest.split_once(";  /* ") else {
            continue;
        };
        let what = what.trim_end_matches(" */");
        out.insert(n.parse().expect("a number"), what.to_owned());
    }
    out
}

/// The markers SPIN reports unreached: `"m_N = 1"` in its report.
fn unreached_markers(report: &str) -> BTreeSet<usize> {
    let mut out = BTreeSet::new();
    for (at, _) in report.match_indices("\"m_") {
        let rest = &report[at + 3..];
        let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
        if !digits.is_empty() && rest[digits.len()..].starts_with(" = 1\"") {
            out.insert(digits.parse().expect("a number"));
        }
    }
    out
}

/// SPIN's verdicts on the model, `None` over the memory budget.
fn spin(dir: &Path, c: &Component, model: &str) -> Option<(Verdicts, String)> {
    std::fs::create_dir_all(dir).expect("work directory");
    std::fs::write(dir.join("model.pml"), model).expect("model written");
    run_ok(dir, "spin", &["-a", "-o3", "model.pml"]);
    let memlim = format!("-DMEMLIM={MEMLIM_MB}");
    run_ok(
        dir,
        "gcc",
        &[
            "-O0",
            "-DSAFETY",
            "-DNOREDUCE",
            &memlim,
            "-o",
            "pan",
            "pan.c",
        ],
    );
    let pan = dir.join("pan");
    let (_, report) = run(
        dir,
        pan.to_str().expect("UTF-8 path"),
        &["-m500000", "-w19"],
    );
    if report.contains("reached -DMEMLIM bound") || report.contains("max search depth too small") {
        return None;
    }
    let errors: Vec<&str> = report.lines().filter(|l| l.starts_with("pan:")).collect();
    for bad in ["invalid end state", "VECTORSZ", "assertion violated"] {
        let found = errors.iter().any(|l| l.contains(bad)) || report.contains("error: ");
        assert!(!found, "SPIN: {bad}\n{model}\n{report}");
    }
    assert!(report.contains("errors: 0"), "SPIN failed:\n{report}");
    let unreached = report
        .find("unreached in proctype")
        .map_or("", |at| &report[at..]);
    let missed = unreached_markers(unreached);
    // A description is never reached iff every marker carrying it is not.
    let mut reached: BTreeMap<String, bool> = BTreeMap::new();
    for (n, what) in marker_table(model) {
        *reached.entry(what).or_insert(false) |= !missed.contains(&n);
    }
    let verdicts = Verdicts::of_facts(c, &reached);
    let stored = report
        .lines()
        .find(|l| l.contains("states, stored"))
        .map_or(String::new(), |l| l.trim().to_owned());
    Some((verdicts, stored))
}

fn one(path: &Path, work: &Path) -> Outcome {
    let (component, ours, states) = match ours(path) {
        Ours::Verdicts(c, v, n) => (c, v, n),
        Ours::OverBudget => {
            return Outcome::OverBudget(format!("{} (genom-check)", path.display()));
        }
        Ours::NoComponent => return Outcome::NoComponent,
    };
    let name = path.to_string_lossy().replace(['/', '\\'], "_");
    let verification = Verification::default();
    let sources = genom_model::SourceMap::default();
    let input = ExportInput {
        component: &component,
        sources: &sources,
        verification: &verification,
    };
    let model = export(Format::Promela, &input).expect("exports").main;
    let Some((spin, stored)) = spin(&work.join(&name), &component, &model) else {
        return Outcome::OverBudget(format!("{} (SPIN)", path.display()));
    };
    Outcome::Compared(Box::new(Case {
        name,
        model,
        ours,
        spin,
        states: format!("genom-check {states} states, SPIN {stored}"),
    }))
}

#[test]
#[cfg_attr(
    not(genom_spin),
    ignore = "needs `spin` and `gcc` on the PATH when the tests are built (GENOM_REQUIRE_SPIN=1 makes their absence a failure)"
)]
fn spin_agrees_with_the_genom3_engine() {
    let required = std::env::var("GENOM_REQUIRE_SPIN").is_ok_and(|v| v == "1");
    if !(tool_present("spin", "-V") && tool_present("gcc", "--version")) {
        assert!(
            !required,
            "GENOM_REQUIRE_SPIN=1 but `spin` or `gcc` is missing"
        );
        eprintln!("note: `spin` or `gcc` not installed: SPIN GenoM3 differential test skipped");
        return;
    }
    let started = Instant::now();
    let temp = tempfile::tempdir().expect("temporary directory");
    let keep = std::env::var_os("GENOM_SPIN_KEEP").map(PathBuf::from);
    let work = keep.as_deref().unwrap_or(temp.path());
    let mut jobs = files();
    let hand = work.join("hand");
    std::fs::create_dir_all(&hand).expect("work directory");
    for (name, text) in HAND {
        let path = hand.join(format!("{name}.gen"));
        std::fs::write(&path, text).expect("written");
        jobs.push(path);
    }
    for seed in 0..GENERATED {
        let generated = generate_genom3(&Genom3Config::small(seed));
        let path = hand.join(format!("generated-{seed}.gen"));
        std::fs::write(&path, generated.r#gen).expect("written");
        jobs.push(path);
    }
    let next = AtomicUsize::new(0);
    let outcomes = Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..WORKERS {
            scope.spawn(|| {
                while let Some(job) = jobs.get(next.fetch_add(1, Ordering::SeqCst)) {
                    let o = one(job, work);
                    outcomes.lock().expect("not poisoned").push(o);
                }
            });
        }
    });
    let mut cases = Vec::new();
    let mut skipped = Vec::new();
    for o in outcomes.into_inner().expect("not poisoned") {
        match o {
            Outcome::Compared(c) => cases.push(*c),
            Outcome::OverBudget(p) => skipped.push(p),
            Outcome::NoComponent => {}
        }
    }
    cases.sort_by(|a, b| a.name.cmp(&b.name));
    skipped.sort();
    report(&cases, &skipped, started);
}

fn report(cases: &[Case], skipped: &[String], started: Instant) {
    let same = cases.iter().filter(|c| c.ours == c.spin).count();
    let count = |f: &dyn Fn(&Verdicts) -> bool| cases.iter().filter(|c| f(&c.ours)).count();
    eprintln!(
        "SPIN agreement on GenoM3 components: {same}/{} ({} with a dead service, {} with an \
         unreachable codel), {:.1} s; over SPIN's {MEMLIM_MB} MB budget, skipped: {skipped:?}",
        cases.len(),
        count(&|v| !v.dead.is_empty()),
        count(&|v| !v.unreachable.is_empty()),
        started.elapsed().as_secs_f64()
    );
    assert!(
        cases.len() >= 100,
        "too few components compared: {}",
        cases.len()
    );
    let keep = std::env::var_os("GENOM_SPIN_KEEP").map(PathBuf::from);
    let mut failures = String::new();
    for case in cases.iter().filter(|c| c.ours != c.spin) {
        if let Some(dir) = &keep {
            std::fs::create_dir_all(dir).expect("keep directory");
            std::fs::write(dir.join(format!("{}.pml", case.name)), &case.model).expect("kept");
        }
        failures.push_str(&format!(
            "\n== {} ({})\ngenom-check: {:?}\nSPIN:        {:?}\n",
            case.name, case.states, case.ours, case.spin
        ));
    }
    assert!(failures.is_empty(), "SPIN disagrees:{failures}");
}
