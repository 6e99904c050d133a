//! Differential test of the timed verdicts against TChecker: for generated
//! timed components, every label of the `tchecker` export (a codel runs, a
//! thread overruns, a service exceeds its max-time) must be reachable for
//! `tck-reach` exactly when genom-check's zone engine says so.
//!
//! Runs only when the environment variable `TCK_REACH` names a `tck-reach`
//! executable (docs/testing/tchecker.md says how to build one); otherwise
//! it prints a note and passes. Other variables:
//!
//! - `TCK_COMPONENTS`: number of components to compare (default 100);
//! - `TCK_SEEDS`: comma-separated seeds to compare instead (to replay a
//!   disagreement);
//! - `TCK_ALGO`: the `tck-reach` algorithm (default `covreach`);
//! - `TCK_KEEP`: a directory where every exported model is kept as
//!   `seed-N.tck` next to its component `seed-N.gen`.
//!
//! What genom-check says about a label:
//!
//! - `codel_S_C` (start, exec or inter codel): reachable unless `S` is a
//!   `dead-service` or `C` has an `unreachable-codel` (LANGUAGE.md section
//!   4: a dead service's codels get no `unreachable-codel`);
//! - `codel_S_control`: genom-check gives no verdict on control codels;
//!   the control codel runs when `S` is accepted, so it is reachable when
//!   `S` is not dead, and unreachable when `S` is dead and has no start
//!   codel (dead then means never accepted); a dead service with a start
//!   codel may still run its control codel (accepted, then pending forever),
//!   so that label is left out of the comparison and counted apart;
//! - `overrun_T`: a `thread-overrun` diagnostic on thread `T`;
//! - `timeout_S`: a `max-time-exceeded` or `max-time-infeasible` diagnostic
//!   on service `S`.
//!
//! A component whose check is `incomplete` is skipped (and replaced by the
//! next seed).

#![allow(clippy::expect_used, clippy::print_stdout, clippy::print_stderr)] // test harness

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use genom_check::{CheckOptions, CheckResult};
use genom_export::{ExportInput, Format, Verification};
use genom_generate::{GeneratorConfig, generate};
use genom_model::behaviour::Behaviour;
use genom_model::component::Component;
use genom_model::kinds::CodelKind;
use genom_model::timed_automata::{Label, LabelKind, Network};
use genom_model::{Code, Span};
use genom_translate::timed_automata::BuildNetwork;

/// Time allowed to one `tck-reach` run.
const TCK_TIMEOUT: Duration = Duration::from_secs(30);

/// Time allowed to genom-check on one component (then `incomplete`, and
/// the component is skipped).
const CHECK_TIMEOUT: Duration = Duration::from_secs(10);

/// The memory limit of one `tck-reach` run in KiB: `TCK_MEMORY_MB`
/// (default 2048 MiB).
fn tck_memory_kib() -> u64 {
    let mb = std::env::var("TCK_MEMORY_MB")
        .ok()
        .map_or(2048, |s| s.parse().expect("TCK_MEMORY_MB: an integer"));
    mb * 1024
}

/// Seeds tried at most, to find enough complete components.
const MAX_SEEDS: u64 = 1000;

/// The `tck-reach` executable named by `TCK_REACH`, if it is a file.
fn tck_reach() -> Option<PathBuf> {
    let path = PathBuf::from(std::env::var_os("TCK_REACH")?);
    path.is_file().then_some(path)
}

/// A small timed component configuration derived from the seed.
fn config(seed: u64) -> GeneratorConfig {
    let mut c = GeneratorConfig::small(seed);
    c.timed = true;
    c.services = c.services.min(3);
    c.codels_per_service = c.codels_per_service.min(2);
    c.threads = c.threads.min(2);
    c
}

/// genom-check's timed verdicts, by the primary span of the diagnostic.
#[derive(Debug, Default)]
struct Verdicts {
    unreachable: BTreeSet<Span>,
    dead: BTreeSet<Span>,
    overrun: BTreeSet<Span>,
    timeout: BTreeSet<Span>,
    incomplete: bool,
}

impl Verdicts {
    fn of(result: &CheckResult) -> Verdicts {
        let mut v = Verdicts::default();
        for d in &result.diagnostics {
            let span = d.labels.first().map(|l| l.span).unwrap_or_default();
            let set = match d.code {
                Code::UnreachableCodel => &mut v.unreachable,
                Code::DeadService => &mut v.dead,
                Code::ThreadOverrun => &mut v.overrun,
                Code::MaxTimeExceeded | Code::MaxTimeInfeasible => &mut v.timeout,
                Code::Incomplete => {
                    v.incomplete = true;
                    continue;
                }
                _ => continue,
            };
            set.insert(span);
        }
        v
    }

