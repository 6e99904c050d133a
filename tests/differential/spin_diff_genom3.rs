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

use crate::common;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use genom_check::{CheckOptions, Inputs, check_path};
use genom_export::{ExportInput, Format, Verification, export};
use genom_generate::{Genom3Config, generate_genom3};
use genom_model::Code;
use genom_model::component::Component;
use genom_model::component::genom3::FsmCodel;

/// Generated GenoM3 components compared (seeds 0..GENERATED, untimed).
const GENERATED: u64 = 120;
/// Worker threads (the machine's cores are shared).
const WORKERS: usize = 2;
/// The state budget of genom-check's exploration: a component above it is
/// skipped and listed (the whole-component state space SPIN explores is
/// larger still than the engine's, which goes part by part).
const MAX_STATES: usize = 50_000;
/// SPIN's memory budget in megabytes (`-DMEMLIM`, with the DFS stack of
/// `-m` and the hash table of `-w`): a component whose state space does not
/// fit is skipped and listed.
const MEMLIM_MB: u32 = 64;
const STUBS: &str = "tests/fixtures/genom3/include";

/// Components written for this test, each mixing rules the fixtures
/// exercise one at a time: `after` chains through a completion only a stop
/// path gives, `before`, `interrupts all`, pending interrupters, the
/// shutdown order of permanent stop paths, exceptions that never count.
const HAND: [(&str, &str); 4] = [
    (
        "hand1",
        r#"component h1 {
  task t { period 10 ms; };
  task u {
    codel<start> h1_boot() yield ether;
    codel<stop> h1_fini() yield more, ether;
    codel<more> h1_more() yield ether;
  };
  activity x() { task t; codel<start> h1_x() yield pause::start; codel<stop> h1_xs() yield pause::stop, ether; };
  activity y() { task u; after x; codel<start> h1_y() yield ether; };
  activity z() { task t; interrupts x; codel<start> h1_z() yield ether; };
  activity w() { task u; after y; before z; codel<start> h1_w() yield ether; };
  function f() { interrupts all; codel h1_f(); };
};
"#,
    ),
    (
        "hand2",
        r#"component h2 {
  task t;
  activity a() { task t; codel<start> h2_a() yield pause::start; };
  activity b() { task t; after a; codel<start> h2_b() yield ether; };
  activity c() { task t; interrupts a, c; codel<start> h2_c() yield s1; codel<s1> h2_c1() yield ether; codel<stop> h2_cs() yield ether; };
  activity d() { task t; after c; before b; codel<start> h2_d() yield ether; };
};
"#,
    ),
    (
        "hand3",
        r#"component h3 {
  task t1 { codel<start> h3_s1() yield ether; };
  task t2 { codel<start> h3_s2() yield ether; codel<stop> h3_st2() yield ether; };
  task t3 { codel<start> h3_s3() yield m; codel<m> h3_m() yield pause::m; codel<stop> h3_st3() yield pause::stop, ether; };
  activity a() { task t1; codel<start> h3_a() yield pause::start, ether; codel<stop> h3_as() yield pause::stop, s2; codel<s2> h3_a2() yield ether; };
  activity b() { task t2; interrupts a; after a; codel<start> h3_b() yield ether; };
  activity e() { task t2; after b; codel<start> h3_e() yield ether; };
  activity g() { task t3; after e; interrupts all; codel<start> h3_g() yield ether; };
};
"#,
    ),
    (
        "hand4",
        r#"component h4 {
  exception bad;
  task t { period 5 ms; };
  activity p() { task t; throw bad; codel<start> h4_p() yield pause::start; };
  activity q() { task t; after p; codel<start> h4_q() yield ether; };
  activity r() { task t; after q; codel<start> h4_r() yield ether; };
  attribute s(in n = 0 : "n") { };
  function k() { after s; interrupts p; codel h4_k(); };
  ids { long n; };
};
"#,
    ),
];

/// The verdicts compared.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Verdicts {
    dead: BTreeSet<String>,
    unreachable: BTreeSet<String>,
}

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

/// What genom-check said about one file.
enum Ours {
    /// Its untimed GenoM3 verdicts.
    Verdicts(Box<Component>, Verdicts, u64),
    /// Its exploration exceeded [`MAX_STATES`].
    OverBudget,
    /// The file has no component (an interface).
    NoComponent,
}

/// genom-check's untimed GenoM3 verdicts (no WCET file: untimed).
fn ours(path: &Path) -> Ours {
    let inputs = Inputs {
        include_dirs: vec![PathBuf::from(STUBS)],
        ..Inputs::default()
    };
    let options = CheckOptions::new().max_states(MAX_STATES);
    let result = check_path(path, &inputs, &options).expect("readable");
    let Some(component) = result.component else {
        return Ours::NoComponent;
    };
    let stats = result.statistics.expect("the GenoM3 engine ran");
    if !stats.complete {
        return Ours::OverBudget;
    }
    let dead = result
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::DeadService)
        .filter_map(|d| d.labels.first().map(|l| l.span))
        .filter_map(|span| {
            component
                .services
                .values()
                .find(|s| s.name.span == span)
                .map(|s| s.name.name.clone())
        })
        .collect();
    let unreachable = result
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::UnreachableCodel)
        .map(|d| codel_key(&d.message))
        .collect();
    let verdicts = Verdicts { dead, unreachable };
    Ours::Verdicts(Box::new(component), verdicts, stats.states)
}

