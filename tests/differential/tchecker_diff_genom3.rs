//! Differential test of GenoM3's timed verdicts against TChecker: for the
//! timed fixtures of `tests/fixtures/genom3/timing/` (each `.gen` with its
//! `.wcet`) and the small corpus components with a WCET file of
//! `tests/fixtures/genom3/wcet/` (uavatt, uavvs, uavpos; the others are too
//! large for `tck-reach`), every label of the `tchecker` export of the
//! GenoM3 network (`Network::build_genom3`) must be reachable for
//! `tck-reach` exactly when genom-check says so:
//!
//! - `overrun_T`: a `thread-overrun` on task `T`, or a `codel-overrun` of
//!   one of its codels with a trace (timed GenoM3 engine);
//! - `codel_S_C` (activity `S`, state `C`): reachable unless `S` is a
//!   `dead-service`, or `C` has an `unreachable-codel`, or no path of
//!   yields leads to `C` from `start` or `stop` (no diagnostic then).
//!
//! genom-check runs with `--max-instances 1` (its default): one instance
//! of each activity, plus one request restarting an activity that
//! interrupts itself, as the network's slots (one per activity, two for
//! such an activity). Runs only when `TCK_REACH` names a `tck-reach`
//! executable (docs/testing/tchecker.md); otherwise it prints a note and
//! passes.
//! Generated timed components (`genom_generate::generate_genom3`, small
//! sizes; `TCK_GENOM3_SEEDS`: a count or a range `A..B`, default 60) are
//! compared with `tck-reach` too.
//! `TCK_ALGO` (default `covreach`), `TCK_KEEP` (a directory that keeps the
//! models) and `TCK_MEMORY_MB` are as for `tests/differential/tchecker_diff.rs`.
//!
//! Always run: the same comparison with a small interpreter of the network
//! (`genom_oracles::ta_sim`: explicit locations and variables, clocks as
//! zones) on the fixtures, and on the small corpus components when the
//! corpus is on the machine, which also checks that no variable leaves its
//! range and that the urgency predicate matches the urgent edges.

#![allow(
    clippy::expect_used,
    clippy::unwrap_used,
    clippy::print_stdout,
    clippy::print_stderr
)] // test harness

use crate::common;
use genom_oracles::ta_sim;

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use genom_check::{CheckOptions, CheckResult, Inputs, check_path};
use genom_export::{ExportInput, Format, Verification};
use genom_generate::{Genom3Config, generate_genom3};
use genom_model::Code;
use genom_model::component::Component;
use genom_model::component::genom3::FsmCodel;
use genom_model::timed_automata::{Label, LabelKind, Network};
use genom_translate::timed_automata::BuildNetwork;

const TIMING: &str = "tests/fixtures/genom3/timing";
const RESPONSE: &str = "tests/fixtures/genom3/response";
const SEMANTICS: &str = "tests/fixtures/genom3/semantics";
const WCETS: &str = "tests/fixtures/genom3/wcet";
const STUBS: &str = "tests/fixtures/genom3/include";

/// The corpus components small enough for `tck-reach`, with their WCET
/// files.
const CORPUS: [(&str, &str); 3] = [
    ("uavatt.wcet", "uavatt-genom3/uavatt.gen"),
    ("uavvs.wcet", "uavvs-genom3/uavvs.gen"),
    ("uavpos.wcet", "uavpos-genom3/uavpos.gen"),
];

const TCK_TIMEOUT: Duration = Duration::from_secs(60);

/// A component and its WCET file.
struct Case {
    name: String,
    source: PathBuf,
    /// Its WCET file (`None`: untimed, only codel labels are compared).
    wcet: Option<PathBuf>,
}