    /// Whether genom-check finds the label reachable (`None`: no verdict).
    fn expects(&self, c: &Component, kind: LabelKind) -> Option<bool> {
        match kind {
            LabelKind::Codel(id) => {
                let codel = &c.codels[id];
                let service = &c.services[codel.service];
                let dead = self.dead.contains(&service.name.span);
                if codel.kind == CodelKind::Control {
                    return match (dead, service.start) {
                        (false, _) => Some(true),
                        (true, None) => Some(false),
                        (true, Some(_)) => None,
                    };
                }
                Some(!dead && !self.unreachable.contains(&codel.name.span))
            }
            LabelKind::Overrun(t) => Some(self.overrun.contains(&c.threads[t].name.span)),
            LabelKind::Timeout(s) => Some(self.timeout.contains(&c.services[s].name.span)),
        }
    }
}

/// What `tck-reach` said about one label.
#[derive(Debug)]
enum Answer {
    /// `REACHABLE true|false`.
    Verdict(bool),
    /// It ran out of time or memory: no verdict, the component is skipped.
    Limit(String),
}

/// Runs `tck-reach` on the model for one label: its answer, or the reason
/// it failed (a model it cannot read, an unknown label).
fn tck_verdict(tck: &Path, algo: &str, model: &Path, label: &str) -> Result<Answer, String> {
    // A shell sets the memory limit: tck-reach can use many GiB on a
    // large zone graph.
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v {}; exec \"$0\" -a \"$1\" -l \"$2\" \"$3\"",
            tck_memory_kib()
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
            return Ok(Answer::Limit(format!("timeout after {TCK_TIMEOUT:?}")));
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    let out = child.wait_with_output().map_err(|e| e.to_string())?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    let answer = stdout.lines().find_map(|l| l.strip_prefix("REACHABLE "));
    let stderr = String::from_utf8_lossy(&out.stderr);
    match answer.map(str::trim) {
        Some("true") => Ok(Answer::Verdict(true)),
        Some("false") => Ok(Answer::Verdict(false)),
        _ if stderr.contains("bad_alloc") || out.status.code().is_none() => Ok(Answer::Limit(
            format!("out of memory or killed: {}", stderr.trim()),
        )),
        _ => Err(format!(
            "no verdict (exit {:?}): {}{}",
            out.status.code(),
            stdout.trim(),
            stderr.trim()
        )),
    }
}

/// Totals of the comparison.
#[derive(Debug, Default)]
struct Tally {
    components: usize,
    skipped_incomplete: Vec<u64>,
    skipped_tck: Vec<u64>,
    labels: usize,
    agree: usize,
    no_verdict_genom: usize,
    reachable: usize,
    by_kind: [(usize, usize); 4],
    problems: Vec<String>,
}

/// Index in [`Tally::by_kind`]: codel, control codel, overrun, timeout.
fn kind_index(c: &Component, kind: LabelKind) -> usize {
    match kind {
        LabelKind::Codel(id) if c.codels[id].kind == CodelKind::Control => 1,
        LabelKind::Codel(_) => 0,
        LabelKind::Overrun(_) => 2,
        LabelKind::Timeout(_) => 3,
    }
}

/// Checks one generated component with both tools; returns false when it
/// was skipped.
fn compare(seed: u64, tck: &Path, algo: &str, dir: &Path, tally: &mut Tally) -> bool {
    let started = Instant::now();
    let text = generate(&config(seed));
    let result = genom_check::check_source(
        Path::new("generated.gen"),
        text.clone(),
        &gen_frontend::MemoryLoader::new(),
        &CheckOptions::new()
            .max_states(2_000_000)
            .timeout(Some(CHECK_TIMEOUT)),
    );
    let check_time = started.elapsed();
    let verdicts = Verdicts::of(&result);
    if verdicts.incomplete {
        eprintln!("seed {seed}: incomplete after {check_time:.1?}, skipped");
        tally.skipped_incomplete.push(seed);
        return false;
    }
    let c = result
        .component
        .as_ref()
        .expect("a generated component resolves");
    tally.components += 1;
    let verification = Verification::default();
    let input = ExportInput {
        component: c,
        sources: &result.sources,
        verification: &verification,
    };
    let model = match genom_export::export(Format::Tchecker, &input) {
        Ok(m) => m.main,
        Err(e) => {
            eprintln!("seed {seed}: export failed after {check_time:.1?}");
            tally
                .problems
                .push(format!("seed {seed}: export failed: {e}"));
            return true;
        }
    };
    let gen_path = dir.join(format!("seed-{seed}.gen"));
    let tck_path = dir.join(format!("seed-{seed}.tck"));
    std::fs::write(&gen_path, &text).expect("writes the component");
    std::fs::write(&tck_path, &model).expect("writes the model");
    let net = Network::build(c, &Behaviour::new(c));
    let tck_started = Instant::now();
    let mut answers = Vec::new();
    for label in &net.labels {
        let expected = verdicts.expects(c, label.kind);
        let answer = match expected {
            None => None,
            Some(_) => match tck_verdict(tck, algo, &tck_path, &label.name) {
                Ok(Answer::Limit(why)) => {
                    eprintln!("seed {seed}: {}: tck-reach {why}, skipped", label.name);
                    tally.components -= 1;
                    tally.skipped_tck.push(seed);
                    return false;
                }
                Ok(Answer::Verdict(b)) => Some(Ok(b)),
                Err(why) => Some(Err(why)),
            },
        };
        answers.push((label, expected, answer));
    }
    let before = tally.problems.len();
    for (label, expected, answer) in answers {
        tally.record(seed, c, label, expected, answer);
    }
    eprintln!(
        "seed {seed}: {} labels, genom-check {check_time:.1?}, tck-reach {:.1?}{}",
        net.labels.len(),
        tck_started.elapsed(),
        if tally.problems.len() > before {
            ", DISAGREEMENT"
        } else {
            ""
        }
    );
    true
}

