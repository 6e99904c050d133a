//! What the differential tests of GenoM3's timed verdicts share (TChecker:
//! `tchecker_diff_genom3.rs`, DIVINE: `divine_diff_genom3.rs`): the
//! components compared (fixtures with their WCET files, the small corpus
//! components, generated ones), genom-check's verdict on each label of the
//! GenoM3 network (`Network::build_genom3`), read from its diagnostics, and
//! the tally of agreements.
//!
//! - `overrun_T`: a `thread-overrun` on task `T`, or a `codel-overrun` of
//!   one of its codels with a trace (timed GenoM3 engine);
//! - `codel_S_C` (activity `S`, state `C`): reachable unless `S` is a
//!   `dead-service`, or `C` has an `unreachable-codel`, or no path of
//!   yields leads to `C` from `start` or `stop` (no diagnostic then).
//!
//! genom-check runs with `--max-instances 1` (its default): one instance
//! of each activity, plus one request restarting an activity that
//! interrupts itself, as the network's slots.

use crate::common;

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Duration;

use genom_check::{CheckOptions, CheckResult, Inputs, check_path};
use genom_generate::{Genom3Config, generate_genom3};
use genom_model::Code;
use genom_model::component::Component;
use genom_model::component::genom3::FsmCodel;
use genom_model::timed_automata::{Label, LabelKind, Network};
use genom_translate::timed_automata::BuildNetwork;

pub(crate) const TIMING: &str = "tests/fixtures/genom3/timing";
pub(crate) const RESPONSE: &str = "tests/fixtures/genom3/response";
pub(crate) const SEMANTICS: &str = "tests/fixtures/genom3/semantics";
pub(crate) const WCETS: &str = "tests/fixtures/genom3/wcet";
pub(crate) const STUBS: &str = "tests/fixtures/genom3/include";

/// The corpus components small enough for `tck-reach`, with their WCET
/// files.
pub(crate) const CORPUS: [(&str, &str); 3] = [
    ("uavatt.wcet", "uavatt-genom3/uavatt.gen"),
    ("uavvs.wcet", "uavvs-genom3/uavvs.gen"),
    ("uavpos.wcet", "uavpos-genom3/uavpos.gen"),
];

/// A component and its WCET file.
pub(crate) struct Case {
    pub(crate) name: String,
    pub(crate) source: PathBuf,
    /// Its WCET file (`None`: untimed, only codel labels are compared).
    pub(crate) wcet: Option<PathBuf>,
}

