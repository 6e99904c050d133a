//! Differential test against SPIN (docs/testing/spin.md): generated
//! components are checked by genom-check's explorer (untimed semantics) and,
//! exported with `export promela`, by SPIN; both must give the same
//! verdicts: deadlock or not, the set of dead services, the set of codels no
//! execution runs.
//!
//! Needs `spin` and `gcc` on the `PATH`. Without them the test prints a note
//! and passes, unless `GENOM_REQUIRE_SPIN=1` (CI), when it fails.

#![allow(clippy::expect_used, clippy::print_stderr)] // test support code

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use gen_frontend::FsLoader;
use genom_check::{CheckOptions, check_source};
use genom_export::{ExportInput, Format, Verification, export};
use genom_generate::{GeneratorConfig, generate};
use genom_model::component::{Component, Idx};
use genom_model::{Code, Diagnostic, Severity};

/// Components generated untimed and checked by the whole pipeline.
const UNTIMED: u64 = 200;
/// Components generated with `max-time`s, checked by the untimed explorer
/// directly (the pipeline would use the timed engine): the watchdog.
const WATCHDOG: u64 = 60;
/// Worker threads (the machine's cores are shared).
const WORKERS: usize = 2;

/// The verdicts compared.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Verdicts {
    deadlock: bool,
    dead: BTreeSet<String>,
    unreachable: BTreeSet<String>,
}

