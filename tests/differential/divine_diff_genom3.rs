//! Differential test of the UPPAAL export of GenoM3 components against
//! DIVINE 3.3.2's UPPAAL front-end (its timed-automata generator, built
//! from `paradise-fi/divine` commit `cb31f33ea`, docs/testing/divine.md).
//!
//! For the timed fixtures of `tests/fixtures/genom3/timing/` and
//! `tests/fixtures/genom3/response/` (each `.gen` with its `.wcet`), the
//! untimed fixtures of `tests/fixtures/genom3/semantics/` (codel queries
//! only), the small corpus components (uavatt, uavvs, uavpos, when the
//! corpus is on the machine) and a few generated timed components, every
//! query of the exported `.q` file is asked to DIVINE:
//!
//! - `E<> P.L` or `E<> (P.L || P.M ...)` (a codel label, in each slot of
//!   its activity) and `A[] not task_T.overrun` (a periodic task) both
//!   become the LTL property `G !(...)` of a `.ltl` file beside the model,
//!   one `#define` per location (DIVINE's front-end takes no disjunction
//!   inside a `#define`); the label is reachable for DIVINE exactly when
//!   `divine verify -p N model.xml` says the property does not hold.
//! - genom-check's verdict on the label is read from its diagnostics as
//!   the TChecker test does (`genom3_verdicts.rs`: a `thread-overrun`, or a
//!   `codel-overrun` with a trace, for an overrun; a codel is reachable
//!   unless its activity is a `dead-service`, the state has an
//!   `unreachable-codel`, or no path of yields leads to it); both must
//!   agree. There is no `A[] not deadlock` query for GenoM3: a correct
//!   component may stop for good.
//! - On every timed component that genom-check verifies (no error) and
//!   whose codels all run (no `unreachable-codel` warning), every query of
//!   the `.q` file must hold in DIVINE: the queries are those that hold on
//!   a correct GenoM3 component. (The `E<>` query of a codel genom-check
//!   warns unreachable fails, as the warning says; the label comparison
//!   above checks that.)
//!
//! Runs only when `DIVINE` names the `divine` executable
//! (`DIVINE=/path/to/divine/_build/tools/divine cargo test --test
//! differential divine_diff_genom3:: -- --nocapture`): when it did not at
//! build time (`build.rs`, `cfg(genom_divine)`) the test shows as
//! `ignored` with its reason; when it does not at run time, it prints a
//! note and passes. `DIVINE_GENOM3_SEEDS` (a count `N` or a range `A..B`,
//! default 10) chooses the generated components; `DIVINE_KEEP` a directory
//! that keeps the models (`NAME.xml`, `NAME.ltl`, `NAME.q`) and generated
//! sources; `DIVINE_MEMORY_MB` (default 2048) is passed as `--max-memory`.
//! Each DIVINE run is killed after 60 seconds: its query is then undecided,
//! counted and listed, not failed.

#![allow(clippy::print_stdout, clippy::print_stderr)] // test harness

use crate::genom3_verdicts::{
    Case, Tally, corpus, distinct_labels, fixtures, generated, prepare, seed_range,
};

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use genom_export::{ExportInput, Format, Verification};
use genom_model::Severity;

const DIVINE_TIMEOUT: Duration = Duration::from_secs(60);

/// One query of the `.q` file.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Query {
    /// The label it asks about (the comment's first word).
    label: String,
    /// The formula as written.
    formula: String,
    /// `A[] not ...` (holds when the label is unreachable); otherwise
    /// `E<> ...` (holds when it is reachable).
    universal: bool,
    /// The locations of the label, `P.L`.
    places: Vec<String>,
}

impl Query {
    /// Whether the query holds when its label is `reachable`.
    fn holds(&self, reachable: bool) -> bool {
        reachable != self.universal
    }
}

/// The queries of a `.q` file: a `/* LABEL: ... */` comment, then the
/// formula, `E<> X` or `A[] not X` with `X` a location `P.L` or a
/// parenthesised disjunction of locations.
fn parse_queries(text: &str) -> Result<Vec<Query>, String> {
    let mut out = Vec::new();
    let mut label: Option<String> = None;
    for line in text.lines().map(str::trim) {
        if line.is_empty() || line.starts_with("//") {
            continue;
        }
        if let Some(c) = line.strip_prefix("/*") {
            let name = c.split(':').next().unwrap_or_default().trim();
            label = Some(name.to_owned());
            continue;
        }
        let (universal, body) = if let Some(b) = line.strip_prefix("E<> ") {
            (false, b)
        } else if let Some(b) = line.strip_prefix("A[] not ") {
            (true, b)
        } else {
            return Err(format!("unexpected query `{line}`"));
        };
        let inner = body
            .strip_prefix('(')
            .and_then(|b| b.strip_suffix(')'))
            .unwrap_or(body);
        let places: Vec<String> = inner.split("||").map(|p| p.trim().to_owned()).collect();
        let location = |p: &String| {
            p.split_once('.').is_some_and(|(a, b)| {
                [a, b].iter().all(|x| {
                    !x.is_empty() && x.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
                })
            })
        };
        if !places.iter().all(location) {
            return Err(format!("not a disjunction of locations: `{line}`"));
        }
        let label = label
            .take()
            .ok_or_else(|| format!("no comment before `{line}`"))?;
        out.push(Query {
            label,
            formula: line.to_owned(),
            universal,
            places,
        });
    }
    Ok(out)
}

