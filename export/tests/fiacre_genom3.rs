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
use genom_model::Code;
use genom_oracles::fiacre::{Net, Program, parse};

const TIMING: &str = "../tests/fixtures/genom3/timing";

/// The symbolic states the interpreter may explore per component.
const MAX_STATES: usize = 150_000;

/// The same for a generated component (they are many).
const MAX_GENERATED_STATES: usize = 40_000;

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
    common::export_as_cli(r, Format::Fiacre).map(|e| e.main)
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
fn model_overruns(prog: &Program, budget: usize) -> (BTreeSet<String>, bool) {
    let net = Net::new(prog).expect("the model instantiates");
    let watchers: Vec<(String, String)> = prog
        .processes
        .iter()
        .filter(|p| p.name.starts_with("watch_"))
        .map(|p| (p.name.clone(), "late".to_owned()))
        .collect();
    let reach = net.explore(&watchers, budget).expect("the model runs");
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
fn every_timing_fixture_is_exported_and_parses() {
    for path in timing_fixtures() {
        let what = path.display().to_string();
        let text = fixture(&path)
            .1
            .unwrap_or_else(|e| panic!("{what}: refused: {e}"));
        let prog = parse(&text).unwrap_or_else(|e| panic!("{what}: {e}"));
        properties_name_own_states(&prog, &what);
        assert!(
            prog.processes.iter().any(|p| p.name.starts_with("watch_")),
            "{what}: timed, with a watcher"
        );
    }
}

#[test]
fn an_untimed_component_is_exported_untimed_and_says_so() {
    let path = Path::new(TIMING).join("f1b_chain_overrun.gen");
    let r = common::check_genom3(&path, &[], None, &CheckOptions::new());
    let c = r.component.as_ref().expect("a component");
    let verification = Verification {
        verified: true,
        tool_version: "0.0.0-test".to_owned(),
        ..Verification::default()
    };
    let input = ExportInput {
        component: c,
        sources: &r.sources,
        verification: &verification,
    };
    let e = genom_export::export(Format::Fiacre, &input).expect("exported untimed");
    assert!(
        e.notes.iter().any(|n| n.contains("untimed")),
        "{:?}",
        e.notes
    );
    assert!(e.main.contains("UNTIMED READING"), "the header says so");
    let prog = parse(&e.main).expect("parses");
    properties_name_own_states(&prog, "untimed f1b");
    assert!(
        !prog.processes.iter().any(|p| p.name.starts_with("watch_")),
        "no overrun watcher"
    );
    assert!(
        prog.properties.iter().all(|p| p.name.starts_with("codel_")),
        "only codel properties"
    );
    // Every codel takes any duration: its `wait` has no upper bound.
    let slot = prog
        .processes
        .iter()
        .find(|p| p.name == "slot_chain")
        .expect("the slot");
    for (state, body) in &slot.froms {
        if state == "idle" {
            continue;
        }
        let Some(genom_oracles::fiacre::ast::Stmt::Wait(i)) = body.first() else {
            panic!("{state}: begins with its wait");
        };
        assert_eq!((i.lo, i.hi), (0, None), "{state}");
    }
    // The timed export of the same component, for contrast, bounds it.
    let (_, timed) = fixture(&path);
    assert!(timed.expect("timed").contains("wait [0,1]"));
}

#[test]
fn the_model_overruns_where_the_engine_does_on_the_timing_fixtures() {
    let mut compared = 0;
    let mut overrunning = 0;
    for path in timing_fixtures() {
        let (r, text) = fixture(&path);
        let Ok(text) = text else { continue };
        let prog = parse(&text).expect("parses");
        let (got, complete) = model_overruns(&prog, MAX_STATES);
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

/// With `--max-instances 2`, the model has two slots per activity (three
/// for one that interrupts itself: 15.8) and still overruns where the
/// engine does, on the instance fixtures (F4: two `move` overrun where
/// one fits).
#[test]
fn the_model_overruns_where_the_engine_does_with_two_instances() {
    let (mut compared, mut overrunning) = (0, 0);
    // Each has one activity: two slots, three when it interrupts itself.
    for (name, want) in [
        ("f4_instances", 2),
        ("f4_self_interrupt", 3),
        ("f1b_chain_paused", 2),
    ] {
        let path = Path::new(TIMING).join(format!("{name}.gen"));
        let wcet = path.with_extension("wcet");
        let options = CheckOptions::new().max_instances(2);
        let r = common::check_genom3(&path, &[], Some(&wcet), &options);
        let text = fiacre(&r).expect("exported");
        let prog = parse(&text).expect("parses");
        let slots: Vec<&str> = prog
            .processes
            .iter()
            .map(|p| p.name.as_str())
            .filter(|n| n.starts_with("slot_") && !n.starts_with("slot_task_"))
            .collect();
        assert_eq!(slots.len(), want, "{name}: {slots:?}");
        let (got, complete) = model_overruns(&prog, MAX_STATES);
        if !complete {
            println!("{name}: skipped, more than {MAX_STATES} symbolic states");
            continue;
        }
        assert_eq!(
            got,
            engine_overruns(&r),
            "{name}: the model's, then the engine's"
        );
        compared += 1;
        overrunning += usize::from(!got.is_empty());
    }
    assert!(
        compared >= 2 && overrunning >= 1,
        "{compared} compared, {overrunning} overrunning"
    );
}

/// A small timed component of seed `seed`: one or two tasks, and by
/// seed, besides the plain ones, permanent codels (with a `stop` codel),
/// `interrupts`/`after`/`before`, or `async` codels.
fn small_generated(seed: u64) -> Genom3Config {
    let mut cfg = Genom3Config::small(seed);
    cfg.timed = true;
    cfg.asyncs = seed % 4 == 3;
    cfg.permanent = seed % 4 == 1;
    cfg.density = if seed % 4 == 2 { 0.6 } else { 0.0 };
    // No function or attribute: with `kill` and `abort_activity`, which
    // every component has, requests at any time already make the state
    // spaces large for the interpreter.
    cfg.functions = 0;
    cfg.attributes = 0;
    cfg.tasks = cfg.tasks.min(2);
    cfg.activities = cfg.activities.min(2);
    cfg.states = cfg.states.min(2);
    cfg
}

#[test]
fn the_model_overruns_where_the_engine_does_on_generated_components() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let (mut compared, mut overrunning) = (0, 0);
    let mut exercised = [0; 3];
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
        let (got, complete) = model_overruns(&prog, MAX_GENERATED_STATES);
        if !complete {
            println!("seed {seed}: skipped, more than {MAX_GENERATED_STATES} symbolic states");
            continue;
        }
        assert_eq!(
            got,
            engine_overruns(&r),
            "seed {seed}: the model's overrunning tasks, then the engine's"
        );
        compared += 1;
        overrunning += usize::from(!got.is_empty());
        // What the compared components exercise.
        let features = [
            text.contains("process slot_task_"),
            g.r#gen.contains("interrupts"),
            g.r#gen.contains("async"),
        ];
        for (n, f) in exercised.iter_mut().zip(features) {
            *n += usize::from(f);
        }
    }
    assert!(
        compared >= 12 && overrunning >= 3,
        "{compared} compared, {overrunning} overrunning"
    );
    assert!(
        exercised.iter().all(|&n| n >= 1),
        "compared with permanent codels, interrupts, async codels: {exercised:?}"
    );
}

/// The (instance, state) pairs a property `ROOT/K/state S or ...` names.
fn property_states(prog: &Program, formula: &str) -> Vec<(String, String)> {
    let root = prog.components.last().expect("a root component");
    let words: Vec<&str> = formula.split_whitespace().collect();
    words
        .windows(6)
        .filter(|w| w[0] == root.name && w[1] == "/" && w[3] == "/" && w[4] == "state")
        .map(|w| {
            let k: usize = w[2].parse().expect("an instance number");
            (root.par[k - 1].name.clone(), w[5].to_owned())
        })
        .collect()
}

/// `(activity, state)` out of the engine's `unreachable-codel` message
/// on a GenoM3 codel (`... of activity `S` (state `C`) ...`).
fn never_run(message: &str) -> Option<(String, String)> {
    let rest = message.split("of activity `").nth(1)?;
    let (service, rest) = rest.split_once('`')?;
    let state = rest.split("(state `").nth(1)?.split('`').next()?;
    Some((service.to_owned(), state.to_owned()))
}

/// The untimed reading runs exactly the activity codels the engine runs:
/// on the semantics fixtures (checked without WCETs), the interpreter
/// explores the whole model and a codel property's states are reached
/// exactly when the engine does not report the codel `unreachable-codel`
/// (services the engine finds dead left aside; fixtures with a state no
/// yield reaches, or an incomplete check or exploration, skipped).
#[test]
fn the_untimed_model_runs_the_codels_the_engine_runs() {
    let dir = Path::new("../tests/fixtures/genom3/semantics");
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("the semantics fixtures")
        .map(|e| e.expect("an entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "gen"))
        .collect();
    paths.sort();
    let include = [PathBuf::from("../tests/fixtures/genom3/include")];
    let (mut compared, mut unreached) = (0, 0);
    for path in paths {
        let what = path.display().to_string();
        let r = common::check_genom3(&path, &include, None, &CheckOptions::new());
        let codes: BTreeSet<Code> = r.diagnostics.iter().map(|d| d.code).collect();
        if codes.contains(&Code::Incomplete) || codes.contains(&Code::UnreachableState) {
            println!("{what}: skipped (incomplete check, or a state no yield reaches)");
            continue;
        }
        let Ok(text) = fiacre(&r) else {
            panic!("{what}: refused");
        };
        let prog = parse(&text).unwrap_or_else(|e| panic!("{what}: {e}"));
        let net = Net::new(&prog).expect("the model instantiates");
        let reach = net.explore(&[], MAX_STATES).expect("the model runs");
        if !reach.complete {
            println!("{what}: skipped, more than {MAX_STATES} symbolic states");
            continue;
        }
        let c = r.component.as_ref().expect("a component");
        let dead: Vec<&str> = r
            .diagnostics
            .iter()
            .filter(|d| d.code == Code::DeadService)
            .map(|d| d.message.as_str())
            .collect();
        let engine: BTreeSet<(String, String)> = r
            .diagnostics
            .iter()
            .filter(|d| d.code == Code::UnreachableCodel)
            .filter_map(|d| never_run(&d.message))
            .collect();
        let mut model = BTreeSet::new();
        for (_, s) in c.services.iter() {
            if dead
                .iter()
                .any(|m| m.contains(&format!("`{}`", s.name.name)))
            {
                continue;
            }
            for &k in &s.codels {
                let codel = &c.codels[k].name.name;
                let name = format!("codel_{}_{codel}_never_runs", s.name.name);
                let Some(p) = prog.properties.iter().find(|p| p.name == name) else {
                    continue;
                };
                let states = property_states(&prog, &p.formula);
                if !states.iter().any(|x| reach.reached.contains(x)) {
                    model.insert((s.name.name.clone(), codel.clone()));
                }
            }
        }
        assert_eq!(
            model, engine,
            "{what}: the codels the model never runs, then those the engine never runs"
        );
        compared += 1;
        unreached += usize::from(!engine.is_empty());
    }
    assert!(
        compared >= 8 && unreached >= 1,
        "{compared} compared, {unreached} with a codel never run"
    );
}