/// One generated component, what both sides said, and why they differ.
struct Case {
    name: String,
    text: String,
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

/// A configuration from a seed: 2–5 services of 2–4 codels on 1–2
/// threads, rules, init, autos, setters and self-stops at random.
fn config(seed: u64, timed: bool) -> GeneratorConfig {
    let mut cfg = GeneratorConfig::small(seed.wrapping_mul(0x9E37_79B9) ^ 0x51ED);
    cfg.services = 2 + (seed % 4) as usize;
    cfg.codels_per_service = 2 + ((seed / 4) % 3) as usize;
    cfg.threads = cfg.threads.min(2);
    cfg.autos = cfg.autos.min(1);
    // `auto` services that delay or forbid others: dead services.
    cfg.auto_rules = cfg.autos > 0 && seed % 3 == 0;
    cfg.rule_density = 0.5 + ((seed / 12) % 5) as f64 * 0.5;
    cfg.timed = timed;
    cfg
}

/// What genom-check found about one component.
struct Ours {
    component: Component,
    sources: genom_model::SourceMap,
    diagnostics: Vec<Diagnostic>,
    states: u64,
}

/// genom-check's verdicts: the whole pipeline when `pipeline` (untimed
/// components), else the static checks, then the untimed explorer and the
/// behavioural checks (the pipeline would use the timed engine). `None`
/// for a file with static errors (a fixture of a static error).
fn ours(path: &Path, text: &str, pipeline: bool) -> Option<Ours> {
    let options = CheckOptions::new().behaviour(pipeline);
    let result = check_source(path, text.to_owned(), &FsLoader, &options);
    if result
        .diagnostics
        .iter()
        .any(|d| d.severity == Severity::Error && !behavioural(d.code))
    {
        return None;
    }
    let component = result.component?;
    let mut diagnostics = result.diagnostics;
    let states = if pipeline {
        let stats = result.statistics.expect("the engines ran");
        assert!(stats.complete, "incomplete exploration: {}", path.display());
        stats.states
    } else {
        let limits = genom_checker::dialect::Limits::default();
        let analysis = genom_checker::dialect::analyse(&component, limits);
        assert!(analysis.stopped.is_none(), "incomplete: {}", path.display());
        diagnostics.extend(genom_checker::checks::behaviour(&component, &analysis));
        analysis.states
    };
    Some(Ours {
        component,
        sources: result.sources,
        diagnostics,
        states,
    })
}

/// Generated components must have no static problem at all.
fn assert_no_static_problem(text: &str, diagnostics: &[Diagnostic]) {
    let problems: Vec<&Diagnostic> = diagnostics
        .iter()
        .filter(|d| d.severity >= Severity::Warning && !behavioural(d.code))
        .filter(|d| d.code != Code::UnreachableCodel)
        .collect();
    assert!(
        problems.is_empty(),
        "static problems in\n{text}\n{problems:?}"
    );
}

fn behavioural(code: Code) -> bool {
    matches!(
        code,
        Code::Deadlock | Code::Starvation | Code::DeadService | Code::UnboundedInterrupt
    )
}

/// Reads our verdicts off the diagnostics, by their primary spans.
fn our_verdicts(c: &Component, diagnostics: &[Diagnostic]) -> Verdicts {
    let primary = |code: Code| -> Vec<genom_model::Span> {
        diagnostics
            .iter()
            .filter(|d| d.code == code)
            .filter_map(|d| d.labels.first().map(|l| l.span))
            .collect()
    };
    let dead_spans = primary(Code::DeadService);
    let codel_spans = primary(Code::UnreachableCodel);
    Verdicts {
        deadlock: diagnostics.iter().any(|d| d.code == Code::Deadlock),
        dead: c
            .services
            .values()
            .filter(|s| dead_spans.contains(&s.name.span))
            .map(|s| s.name.name.clone())
            .collect(),
        unreachable: c
            .codels
            .ids()
            .filter(|&k| codel_spans.contains(&c.codels[k].name.span))
            .map(|k| c.codel_label(k))
            .collect(),
    }
}

/// Occurrences of `prefix<number> = 1` in `text`, by number.
fn markers(text: &str, prefix: &str) -> Vec<usize> {
    let mut out = Vec::new();
    for (at, _) in text.match_indices(prefix) {
        let rest = &text[at + prefix.len()..];
        let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
        let boundary = text[..at]
            .chars()
            .next_back()
            .is_none_or(|ch| !(ch.is_ascii_alphanumeric() || ch == '_'));
        if boundary && !digits.is_empty() && rest[digits.len()..].starts_with(" = 1") {
            out.push(digits.parse().expect("a number"));
        }
    }
    out
}

/// The indices whose every marker copy SPIN reports as unreached.
fn never(model: &str, report: &str, prefix: &str) -> BTreeSet<usize> {
    let all = markers(model, prefix);
    let missed = markers(report, prefix);
    all.iter()
        .copied()
        .filter(|k| {
            let total = all.iter().filter(|x| *x == k).count();
            missed.iter().filter(|x| *x == k).count() == total
        })
        .collect()
}

fn run(dir: &Path, program: &str, args: &[&str]) -> String {
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
    assert!(out.status.success(), "{program} {args:?} failed:\n{text}");
    text
}

/// SPIN's verdicts on the model: generate, compile and run the verifier.
fn spin(dir: &Path, c: &Component, model: &str) -> (Verdicts, String) {
    std::fs::create_dir_all(dir).expect("work directory");
    std::fs::write(dir.join("model.pml"), model).expect("model written");
    run(dir, "spin", &["-a", "-o3", "model.pml"]);
    run(
        dir,
        "gcc",
        &["-O0", "-DSAFETY", "-DNOREDUCE", "-o", "pan", "pan.c"],
    );
    let pan = dir.join("pan");
    let report = run(
        dir,
        pan.to_str().expect("UTF-8 path"),
        &["-c0", "-m2000000", "-w20"],
    );
    let errors: Vec<&str> = report.lines().filter(|l| l.starts_with("pan:")).collect();
    for bad in [
        "invalid end state",
        "max search depth too small",
        "VECTORSZ",
    ] {
        let found = errors.iter().any(|l| l.contains(bad)) || report.contains("error: ");
        assert!(!found, "SPIN: {bad}\n{model}\n{report}");
    }
    let unreached = report
        .find("unreached in proctype")
        .map_or("", |at| &report[at..]);
    let dead_ids = never(model, unreached, "started_");
    let dead: BTreeSet<String> = c
        .services
        .iter()
        .filter(|(id, _)| dead_ids.contains(&id.index()))
        .map(|(_, s)| s.name.name.clone())
        .collect();
    let unreachable = never(model, unreached, "ran_")
        .into_iter()
        .filter_map(|k| c.codels.ids().find(|id| id.index() == k))
        .filter(|&k| !dead.contains(&c.services[c.codels[k].service].name.name))
        .map(|k| c.codel_label(k))
        .collect();
    let stored = report
        .lines()
        .find(|l| l.contains("states, stored"))
        .map_or(String::new(), |l| l.trim().to_owned());
    let verdicts = Verdicts {
        deadlock: errors.iter().any(|l| l.contains("assertion violated")),
        dead,
        unreachable,
    };
    (verdicts, stored)
}

/// One component to compare: generated (seed, with `max-time`s or not) or
/// a file of the repository.
#[derive(Debug, Clone)]
enum Job {
    Generated(u64, bool),
    File(PathBuf),
}

fn one(job: &Job, work: &Path) -> Option<Case> {
    let (name, path, text, pipeline) = match job {
        Job::Generated(seed, timed) => {
            let kind = if *timed { "watchdog" } else { "untimed" };
            let text = generate(&config(*seed, *timed));
            (
                format!("{kind}-{seed}"),
                PathBuf::from("generated.gen"),
                text,
                !*timed,
            )
        }
        Job::File(path) => {
            let text = std::fs::read_to_string(path).expect("readable");
            let name = path.to_string_lossy().replace(['/', '\\'], "_");
            (name, path.clone(), text, false)
        }
    };
    let ours = ours(&path, &text, pipeline)?;
    if matches!(job, Job::Generated(..)) {
        assert_no_static_problem(&text, &ours.diagnostics);
    }
    let verification = Verification::default();
    let input = ExportInput {
        component: &ours.component,
        sources: &ours.sources,
        verification: &verification,
    };
    let model = export(Format::Promela, &input).expect("exports").main;
    let (spin, stored) = spin(&work.join(&name), &ours.component, &model);
    Some(Case {
        name,
        text,
        model,
        ours: our_verdicts(&ours.component, &ours.diagnostics),
        spin,
        states: format!("genom-check {} states, SPIN {stored}", ours.states),
    })
}

/// The repository's components: `specs/` and the fixtures without static
/// errors (the verdict fixtures among them).
fn files() -> Vec<Job> {
    let mut out = Vec::new();
    for dir in [
        "specs",
        "tests/fixtures/valid",
        "tests/fixtures/invalid",
        "tests/fixtures/timing",
    ] {
        let Ok(entries) = std::fs::read_dir(dir) else {
            continue;
        };
        let mut paths: Vec<PathBuf> = entries
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|x| x == "gen"))
            .collect();
        paths.sort();
        out.extend(paths.into_iter().map(Job::File));
    }
    out
}

