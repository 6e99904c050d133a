//! Every timed trace checked by the independent timing checker and
//! replayed; corrupted timings rejected; the JSON form of timed traces;
//! the exact margins of max-time on the worked example of
//! `docs/timing.md`, a hand formula for the worst case, and the timing
//! verdicts of `specs/`.

use super::support::{TIMING, TWINS, trace_lines};
use crate::common;

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use genom_check::{CheckOptions, CheckResult};
use genom_model::Code;
use genom_model::component::ServiceId;
use genom_oracles::replay::replay;
use genom_oracles::timed_trace::{TimedClaim, check_timed};
use serde_json::Value;
// ------------------------------------------------------- every timed trace

/// Every trace of every verdict of the timed fixtures (and of `specs/`)
/// has an instant on each step, passes the independent timing checker,
/// and its events replay in the untimed semantics.
#[test]
fn every_timed_trace_is_a_timed_execution_and_replays() {
    let mut files: Vec<PathBuf> = TWINS
        .iter()
        .flat_map(|&(bad, good, _)| [common::invalid(bad), common::valid(good)])
        .collect();
    files.extend(spec_files());
    let mut checked = 0;
    let mut failures = Vec::new();
    for path in &files {
        let result = common::check(path);
        let Some(c) = result.component.as_ref() else {
            continue;
        };
        for d in &result.diagnostics {
            let Some(trace) = &d.trace else { continue };
            checked += 1;
            let names: Vec<&str> = d.message.split('`').skip(1).step_by(2).collect();
            let claim = match d.code {
                Code::ThreadOverrun => TimedClaim::Overrun(names[0]),
                Code::CodelOverrun => TimedClaim::Overrun(names[1]),
                Code::MaxTimeExceeded | Code::MaxTimeInfeasible => {
                    TimedClaim::LateService(names[0])
                }
                _ => TimedClaim::Rules,
            };
            let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
            if let Err(e) = check_timed(c, trace, claim) {
                failures.push(format!("{name}: `{}`: timing: {e}", d.code));
            }
            if let Err(e) = replay(c, trace) {
                failures.push(format!("{name}: `{}`: replay: {e}", d.code));
            }
        }
    }
    assert!(checked >= 7, "only {checked} traces");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The independent checker rejects traces whose timing is wrong.
#[test]
fn the_timing_checker_rejects_corrupted_timings() {
    let path = common::invalid("thread-overrun.two-services-share-a-period.gen");
    let result = common::check(&path);
    let c = common::component(&result);
    let d = result
        .diagnostics
        .iter()
        .find(|d| d.code == Code::ThreadOverrun)
        .expect("the overrun");
    let original = d.trace.clone().expect("a trace");
    let claim = TimedClaim::Overrun("servo");
    check_timed(c, &original, claim).expect("the original is accepted");
    let index = |line: &str| {
        trace_lines(&original)
            .iter()
            .position(|l| l == line)
            .expect("the step exists")
    };
    let corrupt = |k: usize, ns: u64| {
        let mut t = original.clone();
        t.steps[k].time_ns = Some(ns);
        check_timed(c, &t, claim).expect_err("the corrupted trace is rejected")
    };
    // A codel that ends after its WCET.
    let end = index("@16ms codel-end Track::start -> start");
    let mut late = original.clone();
    for s in &mut late.steps[end..] {
        s.time_ns = s.time_ns.map(|t| t.max(17_000_000));
    }
    let why = check_timed(c, &late, claim).expect_err("a codel longer than its WCET");
    assert!(
        why.contains("must have ended") || why.contains("WCET"),
        "{why}"
    );
    // A wake-up off the period (and the violation with it).
    let mut off = original.clone();
    let last = off.steps.len() - 1;
    for s in &mut off.steps[last - 1..] {
        s.time_ns = Some(21_000_000);
    }
    let why = check_timed(c, &off, claim).expect_err("a wake-up off the period");
    assert!(why.contains("should have woken up at 20000000"), "{why}");
    // Time going backwards.
    let why = corrupt(index("@16ms codel-start Scan::start"), 15_000_000);
    assert!(why.contains("backwards"), "{why}");
    // A thread idling although its codel could start (urgency).
    let mut idle = original.clone();
    let start = index("@10ms codel-start Track::start");
    idle.steps[start].time_ns = Some(11_000_000);
    let why = check_timed(c, &idle, claim).expect_err("codel starts are urgent");
    assert!(why.contains("at its turn"), "{why}");
    // Scan before Track although Track was acknowledged first.
    let mut swapped = original.clone();
    let scan = index("@16ms codel-start Scan::start");
    swapped.steps.swap(start, scan);
    swapped.steps[start].time_ns = Some(10_000_000);
    let why = check_timed(c, &swapped, claim).expect_err("acknowledgment order");
    assert!(
        why.contains("not its turn") || why.contains("still runs"),
        "{why}"
    );
    // An overrun claimed on the wrong thread.
    assert!(check_timed(c, &original, TimedClaim::Overrun("nothing")).is_err());
}

/// `--format json` gives `time_ns` on every step of a timed trace.
#[test]
fn json_timed_traces_have_an_instant_per_step() {
    let out = Command::cargo_bin("genom-check")
        .expect("binary is built")
        .args([
            "--format",
            "json",
            "tests/fixtures/invalid/thread-overrun.two-services-share-a-period.gen",
        ])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(1));
    let v: Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let d = &v["files"][0]["diagnostics"][0];
    assert_eq!(d["code"], "thread-overrun");
    let steps = d["trace"].as_array().expect("a trace");
    let times: Vec<u64> = steps
        .iter()
        .map(|s| s["time_ns"].as_u64().expect("time_ns is a number"))
        .collect();
    assert!(times.windows(2).all(|w| w[0] <= w[1]), "{times:?}");
    assert_eq!(times.last(), Some(&20_000_000));
}