/// The fixtures of a folder (with their WCET files when `timed`).
fn fixtures_in(dir: &str, timed: bool) -> Vec<Case> {
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
fn fixtures() -> Vec<Case> {
    let mut out = fixtures_in(TIMING, true);
    out.extend(fixtures_in(RESPONSE, true));
    out.extend(fixtures_in(SEMANTICS, false));
    out
}

fn corpus() -> Vec<Case> {
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
fn generated(dir: &Path, seeds: std::ops::Range<u64>) -> Vec<Case> {
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

/// Generated seeds compared with `tck-reach` (`TCK_GENOM3_SEEDS`: a count
/// `N` for seeds `0..N`, or a range `A..B`; default `0..n`). The
/// interpreter does not take them: many make millions of symbolic states.
fn seed_range(n: u64) -> std::ops::Range<u64> {
    let var = std::env::var("TCK_GENOM3_SEEDS").unwrap_or_default();
    let parse = |x: &str| x.trim().parse::<u64>().ok();
    match var.split_once("..") {
        Some((a, b)) => parse(a).unwrap_or(0)..parse(b).unwrap_or(n),
        None => 0..parse(&var).unwrap_or(n),
    }
}

fn check(case: &Case) -> CheckResult {
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
struct Verdicts {
    /// Whether the timed engine ran (a WCET file).
    timed: bool,
    overrun: BTreeSet<String>,
    dead: BTreeSet<String>,
    unreachable: Vec<String>,
    incomplete: bool,
}

impl Verdicts {
    fn of(r: &CheckResult, timed: bool) -> Verdicts {
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

    fn expects(&self, c: &Component, label: &Label) -> Option<bool> {
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
fn statically_reachable(c: &Component, sid: genom_model::component::ServiceId) -> BTreeSet<String> {
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

/// Disagreements explained by a documented gap of the network
/// (docs/exports/tchecker.md, "Not modelled"), with the verdict genom-check
/// gives: reported, not failed. A listed label that agrees again is
/// reported too, so that the list is kept short.
/// Empty since both model GenoM3's resource FIFO (seed 21's `overrun_t0`,
/// which needs it, agrees).
const KNOWN: &[(&str, &str, bool, &str)] = &[];

/// The comparison's totals.
#[derive(Default)]
struct Tally {
    components: usize,
    labels: usize,
    agree: usize,
    reachable: usize,
    skipped: Vec<String>,
    problems: Vec<String>,
    /// Disagreements of [`KNOWN`], and known ones that agree now.
    explained: Vec<String>,
}

impl Tally {
    fn record(&mut self, case: &str, label: &str, expected: bool, got: Result<bool, String>) {
        self.labels += 1;
        let known = KNOWN
            .iter()
            .find(|k| (k.0, k.1, k.2) == (case, label, expected));
        match got {
            Ok(b) if b == expected => {
                self.agree += 1;
                self.reachable += usize::from(b);
                if known.is_some() {
                    self.explained
                        .push(format!("{case}: {label}: listed in KNOWN but agrees now"));
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

    fn report(&self, what: &str) -> String {
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

fn word(b: bool) -> &'static str {
    if b { "reachable" } else { "unreachable" }
}

/// The labels of a network, each once (a codel label marks its location
/// in each slot of its activity: one entry per location).
fn distinct_labels(net: &Network) -> Vec<&Label> {
    let mut seen = BTreeSet::new();
    net.labels
        .iter()
        .filter(|l| seen.insert(l.name.as_str()))
        .collect()
}

/// The network and genom-check's verdicts of a case; `None` when the
/// check is incomplete.
fn prepare(case: &Case) -> Option<(CheckResult, Verdicts, Network)> {
    let r = check(case);
    let v = Verdicts::of(&r, case.wcet.is_some());
    if v.incomplete {
        return None;
    }
    let c = r.component.as_ref().expect("a component");
    let net = Network::build_genom3(c).expect("a GenoM3 network");
    Some((r, v, net))
}

#[test]
fn the_network_agrees_with_the_timed_engine_on_the_timing_fixtures() {
    let mut tally = Tally::default();
    for case in fixtures() {
        let (r, v, net) = prepare(&case).expect("the fixtures' checks finish");
        let c = r.component.as_ref().unwrap();
        let reach = ta_sim::explore(&net, 2_000_000);
        assert!(
            reach.problems.is_empty(),
            "{}: {:?}",
            case.name,
            reach.problems
        );
        assert!(reach.complete, "{}: {} states", case.name, reach.states);
        tally.components += 1;
        let overruns: Vec<&String> = reach
            .labels
            .iter()
            .filter(|l| l.starts_with("overrun_"))
            .collect();
        println!("{}: {} states, {overruns:?}", case.name, reach.states);
        for label in distinct_labels(&net) {
            let Some(expected) = v.expects(c, label) else {
                continue;
            };
            let got = reach.labels.contains(&label.name);
            tally.record(&case.name, &label.name, expected, Ok(got));
        }
    }
    let text = tally.report("interpreter");
    println!("{text}");
    assert!(tally.labels > 20, "{text}");
    assert!(tally.problems.is_empty(), "{text}");
}

/// The interpreter on the small corpus components, when the corpus is on
/// the machine (seconds with zones).
#[test]
fn the_network_agrees_with_the_timed_engine_on_the_small_corpus_components() {
    let mut tally = Tally::default();
    for case in corpus() {
        let Some((r, v, net)) = prepare(&case) else {
            tally
                .skipped
                .push(format!("{} (genom-check incomplete)", case.name));
            continue;
        };
        let c = r.component.as_ref().unwrap();
        let started = Instant::now();
        let reach = ta_sim::explore(&net, 5_000_000);
        println!(
            "{}: {} states in {:.1?}, complete {}",
            case.name,
            reach.states,
            started.elapsed(),
            reach.complete
        );
        assert!(
            reach.problems.is_empty(),
            "{}: {:?}",
            case.name,
            reach.problems
        );
        tally.components += 1;
        for label in distinct_labels(&net) {
            if let Some(expected) = v.expects(c, label) {
                let got = reach.labels.contains(&label.name);
                // Incomplete, a label reached is still reachable: only
                // that direction is compared.
                if reach.complete || got {
                    tally.record(&case.name, &label.name, expected, Ok(got));
                }
            }
        }
        if !reach.complete {
            tally.skipped.push(format!(
                "{} (interpreter limit: labels reached only)",
                case.name
            ));
        }
    }
    let text = tally.report("interpreter, corpus");
    println!("{text}");
    assert!(tally.problems.is_empty(), "{text}");
}

/// What `tck-reach` says about one label.
fn tck(tck: &Path, algo: &str, model: &Path, label: &str) -> Result<Option<bool>, String> {
    let mb = std::env::var("TCK_MEMORY_MB").ok().map_or(2048, |s| {
        s.parse::<u64>().expect("TCK_MEMORY_MB: an integer")
    });
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v {}; exec \"$0\" -a \"$1\" -l \"$2\" \"$3\"",
            mb * 1024
        ))
        .arg(tck)
        .args([algo, label])
        .arg(model)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot run {}: {e}", tck.display()))?;
    let started = Instant::now();
    while child.try_wait().map_err(|e| e.to_string())?.is_none() {
        if started.elapsed() > TCK_TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            return Ok(None);
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let out = child.wait_with_output().map_err(|e| e.to_string())?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    match stdout
        .lines()
        .find_map(|l| l.strip_prefix("REACHABLE "))
        .map(str::trim)
    {
        Some("true") => Ok(Some(true)),
        Some("false") => Ok(Some(false)),
        _ if stderr.contains("bad_alloc") || out.status.code().is_none() => Ok(None),
        _ => Err(format!("no verdict: {}{}", stdout.trim(), stderr.trim())),
    }
}

fn tck_case(case: &Case, exe: &Path, algo: &str, dir: &Path, tally: &mut Tally) {
    let Some((r, v, net)) = prepare(case) else {
        tally
            .skipped
            .push(format!("{} (genom-check incomplete)", case.name));
        return;
    };
    let c = r.component.as_ref().unwrap();
    let verification = Verification::default();
    let input = ExportInput {
        component: c,
        sources: &r.sources,
        verification: &verification,
    };
    let model = genom_export::export(Format::Tchecker, &input)
        .expect("the export succeeds")
        .main;
    let path = dir.join(format!("{}.tck", case.name));
    std::fs::write(&path, model).expect("writes the model");
    let started = Instant::now();
    let mut answers = Vec::new();
    for label in distinct_labels(&net) {
        let Some(expected) = v.expects(c, label) else {
            continue;
        };
        match tck(exe, algo, &path, &label.name) {
            Ok(None) => {
                tally
                    .skipped
                    .push(format!("{} ({}: tck-reach limit)", case.name, label.name));
                return;
            }
            Ok(Some(b)) => answers.push((label.name.clone(), expected, Ok(b))),
            Err(e) => answers.push((label.name.clone(), expected, Err(e))),
        }
    }
    tally.components += 1;
    for (label, expected, got) in answers {
        tally.record(&case.name, &label, expected, got);
    }
    eprintln!(
        "{}: {} labels, tck-reach {:.1?}",
        case.name,
        distinct_labels(&net).len(),
        started.elapsed()
    );
}

#[test]
fn genom3_timed_verdicts_agree_with_tchecker() {
    let Some(exe) = std::env::var_os("TCK_REACH")
        .map(PathBuf::from)
        .filter(|p| p.is_file())
    else {
        eprintln!(
            "note: TCK_REACH is not set to a tck-reach executable; the GenoM3 TChecker \
             differential test is skipped (see docs/testing/tchecker.md)"
        );
        return;
    };
    let algo = std::env::var("TCK_ALGO").unwrap_or_else(|_| "covreach".to_owned());
    let tmp = tempfile::tempdir().expect("a temporary directory");
    let dir = std::env::var_os("TCK_KEEP").map_or_else(|| tmp.path().to_owned(), PathBuf::from);
    std::fs::create_dir_all(&dir).expect("creates TCK_KEEP");
    let mut tally = Tally::default();
    // With `TCK_KEEP`, the generated sources and WCET files stay there too.
    let gen_dir = tempfile::tempdir().expect("a temporary directory");
    let gen_path =
        std::env::var_os("TCK_KEEP").map_or_else(|| gen_dir.path().to_owned(), PathBuf::from);
    let cases = fixtures()
        .into_iter()
        .chain(corpus())
        .chain(generated(&gen_path, seed_range(60)));
    for case in cases {
        tck_case(&case, &exe, &algo, &dir, &mut tally);
    }
    let text = tally.report(&format!("tchecker ({algo})"));
    println!("{text}");
    assert!(tally.labels > 0, "{text}");
    assert!(tally.problems.is_empty(), "{text}");
}