/// "codel `f` of activity `a` (state `s`)": the common prefix of the
/// engine's message and of the model's marker comments.
fn codel_key(text: &str) -> String {
    text.find(')')
        .map_or_else(|| text.to_owned(), |at| text[..=at].to_owned())
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
    let builtin = builtins(c);
    let dead: BTreeSet<String> = reached
        .iter()
        .filter(|(what, r)| !**r && what.starts_with("service `"))
        .filter_map(|(what, _)| what.split('`').nth(1).map(str::to_owned))
        .filter(|s| !builtin.contains(s))
        .collect();
    let leads = statically_reachable(c);
    let unreachable = reached
        .iter()
        .filter(|(what, r)| !**r && what.starts_with("codel `"))
        .map(|(what, _)| codel_key(what))
        .filter(|k| leads.contains(k))
        .filter(|k| {
            !dead
                .iter()
                .any(|d| k.contains(&format!("of activity `{d}`")))
        })
        .collect();
    let stored = report
        .lines()
        .find(|l| l.contains("states, stored"))
        .map_or(String::new(), |l| l.trim().to_owned());
    Some((Verdicts { dead, unreachable }, stored))
}

/// The services of the built-in `genom` interface (never reported dead).
fn builtins(c: &Component) -> BTreeSet<String> {
    let g = c.genom3.as_deref().expect("a GenoM3 component");
    g.services
        .iter()
        .filter(|i| i.interface.as_deref() == Some("genom"))
        .map(|i| c.services[i.service].name.name.clone())
        .collect()
}

/// The codels a path of yields reaches from `start` or `stop` (the only
/// ones `unreachable-codel` speaks of), as codel keys.
fn statically_reachable(c: &Component) -> BTreeSet<String> {
    let g = c.genom3.as_deref().expect("a GenoM3 component");
    let mut out = BTreeSet::new();
    for s in c.services.values() {
        let mut fsms: Vec<&FsmCodel> = Vec::new();
        let fsm_codels = g
            .codels
            .iter()
            .filter(|i| s.codels.contains(&i.codel))
            .filter(|i| c.codels[i.codel].kind != genom_model::kinds::CodelKind::Control);
        for i in fsm_codels {
            if !fsms.contains(&&i.fsm) {
                fsms.push(&i.fsm);
            }
        }
        out.extend(reach(&fsms, &format!("activity `{}`", s.name.name)));
    }
    for (tid, t) in c.threads.iter() {
        let fsms: Vec<&FsmCodel> = g
            .tasks
            .iter()
            .filter(|k| k.thread == tid)
            .flat_map(|k| k.codels.iter())
            .collect();
        out.extend(reach(&fsms, &format!("task `{}`", t.name.name)));
    }
    out
}

fn reach(fsms: &[&FsmCodel], owner: &str) -> Vec<String> {
    let codel_of = |state: &str| {
        fsms.iter()
            .find(|f| f.states.iter().any(|s| s.name == state))
    };
    let mut seen: BTreeSet<String> = BTreeSet::new();
    let mut todo = vec!["start".to_owned(), "stop".to_owned()];
    while let Some(state) = todo.pop() {
        let Some(f) = codel_of(&state) else { continue };
        if !seen.insert(state.clone()) {
            continue;
        }
        todo.extend(f.yields.iter().map(|y| y.state.name.clone()));
    }
    seen.iter()
        .filter_map(|state| {
            codel_of(state)
                .map(|f| format!("codel `{}` of {owner} (state `{state}`)", f.function.name))
        })
        .collect()
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

/// The fixtures (semantics and timing, untimed) and the corpus.
fn files() -> Vec<PathBuf> {
    let mut out = Vec::new();
    for dir in [
        "tests/fixtures/genom3/semantics",
        "tests/fixtures/genom3/timing",
    ] {
        out.extend(gen_files(Path::new(dir)));
    }
    let corpus = std::env::var_os("GENOM3_CORPUS")
        .map(PathBuf::from)
        .or_else(common::genom3_corpus);
    if let Some(corpus) = corpus {
        let mut dirs: Vec<PathBuf> = std::fs::read_dir(&corpus)
            .expect("corpus readable")
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| p.is_dir() && !p.ends_with("genom3"))
            .collect();
        dirs.sort();
        for d in dirs {
            out.extend(gen_files(&d));
        }
        let regress = corpus.join("genom3/regress/component.gen");
        if regress.is_file() {
            out.push(regress);
        }
    }
    out
}

fn gen_files(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut paths: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "gen"))
        .collect();
    paths.sort();
    paths
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