impl Tally {
    /// Counts one label: genom-check's verdict and tck-reach's answer.
    fn record(
        &mut self,
        seed: u64,
        c: &Component,
        label: &Label,
        expected: Option<bool>,
        answer: Option<Result<bool, String>>,
    ) {
        let (Some(expected), Some(answer)) = (expected, answer) else {
            self.no_verdict_genom += 1;
            return;
        };
        self.labels += 1;
        let k = kind_index(c, label.kind);
        self.by_kind[k].0 += 1;
        match answer {
            Ok(got) if got == expected => {
                self.agree += 1;
                self.by_kind[k].1 += 1;
                self.reachable += usize::from(got);
            }
            Ok(got) => self.problems.push(format!(
                "seed {seed}: {}: genom-check {}, tck-reach {}",
                label.name,
                reach_word(expected),
                reach_word(got)
            )),
            Err(why) => self
                .problems
                .push(format!("seed {seed}: {}: tck-reach: {why}", label.name)),
        }
    }
}

fn reach_word(b: bool) -> &'static str {
    if b { "reachable" } else { "unreachable" }
}

/// The seeds to compare: `TCK_SEEDS`, or the first `TCK_COMPONENTS`
/// complete ones from 0.
fn seeds() -> (Vec<u64>, usize) {
    if let Ok(list) = std::env::var("TCK_SEEDS") {
        let seeds: Vec<u64> = list
            .split(',')
            .map(|s| {
                s.trim()
                    .parse()
                    .expect("TCK_SEEDS: comma-separated integers")
            })
            .collect();
        let n = seeds.len();
        return (seeds, n);
    }
    let wanted = std::env::var("TCK_COMPONENTS")
        .ok()
        .map_or(100, |s| s.parse().expect("TCK_COMPONENTS: an integer"));
    ((0..MAX_SEEDS).collect(), wanted)
}

fn report(t: &Tally, algo: &str, elapsed: Duration) -> String {
    let mut s = String::new();
    let names = ["codel", "control codel", "overrun", "timeout"];
    let _ = writeln!(
        s,
        "tchecker agreement ({algo}): {}/{} labels over {} components ({} reachable); \
         {} control-codel labels without a genom-check verdict; {} components skipped as \
         incomplete {:?}; {} skipped on tck-reach limits {:?}; {:.1} s",
        t.agree,
        t.labels,
        t.components,
        t.reachable,
        t.no_verdict_genom,
        t.skipped_incomplete.len(),
        t.skipped_incomplete,
        t.skipped_tck.len(),
        t.skipped_tck,
        elapsed.as_secs_f64()
    );
    for (name, (n, ok)) in names.iter().zip(t.by_kind) {
        let _ = writeln!(s, "  {name}: {ok}/{n}");
    }
    for p in &t.problems {
        let _ = writeln!(s, "DISAGREEMENT {p}");
    }
    s
}

#[test]
#[cfg_attr(
    not(genom_tchecker),
    ignore = "needs TCK_REACH=path/to/tck-reach when the tests are built (see docs/testing/tchecker.md)"
)]
fn timed_verdicts_agree_with_tchecker() {
    let Some(tck) = tck_reach() else {
        eprintln!(
            "note: TCK_REACH is not set to a tck-reach executable; the TChecker \
             differential test is skipped (see docs/testing/tchecker.md)"
        );
        return;
    };
    let algo = std::env::var("TCK_ALGO").unwrap_or_else(|_| "covreach".to_owned());
    let tmp = tempfile::tempdir().expect("a temporary directory");
    let dir = std::env::var_os("TCK_KEEP").map_or_else(|| tmp.path().to_owned(), PathBuf::from);
    std::fs::create_dir_all(&dir).expect("creates TCK_KEEP");
    let started = Instant::now();
    let (seeds, wanted) = seeds();
    let mut tally = Tally::default();
    for seed in seeds {
        if tally.components >= wanted {
            break;
        }
        compare(seed, &tck, &algo, &dir, &mut tally);
    }
    let text = report(&tally, &algo, started.elapsed());
    println!("{text}");
    assert!(
        tally.components >= wanted,
        "too few complete components\n{text}"
    );
    assert!(tally.labels > 0, "no label compared\n{text}");
    assert!(tally.problems.is_empty(), "{text}");
}