/// The `.ltl` file of the queries: property `i` is `G !(...)` over the
/// locations of query `i`, each named by a `#define`.
fn ltl_file(queries: &[Query]) -> String {
    let mut out = String::from("// The queries of the UPPAAL export, as DIVINE LTL properties.\n");
    for (i, q) in queries.iter().enumerate() {
        let _ = writeln!(out, "// {}: {}", i, q.formula);
        let mut atoms = Vec::new();
        for (j, place) in q.places.iter().enumerate() {
            let _ = writeln!(out, "#define q{i}_{j} ({place})");
            atoms.push(format!("q{i}_{j}"));
        }
        let _ = writeln!(out, "#property G !({})", atoms.join(" || "));
    }
    out
}

/// What DIVINE says about property `index` of `model` (`G !X`): whether
/// it holds; `Ok(None)` when the run hit the time or memory limit.
fn divine(exe: &Path, model: &Path, index: usize) -> Result<Option<bool>, String> {
    let mb = std::env::var("DIVINE_MEMORY_MB").ok().map_or(2048, |s| {
        s.parse::<u64>().expect("DIVINE_MEMORY_MB: an integer")
    });
    let mut child = Command::new(exe)
        .args(["verify", "-r", "-n", "-w", "1"])
        .arg(format!("--max-memory={mb}"))
        .arg("-p")
        .arg(index.to_string())
        .arg(model)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot run {}: {e}", exe.display()))?;
    // Read the pipes while waiting, so that a large output cannot block it.
    let mut stdout = child.stdout.take().expect("a pipe");
    let mut stderr = child.stderr.take().expect("a pipe");
    let out_reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut stdout, &mut s);
        s
    });
    let err_reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut stderr, &mut s);
        s
    });
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break status;
        }
        if started.elapsed() > DIVINE_TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            return Ok(None);
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let stdout = out_reader.join().unwrap_or_default();
    let stderr = err_reader.join().unwrap_or_default();
    let all = format!("{stdout}{stderr}");
    if all.contains("Memory limit exceeded") || all.contains("Time limit exceeded") {
        return Ok(None);
    }
    // DIVINE prints an LTL syntax error of any property of the file, and
    // then may still answer: any error is a failure.
    if let Some(e) = all
        .lines()
        .find(|l| l.trim_start().starts_with("Error") || l.contains("FATAL ERROR"))
    {
        return Err(format!("DIVINE: {}", e.trim()));
    }
    if !status.success() {
        return Err(format!("DIVINE failed ({status}): {}", all.trim()));
    }
    match stdout
        .lines()
        .find_map(|l| l.strip_prefix("Property-Holds:"))
        .map(str::trim)
    {
        Some("Yes") => Ok(Some(true)),
        Some("No") => Ok(Some(false)),
        _ => Err(format!("no verdict: {}", all.trim())),
    }
}

/// The totals of the DIVINE comparison.
#[derive(Default)]
struct Run {
    tally: Tally,
    /// Queries run.
    queries: usize,
    /// Queries of verified timed components that do not hold in DIVINE.
    failing: Vec<String>,
    /// Queries of verified timed components, and how many hold.
    verified_queries: usize,
    verified_hold: usize,
    verified_components: usize,
    /// Runs killed at the limit.
    undecided: Vec<String>,
}

