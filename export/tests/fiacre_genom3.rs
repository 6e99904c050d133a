//! The `fiacre` export of GenoM3 components (docs/exports/fiacre.md,
//! "GenoM3 components"): snapshots of the timing fixtures it models; every
//! export parses with the Fiacre reader of `genom_oracles::fiacre`
//! (written from the language's reference, not from the emitter) and
//! names in its properties only states of its own processes; and the
//! model *behaves* as the timed GenoM3 engine says: the interpreter of
//! `genom_oracles::fiacre` explores it (clocks as zones) and the tasks
//! whose watcher can stay `late` for a positive time (the first overrun of
//! a run, as the engine stops there) are exactly the tasks with a
//! `thread-overrun` (or a `codel-overrun` with a trace), on the timing
//! fixtures and on small generated components.

#![allow(clippy::expect_used, clippy::print_stdout)] // test support code outside #[test] functions; skipped cases say why

mod common;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use genom_checker::CheckOptions;
use genom_export::{ExportError, ExportInput, Format, Verification};
use genom_generate::{Genom3Config, generate_genom3};
use genom_model::{Code, Severity};
use genom_oracles::fiacre::{Net, Program, parse};

const TIMING: &str = "../tests/fixtures/genom3/timing";

/// The symbolic states the interpreter may explore per component.
const MAX_STATES: usize = 150_000;