#[test]
#[cfg_attr(
    not(genom_spin),
    ignore = "needs `spin` and `gcc` on the PATH when the tests are built (GENOM_REQUIRE_SPIN=1 makes their absence a failure)"
)]
fn spin_agrees_with_the_explorer_on_generated_components() {
    let required = std::env::var("GENOM_REQUIRE_SPIN").is_ok_and(|v| v == "1");
    if !(tool_present("spin", "-V") && tool_present("gcc", "--version")) {
        assert!(
            !required,
            "GENOM_REQUIRE_SPIN=1 but `spin` or `gcc` is missing"
        );
        eprintln!("note: `spin` or `gcc` not installed: SPIN differential test skipped");
        return;
    }
    let started = Instant::now();
    let temp = tempfile::tempdir().expect("temporary directory");
    let keep = std::env::var_os("GENOM_SPIN_KEEP").map(PathBuf::from);
    let work = keep.as_deref().unwrap_or(temp.path());
    let jobs: Vec<Job> = (0..UNTIMED)
        .map(|s| Job::Generated(s, false))
        .chain((0..WATCHDOG).map(|s| Job::Generated(s, true)))
        .chain(files())
        .collect();
    let next = AtomicUsize::new(0);
    let cases = Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..WORKERS {
            scope.spawn(|| {
                while let Some(job) = jobs.get(next.fetch_add(1, Ordering::SeqCst)) {
                    if let Some(case) = one(job, work) {
                        cases.lock().expect("not poisoned").push(case);
                    }
                }
            });
        }
    });
    let mut cases = cases.into_inner().expect("not poisoned");
    cases.sort_by(|a, b| a.name.cmp(&b.name));
    report(&cases, started);
}

fn report(cases: &[Case], started: Instant) {
    let generated = |c: &&Case| c.name.starts_with("untimed-") || c.name.starts_with("watchdog-");
    let agree = |f: &dyn Fn(&&Case) -> bool| {
        let all: Vec<&Case> = cases.iter().filter(f).collect();
        let same = all.iter().filter(|c| c.ours == c.spin).count();
        format!("{same}/{}", all.len())
    };
    let count = |f: &dyn Fn(&Verdicts) -> bool| cases.iter().filter(|c| f(&c.ours)).count();
    eprintln!(
        "SPIN agreement: {} generated components, {} repository files ({} with a deadlock, \
         {} with a dead service, {} with an unreachable codel), {:.1} s",
        agree(&generated),
        agree(&|c| !generated(c)),
        count(&|v| v.deadlock),
        count(&|v| !v.dead.is_empty()),
        count(&|v| !v.unreachable.is_empty()),
        started.elapsed().as_secs_f64()
    );
    let keep = std::env::var_os("GENOM_SPIN_KEEP").map(PathBuf::from);
    let mut failures = String::new();
    for case in cases.iter().filter(|c| c.ours != c.spin) {
        if let Some(dir) = &keep {
            std::fs::create_dir_all(dir).expect("keep directory");
            std::fs::write(dir.join(format!("{}.gen", case.name)), &case.text).expect("kept");
            std::fs::write(dir.join(format!("{}.pml", case.name)), &case.model).expect("kept");
        }
        failures.push_str(&format!(
            "\n== {} ({})\ngenom-check: {:?}\nSPIN:        {:?}\n{}",
            case.name, case.states, case.ours, case.spin, case.text
        ));
    }
    assert!(failures.is_empty(), "SPIN disagrees:{failures}");
}