fn divine_case(case: &Case, exe: &Path, dir: &Path, run: &mut Run) {
    let Some((r, v, net)) = prepare(case) else {
        run.tally
            .skipped
            .push(format!("{} (genom-check incomplete)", case.name));
        return;
    };
    let c = r.component.as_ref().expect("a component");
    let verification = Verification::default();
    let input = ExportInput {
        component: c,
        sources: &r.sources,
        verification: &verification,
    };
    let exported = genom_export::export(Format::Uppaal, &input).expect("the export succeeds");
    let q_text = exported
        .extra
        .iter()
        .find(|(suffix, _)| suffix == ".q")
        .map(|(_, text)| text.clone())
        .expect("the export has a query file");
    let queries = match parse_queries(&q_text) {
        Ok(q) => q,
        Err(e) => {
            run.tally.problems.push(format!("{}: {e}", case.name));
            return;
        }
    };
    let model = dir.join(format!("{}.xml", case.name));
    std::fs::write(&model, &exported.main).expect("writes the model");
    std::fs::write(dir.join(format!("{}.q", case.name)), &q_text).expect("writes the queries");
    std::fs::write(dir.join(format!("{}.ltl", case.name)), ltl_file(&queries))
        .expect("writes the properties");
    let labels = distinct_labels(&net);
    let (problems, failing) = (run.tally.problems.len(), run.failing.len());
    // A timed component genom-check verifies, without a codel it warns
    // unreachable (whose `E<>` query fails, as the warning says): every
    // query must hold.
    let verified = case.wcet.is_some()
        && !r.diagnostics.iter().any(|d| {
            d.severity == Severity::Error || d.code == genom_model::Code::UnreachableCodel
        });
    run.verified_components += usize::from(verified);
    let started = Instant::now();
    for (i, q) in queries.iter().enumerate() {
        run.queries += 1;
        let Some(label) = labels.iter().find(|l| l.name == q.label) else {
            run.tally
                .problems
                .push(format!("{}: `{}`: no such label", case.name, q.formula));
            continue;
        };
        let reachable = match divine(exe, &model, i) {
            Ok(Some(holds_g_not)) => Ok(!holds_g_not),
            Ok(None) => {
                run.undecided
                    .push(format!("{}: {} (DIVINE limit)", case.name, q.formula));
                continue;
            }
            Err(e) => Err(e),
        };
        if verified {
            run.verified_queries += 1;
            match &reachable {
                Ok(b) if q.holds(*b) => run.verified_hold += 1,
                Ok(_) => run.failing.push(format!(
                    "{}: `{}` does not hold in DIVINE",
                    case.name, q.formula
                )),
                Err(e) => run
                    .failing
                    .push(format!("{}: `{}`: {e}", case.name, q.formula)),
            }
        }
        if let Some(expected) = v.expects(c, label) {
            run.tally.record(&case.name, &q.label, expected, reachable);
        } else if let Err(e) = reachable {
            run.tally
                .problems
                .push(format!("{}: `{}`: {e}", case.name, q.formula));
        }
    }
    run.tally.components += 1;
    eprintln!(
        "{}: {} queries, DIVINE {:.1?}",
        case.name,
        queries.len(),
        started.elapsed()
    );
    // Shown at once too, so that a long run interrupted still tells.
    for p in &run.tally.problems[problems..] {
        eprintln!("  DISAGREEMENT {p}");
    }
    for f in &run.failing[failing..] {
        eprintln!("  FAILS {f}");
    }
}

#[test]
#[cfg_attr(
    not(genom_divine),
    ignore = "needs DIVINE=path/to/divine when the tests are built (see docs/testing/divine.md)"
)]
fn genom3_uppaal_queries_agree_with_divine() {
    let Some(exe) = std::env::var_os("DIVINE")
        .map(PathBuf::from)
        .filter(|p| p.is_file())
    else {
        eprintln!(
            "note: DIVINE is not set to a divine executable; the GenoM3 UPPAAL/DIVINE \
             differential test is skipped (see docs/testing/divine.md)"
        );
        return;
    };
    let tmp = tempfile::tempdir().expect("a temporary directory");
    let dir = std::env::var_os("DIVINE_KEEP").map_or_else(|| tmp.path().to_owned(), PathBuf::from);
    std::fs::create_dir_all(&dir).expect("creates DIVINE_KEEP");
    let started = Instant::now();
    let mut run = Run::default();
    let cases = fixtures()
        .into_iter()
        .chain(corpus())
        .chain(generated(&dir, seed_range("DIVINE_GENOM3_SEEDS", 10)));
    for case in cases {
        divine_case(&case, &exe, &dir, &mut run);
    }
    let mut text = run.tally.report("divine");
    let _ = writeln!(
        text,
        "{} queries run in {:.1?}; on {} verified timed components {}/{} queries hold; \
         {} undecided (60 s or memory limit) {:?}",
        run.queries,
        started.elapsed(),
        run.verified_components,
        run.verified_hold,
        run.verified_queries,
        run.undecided.len(),
        run.undecided
    );
    for f in &run.failing {
        let _ = writeln!(text, "FAILS {f}");
    }
    println!("{text}");
    assert!(run.tally.labels > 0, "{text}");
    assert!(run.verified_queries > 0, "{text}");
    assert!(run.tally.problems.is_empty(), "{text}");
    assert!(run.failing.is_empty(), "{text}");
}

#[test]
fn queries_are_read_and_written_as_ltl() {
    let q = "// header\n\n/* overrun_t: the task never overruns its period */\n\
             A[] not task_t.overrun\n\n/* codel_a_start: the codel can run */\n\
             E<> (task_t.a_start || task_t.a_2_start)\n";
    let queries = parse_queries(q).expect("the queries parse");
    assert_eq!(queries.len(), 2);
    assert_eq!(queries[0].label, "overrun_t");
    assert!(queries[0].universal && !queries[0].holds(true) && queries[0].holds(false));
    assert_eq!(queries[1].places, ["task_t.a_start", "task_t.a_2_start"]);
    assert!(queries[1].holds(true) && !queries[1].holds(false));
    let ltl = ltl_file(&queries);
    assert!(ltl.contains("#define q1_1 (task_t.a_2_start)\n"), "{ltl}");
    assert!(ltl.contains("#property G !(q1_0 || q1_1)\n"), "{ltl}");
    assert!(parse_queries("E<> deadlock or x\n").is_err());
}
