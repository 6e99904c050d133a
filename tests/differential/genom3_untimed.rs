//! What the untimed GenoM3 differential tests (SPIN on the Promela export,
//! the token game on the Petri net export) compare: genom-check's untimed
//! GenoM3 verdicts (`dead-service`, `unreachable-codel`), the same
//! verdicts read from which facts an independent model shows (a service
//! accepted or started, a codel run), and the components both run on.

#![allow(clippy::expect_used)] // test support code

use crate::common;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use genom_check::{CheckOptions, Inputs, check_path};
use genom_model::Code;
use genom_model::component::Component;
use genom_model::component::genom3::FsmCodel;

/// The state budget of genom-check's exploration: a component above it is
/// skipped and listed (the whole-component state space an independent
/// model explores is larger still than the engine's, which goes part by
/// part).
pub const MAX_STATES: usize = 50_000;
pub const STUBS: &str = "tests/fixtures/genom3/include";

/// Components written for this test, each mixing rules the fixtures
/// exercise one at a time: `after` chains through a completion only a stop
/// path gives, `before`, `interrupts all`, pending interrupters, the
/// shutdown order of permanent stop paths, exceptions that never count.
pub const HAND: [(&str, &str); 4] = [
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
pub struct Verdicts {
    pub dead: BTreeSet<String>,
    pub unreachable: BTreeSet<String>,
}

impl Verdicts {
    /// The verdicts read from which facts a model shows: `reached` maps
    /// each fact (`service `S` is accepted`, `service `A` starts`, `codel
    /// `f` of activity `A` (state `s`) runs`...) to whether some execution
    /// shows it. A service is dead when none of its facts is shown (the
    /// built-in `genom` services aside); a codel is unreachable when it is
    /// not shown, some path of yields leads to it, and its activity is not
    /// dead.
    pub fn of_facts(c: &Component, reached: &BTreeMap<String, bool>) -> Verdicts {
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
        Verdicts { dead, unreachable }
    }
}

/// What genom-check said about one file.
pub enum Ours {
    /// Its untimed GenoM3 verdicts.
    Verdicts(Box<Component>, Verdicts, u64),
    /// Its exploration exceeded [`MAX_STATES`].
    OverBudget,
    /// The file has no component (an interface).
    NoComponent,
}

/// genom-check's untimed GenoM3 verdicts (no WCET file: untimed).
pub fn ours(path: &Path) -> Ours {
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
pub fn codel_key(text: &str) -> String {
    text.find(')')
        .map_or_else(|| text.to_owned(), |at| text[..=at].to_owned())
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

/// The fixtures (semantics and timing, untimed) and the corpus.
pub fn files() -> Vec<PathBuf> {
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