/// Every timing fixture, sorted.
fn timing_fixtures() -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(TIMING)
        .expect("the timing fixtures")
        .map(|e| e.expect("an entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "gen"))
        .collect();
    out.sort();
    out
}

/// The Fiacre export of a checked component, as the CLI makes it.
fn fiacre(r: &common::CheckResult) -> Result<String, ExportError> {
    let verification = Verification {
        verified: !r.diagnostics.iter().any(|d| d.severity == Severity::Error),
        tool_version: "0.0.0-test".to_owned(),
        assumptions: r
            .statistics
            .as_ref()
            .map(|s| s.assumptions.clone())
            .unwrap_or_default(),
        ..Verification::default()
    };
    let input = ExportInput {
        component: r.component.as_ref().expect("a component"),
        sources: &r.sources,
        verification: &verification,
    };
    genom_export::export(Format::Fiacre, &input).map(|e| e.main)
}

/// The tasks the timed engine finds overrunning.
fn engine_overruns(r: &common::CheckResult) -> BTreeSet<String> {
    let quoted = |m: &str, after: &str| {
        m.split(after)
            .nth(1)
            .and_then(|s| s.split('`').next())
            .unwrap_or_default()
            .to_owned()
    };
    r.diagnostics
        .iter()
        .filter_map(|d| match d.code {
            Code::ThreadOverrun => Some(quoted(&d.message, "`")),
            Code::CodelOverrun if d.trace.is_some() => Some(quoted(&d.message, "but task `")),
            _ => None,
        })
        .collect()
}

/// The tasks whose watcher the interpreter finds `late` for a positive
/// time, and whether the exploration was complete.
fn model_overruns(prog: &Program) -> (BTreeSet<String>, bool) {
    let net = Net::new(prog).expect("the model instantiates");
    let watchers: Vec<(String, String)> = prog
        .processes
        .iter()
        .filter(|p| p.name.starts_with("watch_"))
        .map(|p| (p.name.clone(), "late".to_owned()))
        .collect();
    let reach = net.explore(&watchers, MAX_STATES).expect("the model runs");
    let tasks = reach
        .lingered
        .iter()
        .map(|(p, _)| p.trim_start_matches("watch_").to_owned())
        .collect();
    (tasks, reach.complete)
}

/// Each `ROOT/K/state S` of a property names a state `S` of the `K`-th
/// process of the root's `par`.
fn properties_name_own_states(prog: &Program, what: &str) {
    let root = prog.components.last().expect("a root component");
    assert_eq!(prog.root.as_deref(), Some(root.name.as_str()), "{what}");
    assert!(!prog.properties.is_empty(), "{what}: no property");
    for p in &prog.properties {
        let words: Vec<&str> = p.formula.split_whitespace().collect();
        for w in words.windows(6) {
            if w[0] != root.name || w[1] != "/" || w[3] != "/" || w[4] != "state" {
                continue;
            }
            let k: usize = w[2].parse().expect("an instance number");
            let inst = &root.par[k - 1];
            let proc_ = prog
                .processes
                .iter()
                .find(|q| q.name == inst.name)
                .expect("a process");
            assert!(
                proc_.states.iter().any(|s| s == w[5]),
                "{what}: {} names {} {}",
                p.name,
                inst.name,
                w[5]
            );
        }
        assert!(
            prog.asserts.contains(&p.name),
            "{what}: {} is not asserted",
            p.name
        );
    }
}

/// The check with its WCET file and the export's model, or why the export
/// refused the component.
fn fixture(path: &Path) -> (common::CheckResult, Result<String, ExportError>) {
    let r = common::check_genom3_fixture(path);
    let text = fiacre(&r);
    (r, text)
}

#[test]
fn snapshots_of_the_timing_fixtures() {
    for name in ["f1b_chain_overrun", "f11_hidden", "f11_permanent_long"] {
        let (_, text) = fixture(&Path::new(TIMING).join(format!("{name}.gen")));
        let text = text.expect("the fixture is exported");
        insta::assert_snapshot!(format!("fiacre_genom3__{name}"), text);
    }
}

#[test]
fn every_export_parses_and_refusals_say_why() {
    let mut exported = 0;
    for path in timing_fixtures() {
        let what = path.display().to_string();
        match fixture(&path).1 {
            Ok(text) => {
                let prog = parse(&text).unwrap_or_else(|e| panic!("{what}: {e}"));
                properties_name_own_states(&prog, &what);
                exported += 1;
            }
            Err(e) => assert!(e.to_string().contains("does not model yet"), "{what}: {e}"),
        }
    }
    assert!(exported >= 10, "only {exported} timing fixtures exported");
}

#[test]
fn an_untimed_component_is_refused_with_the_remedy() {
    let path = Path::new("../tests/fixtures/genom3/semantics/f1b_chain_overrun.gen");
    let path = if path.exists() {
        path.to_owned()
    } else {
        Path::new(TIMING).join("f1b_chain_overrun.gen")
    };
    let r = common::check_genom3(&path, &[], None, &CheckOptions::new());
    let e = fiacre(&r).expect_err("no WCET: refused");
    assert!(e.to_string().contains("--wcet"), "{e}");
}

#[test]
fn the_model_overruns_where_the_engine_does_on_the_timing_fixtures() {
    let mut compared = 0;
    let mut overrunning = 0;
    for path in timing_fixtures() {
        let (r, text) = fixture(&path);
        let Ok(text) = text else { continue };
        let prog = parse(&text).expect("parses");
        let t0 = std::time::Instant::now();
        let (got, complete) = model_overruns(&prog);
        println!("TIME {} {:?}", path.display(), t0.elapsed());
        if !complete {
            println!(
                "{}: skipped, more than {MAX_STATES} symbolic states",
                path.display()
            );
            continue;
        }
        let want = engine_overruns(&r);
        assert_eq!(
            got,
            want,
            "{}: the model's overrunning tasks, then the engine's",
            path.display()
        );
        compared += 1;
        overrunning += usize::from(!want.is_empty());
    }
    assert!(
        compared >= 10 && overrunning >= 5,
        "{compared} compared, {overrunning} overrunning"
    );
}

/// A small timed component of seed `seed` the export can model: one or
/// two tasks, no `interrupts`/`after`/`before` (density 0), no permanent
/// codels (they have a `stop` codel).
fn small_generated(seed: u64) -> Genom3Config {
    let mut cfg = Genom3Config::small(seed);
    cfg.timed = true;
    cfg.asyncs = false;
    cfg.permanent = false;
    cfg.density = 0.0;
    cfg.functions = cfg.functions.min(1);
    cfg.attributes = cfg.attributes.min(1);
    cfg.tasks = cfg.tasks.min(2);
    cfg.activities = cfg.activities.min(2);
    cfg.states = cfg.states.min(2);
    cfg
}

#[test]
fn the_model_overruns_where_the_engine_does_on_generated_components() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let (mut compared, mut overrunning) = (0, 0);
    for seed in 0..40 {
        let g = generate_genom3(&small_generated(seed));
        let source = dir.path().join(format!("gen-{seed}.gen"));
        let wcet = dir.path().join(format!("gen-{seed}.wcet"));
        std::fs::write(&source, &g.r#gen).expect("writes the component");
        std::fs::write(&wcet, g.wcet.expect("timed")).expect("writes the WCETs");
        let r = common::check_genom3(&source, &[], Some(&wcet), &CheckOptions::new());
        if r.diagnostics.iter().any(|d| d.code == Code::Incomplete) {
            println!("seed {seed}: skipped, the check is incomplete");
            continue;
        }
        let text = match fiacre(&r) {
            Ok(text) => text,
            Err(e) => {
                println!("seed {seed}: {e}");
                continue;
            }
        };
        let prog = parse(&text).unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        properties_name_own_states(&prog, &format!("seed {seed}"));
        let (got, complete) = model_overruns(&prog);
        if !complete {
            println!("seed {seed}: skipped, more than {MAX_STATES} symbolic states");
            continue;
        }
        assert_eq!(
            got,
            engine_overruns(&r),
            "seed {seed}: the model's overrunning tasks, then the engine's"
        );
        compared += 1;
        overrunning += usize::from(!got.is_empty());
    }
    assert!(
        compared >= 6 && overrunning >= 2,
        "{compared} compared, {overrunning} overrunning"
    );
}