// ------------------------------------------------------------ exact margins

/// The worked example of docs/timing.md with this max-time.
pub(crate) fn worked_example(max_time: &str) -> String {
    format!(
        "component servo {{ category: default; lang: C; }}\n\
         thread servoTask {{ priority: 50; period: 10ms; }}\n\
         service Step {{\n\
         \x20 thread: servoTask;\n\
         \x20 max-time: {max_time};\n\
         \x20 start codel {{ exec: servoStep(); max-time: 2ms; next: end; }}\n\
         }}\n"
    )
}

pub(crate) fn check_inline(src: &str) -> CheckResult {
    genom_check::check_source(
        Path::new("inline.gen"),
        src.to_owned(),
        &gen_frontend::MemoryLoader::new(),
        &CheckOptions::new(),
    )
}

pub(crate) fn timing_codes(result: &CheckResult) -> Vec<Code> {
    result
        .diagnostics
        .iter()
        .map(|d| d.code)
        .filter(|c| TIMING.contains(c))
        .collect()
}

/// The time unit of the timed model of the whole component.
fn unit_of(result: &CheckResult) -> u64 {
    let c = common::component(result);
    let all: Vec<ServiceId> = c.services.ids().collect();
    genom_checker::timed::clocks::unit_ns(c, &all)
}

/// Worst case 12 ms (acknowledged at a wake-up but run at the next one,
/// 10 ms later, then 2 ms of codel): a max-time of 12 ms is clean, and one
/// time unit less is reported, whatever the unit (which the max-time
/// itself changes: the unit is the GCD of 10 ms, 2 ms and the max-time).
#[test]
fn margins_are_exact_on_the_worked_example() {
    let cases: &[(&str, u64, bool)] = &[
        // (max-time, time unit in ns, exceeded)
        ("12ms", 2_000_000, false),
        ("10ms", 2_000_000, true), // 12 ms minus one unit of the 12 ms model
        ("11ms", 1_000_000, true), // 12 ms minus one unit of 1 ms
        ("11999999ns", 1, true),   // 12 ms minus one nanosecond
        ("12000001ns", 1, false),
        ("13ms", 1_000_000, false),
    ];
    for &(max_time, unit, exceeded) in cases {
        let result = check_inline(&worked_example(max_time));
        let report = common::render(Path::new("inline.gen"), &result);
        assert_eq!(unit_of(&result), unit, "max-time {max_time}: unit");
        let expected: &[Code] = if exceeded {
            &[Code::MaxTimeExceeded]
        } else {
            &[]
        };
        assert_eq!(
            timing_codes(&result),
            expected,
            "max-time {max_time}:\n{report}"
        );
        if exceeded {
            let d = &result.diagnostics[0];
            let trace = d.trace.as_ref().expect("a trace");
            let end = check_timed(
                common::component(&result),
                trace,
                TimedClaim::LateService("Step"),
            )
            .expect("a timed execution");
            let m = common::component(&result).services[ServiceId(0)]
                .max_time
                .expect("a max-time")
                .ns;
            assert!(end.last_ns > end.late_ack_ns.expect("acknowledged") + m);
        }
    }
}

/// A service of `n` codels on a thread of period `p`, each codel with
/// WCET `w`, and optionally another looping service with a codel of WCET
/// `b` on the same thread: by hand, the worst case from acknowledgment to
/// the end is `n·p + b + w` (acknowledged exactly at a wake-up but run at
/// the next one; then one codel per period, each after the other
/// service's codel when that one was acknowledged first), as long as
/// `b + w < p` (no overrun) — and the best case is `(n − 1)·p`.
fn chain(p: u64, n: usize, w: u64, b: Option<u64>, max_time_ns: u64) -> String {
    let mut src = format!(
        "component chain {{ category: default; lang: C; }}\n\
         thread t {{ period: {p}ns; }}\n\
         service S {{\n  thread: t;\n  max-time: {max_time_ns}ns;\n"
    );
    for i in 0..n {
        let name = if i == 0 {
            "start codel".to_owned()
        } else {
            format!("exec codel c{i}")
        };
        let next = if i + 1 == n {
            "end".to_owned()
        } else {
            format!("c{}", i + 1)
        };
        src.push_str(&format!(
            "  {name} {{ exec: f{i}(); max-time: {w}ns; next: {next}; }}\n"
        ));
    }
    src.push_str("}\n");
    if let Some(b) = b {
        src.push_str(&format!(
            "service B {{\n  thread: t;\n  start codel {{ exec: g(); max-time: {b}ns; next: start, end; }}\n}}\n"
        ));
    }
    src
}