/// The fixtures of a folder (with their WCET files when `timed`).
pub(crate) fn fixtures_in(dir: &str, timed: bool) -> Vec<Case> {
    let mut out: Vec<Case> = std::fs::read_dir(dir)
        .expect("the fixtures")
        .map(|e| e.expect("an entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "gen"))
        .map(|source| Case {
            name: source.file_stem().unwrap().to_string_lossy().into_owned(),
            wcet: timed.then(|| source.with_extension("wcet")),
            source,
        })
        .collect();
    out.sort_by(|a, b| a.name.cmp(&b.name));
    assert!(!out.is_empty(), "the fixtures of {dir} are there");
    out
}

/// The timed fixtures (timing and response times), then the untimed
/// semantics fixtures (codel labels only).
pub(crate) fn fixtures() -> Vec<Case> {
    let mut out = fixtures_in(TIMING, true);
    out.extend(fixtures_in(RESPONSE, true));
    out.extend(fixtures_in(SEMANTICS, false));
    out
}

pub(crate) fn corpus() -> Vec<Case> {
    let Some(dir) = common::genom3_corpus() else {
        return Vec::new();
    };
    CORPUS
        .iter()
        .filter_map(|(wcet, source)| {
            let source = dir.join(source);
            source.is_file().then(|| Case {
                name: source.file_stem().unwrap().to_string_lossy().into_owned(),
                wcet: Some(Path::new(WCETS).join(wcet)),
                source,
            })
        })
        .collect()
}

/// Generated timed GenoM3 components (`genom_generate::generate_genom3`),
/// kept small enough for complete verdicts: at most 2 tasks, 3 activities
/// of 2 states, 1 function and 1 attribute; written with their WCET files
/// to `dir`.
pub(crate) fn generated(dir: &Path, seeds: std::ops::Range<u64>) -> Vec<Case> {
    seeds
        .map(|seed| {
            let mut cfg = Genom3Config::small(seed);
            cfg.timed = true;
            cfg.asyncs = false;
            cfg.tasks = cfg.tasks.min(2);
            cfg.activities = cfg.activities.min(3);
            cfg.states = cfg.states.min(2);
            cfg.functions = cfg.functions.min(1);
            cfg.attributes = cfg.attributes.min(1);
            let g = generate_genom3(&cfg);
            let source = dir.join(format!("gen-{seed}.gen"));
            let wcet = dir.join(format!("gen-{seed}.wcet"));
            std::fs::write(&source, &g.r#gen).expect("writes the component");
            std::fs::write(&wcet, g.wcet.expect("a timed component has WCETs"))
                .expect("writes the WCET file");
            Case {
                name: format!("gen-{seed}"),
                source,
                wcet: Some(wcet),
            }
        })
        .collect()
}

/// The generated seeds to compare, from the environment variable `var`: a
/// count `N` for seeds `0..N`, or a range `A..B`; default `0..n`. The
/// interpreter does not take them: many make millions of symbolic states.
pub(crate) fn seed_range(var: &str, n: u64) -> std::ops::Range<u64> {
    let var = std::env::var(var).unwrap_or_default();
    let parse = |x: &str| x.trim().parse::<u64>().ok();
    match var.split_once("..") {
        Some((a, b)) => parse(a).unwrap_or(0)..parse(b).unwrap_or(n),
        None => 0..parse(&var).unwrap_or(n),
    }
}

pub(crate) fn check(case: &Case) -> CheckResult {
    let inputs = Inputs {
        wcet_file: case.wcet.clone(),
        include_dirs: vec![PathBuf::from(STUBS)],
        ..Inputs::default()
    };
    let options = CheckOptions::new()
        .max_instances(1)
        .timeout(Some(Duration::from_secs(120)));
    check_path(&case.source, &inputs, &options).expect("the component is readable")
}

/// genom-check's verdict on each label (`None`: no verdict).
pub(crate) struct Verdicts {
    /// Whether the timed engine ran (a WCET file).
    pub(crate) timed: bool,
    pub(crate) overrun: BTreeSet<String>,
    pub(crate) dead: BTreeSet<String>,
    pub(crate) unreachable: Vec<String>,
    pub(crate) incomplete: bool,
}

impl Verdicts {
    pub(crate) fn of(r: &CheckResult, timed: bool) -> Verdicts {
        let name = |m: &str| m.split('`').nth(1).unwrap_or_default().to_owned();
        let mut v = Verdicts {
            timed,
            overrun: BTreeSet::new(),
            dead: BTreeSet::new(),
            unreachable: Vec::new(),
            incomplete: false,
        };
        for d in &r.diagnostics {
            match d.code {
                Code::ThreadOverrun => {
                    v.overrun.insert(name(&d.message));
                }
                // A codel longer than its period that the timed engine saw
                // running at a tick (its trace): its task overruns.
                Code::CodelOverrun if d.trace.is_some() => {
                    let task = d.message.split("but task `").nth(1).unwrap_or_default();
                    v.overrun
                        .insert(task.split('`').next().unwrap_or_default().to_owned());
                }
                Code::DeadService => {
                    v.dead.insert(name(&d.message));
                }
                Code::UnreachableCodel => v.unreachable.push(d.message.clone()),
                Code::Incomplete => v.incomplete = true,
                _ => {}
            }
        }
        v
    }

    pub(crate) fn expects(&self, c: &Component, label: &Label) -> Option<bool> {
        match label.kind {
            LabelKind::Overrun(t) => self
                .timed
                .then(|| self.overrun.contains(&c.threads[t].name.name)),
            LabelKind::Codel(k) => {
                let codel = &c.codels[k];
                let service = &c.services[codel.service].name.name;
                let state = &codel.name.name;
                if self.dead.contains(service) {
                    return Some(false);
                }
                let never = format!("of activity `{service}` (state `{state}`)");
                if self.unreachable.iter().any(|m| m.contains(&never)) {
                    return Some(false);
                }
                Some(statically_reachable(c, codel.service).contains(state))
            }
            LabelKind::Timeout(_) => None,
        }
    }
}

/// The states of an activity that some path of yields reaches from
/// `start` or `stop`.
pub(crate) fn statically_reachable(
    c: &Component,
    sid: genom_model::component::ServiceId,
) -> BTreeSet<String> {
    let g = c.genom3.as_deref().expect("a GenoM3 component");
    let s = &c.services[sid];
    let fsms: Vec<&FsmCodel> = g
        .codels
        .iter()
        .filter(|i| s.codels.contains(&i.codel))
        .map(|i| &i.fsm)
        .collect();
    let mut seen = BTreeSet::new();
    let mut todo: Vec<String> = vec!["start".to_owned(), "stop".to_owned()];
    todo.retain(|x| fsms.iter().any(|f| f.states.iter().any(|n| &n.name == x)));
    while let Some(x) = todo.pop() {
        if !seen.insert(x.clone()) {
            continue;
        }
        for f in fsms.iter().filter(|f| f.states.iter().any(|n| n.name == x)) {
            todo.extend(f.yields.iter().map(|y| y.state.name.clone()));
        }
    }
    seen
}

/// A disagreement explained by a documented gap: (case, label, the
/// verdict genom-check gives, why). Reported, not failed.
pub(crate) type Known = (&'static str, &'static str, bool, &'static str);

/// The comparison's totals.
#[derive(Default)]
pub(crate) struct Tally {
    /// The explained disagreements of the tool compared with.
    pub(crate) known: &'static [Known],
    pub(crate) components: usize,
    pub(crate) labels: usize,
    pub(crate) agree: usize,
    pub(crate) reachable: usize,
    pub(crate) skipped: Vec<String>,
    pub(crate) problems: Vec<String>,
    /// Disagreements listed in `known`, and known ones that agree now.
    pub(crate) explained: Vec<String>,
}

impl Tally {
    pub(crate) fn record(
        &mut self,
        case: &str,
        label: &str,
        expected: bool,
        got: Result<bool, String>,
    ) {
        self.labels += 1;
        let known = self
            .known
            .iter()
            .find(|k| (k.0, k.1, k.2) == (case, label, expected));
        match got {
            Ok(b) if b == expected => {
                self.agree += 1;
                self.reachable += usize::from(b);
                if known.is_some() {
                    self.explained
                        .push(format!("{case}: {label}: listed as known but agrees now"));
                }
            }
            Ok(_) if known.is_some() => {
                let why = known.map_or("", |k| k.3);
                self.explained.push(format!("{case}: {label}: {why}"));
            }
            Ok(b) => self.problems.push(format!(
                "{case}: {label}: genom-check {}, model {}",
                word(expected),
                word(b)
            )),
            Err(why) => self.problems.push(format!("{case}: {label}: {why}")),
        }
    }

    pub(crate) fn report(&self, what: &str) -> String {
        let mut s = format!(
            "{what}: {}/{} labels agree over {} components ({} reachable); skipped {:?}\n",
            self.agree, self.labels, self.components, self.reachable, self.skipped
        );
        for p in &self.problems {
            let _ = writeln!(s, "DISAGREEMENT {p}");
        }
        for p in &self.explained {
            let _ = writeln!(s, "EXPLAINED {p}");
        }
        s
    }
}

pub(crate) fn word(b: bool) -> &'static str {
    if b { "reachable" } else { "unreachable" }
}

/// The labels of a network, each once (a codel label marks its location
/// in each slot of its activity: one entry per location).
pub(crate) fn distinct_labels(net: &Network) -> Vec<&Label> {
    let mut seen = BTreeSet::new();
    net.labels
        .iter()
        .filter(|l| seen.insert(l.name.as_str()))
        .collect()
}

/// The network and genom-check's verdicts of a case; `None` when the
/// check is incomplete.
pub(crate) fn prepare(case: &Case) -> Option<(CheckResult, Verdicts, Network)> {
    let r = check(case);
    let v = Verdicts::of(&r, case.wcet.is_some());
    if v.incomplete {
        return None;
    }
    let c = r.component.as_ref().expect("a component");
    let net = Network::build_genom3(c).expect("a GenoM3 network");
    Some((r, v, net))
}