#[test]
fn the_worst_case_matches_the_hand_formula() {
    let ms = 1_000_000;
    let cases: &[(u64, usize, u64, Option<u64>)] = &[
        (10 * ms, 1, 2 * ms, None),
        (10 * ms, 3, 4 * ms, None),
        (5 * ms, 2, ms, None),
        (7 * ms, 2, 3 * ms, None),
        (10 * ms, 2, 3 * ms, Some(4 * ms)),
        (20 * ms, 1, 5 * ms, Some(12 * ms)),
        (1_000_000, 2, 250_000, None),
    ];
    for &(p, n, w, b) in cases {
        let n64 = n as u64;
        let worst = n64 * p + b.unwrap_or(0) + w;
        let best = (n64 - 1) * p;
        let unit = [p, w, b.unwrap_or(0)].into_iter().fold(0, gcd);
        let run = |m: u64| {
            let src = chain(p, n, w, b, m);
            let result = check_inline(&src);
            let codes = timing_codes(&result);
            (codes, common::render(Path::new("inline.gen"), &result))
        };
        let label = format!("p={p} n={n} w={w} b={b:?}: worst {worst}, best {best}");
        let (codes, report) = run(worst);
        assert_eq!(
            codes,
            [],
            "{label}: max-time = worst case is clean\n{report}"
        );
        let (codes, report) = run(worst - unit);
        assert_eq!(
            codes,
            [Code::MaxTimeExceeded],
            "{label}: one unit less is exceeded\n{report}"
        );
        if best == 0 {
            continue; // a max-time must be positive
        }
        let (codes, report) = run(best);
        let expected: &[Code] = if best < worst {
            &[Code::MaxTimeExceeded]
        } else {
            &[]
        };
        assert_eq!(
            codes, expected,
            "{label}: max-time = best case is feasible\n{report}"
        );
        if best > unit {
            let (codes, report) = run(best - unit);
            assert_eq!(
                codes,
                [Code::MaxTimeInfeasible],
                "{label}: under the best case is infeasible\n{report}"
            );
        }
    }
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 { a } else { gcd(b, a % b) }
}

// ------------------------------------------------------------------ specs

fn spec_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(common::root().join("specs"))
        .expect("specs/ is readable")
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "gen"))
        .collect();
    files.sort();
    files
}

/// The timing verdicts of every file in `specs/`, as docs/timing.md
/// explains them.
#[test]
fn the_timing_verdicts_of_the_specs_are_the_documented_ones() {
    let expected: &[(&str, &[&str])] = &[
        (
            "arm.gen",
            &[
                "max-time-watchdog: `Calibrate` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 20ms",
                "max-time-watchdog: `MoveJoints` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 20ms",
            ],
        ),
        (
            "battery.gen",
            &[
                "max-time-watchdog: `CalibrateGauge` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 2s",
                "max-time-watchdog: `WaitCharged` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 1s",
            ],
        ),
        ("camera.gen", &[]),
        (
            "gripper.gen",
            &[
                "max-time-watchdog: `Home` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 20ms",
                "max-time-watchdog: `Open` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 20ms",
                "max-time-watchdog: `Grasp` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 30ms",
            ],
        ),
        (
            "localization.gen",
            &[
                "max-time-watchdog: `Init` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 200ms",
                "missing-wcet: 5 codels without WCET (`max-time`) are taken as running in no time",
            ],
        ),
        (
            "mobileBase.gen",
            &[
                "missing-wcet: 7 codels without WCET (`max-time`) are taken as running in no time",
                "max-time-watchdog: `GotoPosition` loops without bound: its max-time is enforced only by the watchdog; worst stop latency at most 100ms",
            ],
        ),
        (
            "pilot.gen",
            &["missing-wcet: 4 codels without WCET (`max-time`) are taken as running in no time"],
        ),
    ];
    let mut found = Vec::new();
    for path in spec_files() {
        let result = common::check(&path);
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_default()
            .to_owned();
        let lines: Vec<String> = result
            .diagnostics
            .iter()
            .filter(|d| TIMING.contains(&d.code))
            .map(|d| format!("{}: {}", d.code, d.message))
            .collect();
        found.push((name, lines));
    }
    let expected: Vec<(String, Vec<String>)> = expected
        .iter()
        .map(|(n, l)| ((*n).to_owned(), l.iter().map(|s| (*s).to_owned()).collect()))
        .collect();
    assert_eq!(found, expected);
}
