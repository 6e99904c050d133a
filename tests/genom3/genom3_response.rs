//! Worst-case response times in GenoM3's timed semantics
//! (docs/genom3-semantics.md section 16): each fixture of
//! `tests/fixtures/genom3/response/` says how its worst cases are computed
//! by hand; the check must find exactly them, and `--deadline` must turn a
//! worst case one nanosecond later than the deadline into a
//! `deadline-miss` whose trace the independent replay
//! (`genom_oracles::replay::genom3_timed`) accepts and shows the instance
//! still alive past the deadline.

#![allow(clippy::expect_used, clippy::unwrap_used)] // test support code outside #[test] functions

use std::path::{Path, PathBuf};

use genom_check::{CheckOptions, CheckResult, Inputs, check_path};
use genom_model::Code;
use genom_model::response::Bound;
use genom_model::trace::Event;
use genom_oracles::replay::genom3_timed::replay_genom3_alive;

const DIR: &str = "tests/fixtures/genom3/response";
const MS: u64 = 1_000_000;

const TIMING: &str = "tests/fixtures/genom3/timing";

/// Checks `DIR/name.gen` with its WCET file `DIR/name.wcet`.
fn check_in(dir: &str, name: &str, options: &CheckOptions) -> CheckResult {
    let path = Path::new(dir).join(format!("{name}.gen"));
    let inputs = Inputs {
        wcet_file: Some(PathBuf::from(dir).join(format!("{name}.wcet"))),
        ..Inputs::default()
    };
    check_path(&path, &inputs, options).unwrap()
}

fn check_with(name: &str, options: &CheckOptions) -> CheckResult {
    check_in(DIR, name, options)
}

fn worst(r: &CheckResult, service: &str) -> Bound {
    r.response_times
        .iter()
        .find(|t| t.service == service)
        .unwrap_or_else(|| panic!("no response time for `{service}`"))
        .worst
}

fn times(name: &str) -> CheckResult {
    check_with(name, &CheckOptions::new().response_times(true))
}

fn misses(r: &CheckResult) -> Vec<&genom_model::Diagnostic> {
    r.diagnostics
        .iter()
        .filter(|d| d.code == Code::DeadlineMiss)
        .collect()
}

#[test]
fn a_paused_chain_replies_two_periods_and_its_last_codel_after_acknowledgment() {
    let r = times("r1_paused_chain");
    assert_eq!(worst(&r, "go"), Bound::Exact(23 * MS));
    assert!(r.statistics.as_ref().unwrap().complete);
}

#[test]
fn an_unpaused_chain_replies_within_the_period_after_its_start_and_round_robin() {
    let r = times("r2_unpaused_chain");
    assert_eq!(worst(&r, "go"), Bound::Exact(16 * MS));
    assert_eq!(worst(&r, "spin"), Bound::Unbounded);
    assert_eq!(worst(&r, "halt"), Bound::Exact(0));
}

#[test]
fn a_function_waits_for_the_lock_held_by_a_task_codel() {
    let r = times("r3_function_lock");
    assert_eq!(worst(&r, "set"), Bound::Exact(5 * MS));
    assert_eq!(worst(&r, "watch"), Bound::Unbounded);
    // Its own codel takes 1ms: the other 4ms are the wait for the lock,
    // and the table and JSON say so apart.
    assert_eq!(own(&r, "set"), Some(MS));
    assert_eq!(own(&r, "watch"), None, "`watch` loops");
    let table = genom_model::response::render_table(&r.response_times);
    assert!(
        table
            .lines()
            .any(|l| l.split_whitespace().collect::<Vec<_>>() == ["set", "5ms", "1ms"]),
        "{table}"
    );
    assert!(table.contains("own codels"), "{table}");
}

fn own(r: &CheckResult, service: &str) -> Option<u64> {
    r.response_times
        .iter()
        .find(|t| t.service == service)
        .unwrap_or_else(|| panic!("no response time for `{service}`"))
        .own
}

#[test]
fn no_response_times_unless_asked() {
    let r = check_with("r1_paused_chain", &CheckOptions::new());
    assert!(r.response_times.is_empty());
}

#[test]
fn a_deadline_equal_to_the_worst_case_is_met() {
    for (name, service, ms) in [
        ("r1_paused_chain", "go", 23),
        ("r2_unpaused_chain", "go", 16),
        ("r3_function_lock", "set", 5),
    ] {
        let r = check_with(name, &CheckOptions::new().deadline_for(service, ms * MS));
        assert!(misses(&r).is_empty(), "{name}: {:?}", misses(&r));
        assert!(
            r.diagnostics.iter().all(|d| d.code != Code::Incomplete),
            "{name}"
        );
    }
}

#[test]
fn a_deadline_one_nanosecond_short_is_missed_with_a_replayed_trace() {
    for (name, service, ms) in [
        ("r1_paused_chain", "go", 23),
        ("r2_unpaused_chain", "go", 16),
    ] {
        let deadline = ms * MS - 1;
        let r = check_with(name, &CheckOptions::new().deadline_for(service, deadline));
        let found = misses(&r);
        assert_eq!(found.len(), 1, "{name}");
        let trace = found[0].trace.as_ref().expect("a trace");
        assert_eq!(trace.steps.last().unwrap().event, Event::Violation);
        let c = r.component.as_ref().unwrap();
        let age = replay_genom3_alive(c, 1, trace, service)
            .unwrap_or_else(|e| panic!("{name}: replay: {e}\n{trace:#?}"));
        assert!(age > deadline, "{name}: alive {age} ns only");
        assert!(
            age <= ms * MS,
            "{name}: alive {age} ns, beyond the worst case"
        );
    }
}

#[test]
fn a_function_deadline_one_nanosecond_short_is_missed() {
    let r = check_with(
        "r3_function_lock",
        &CheckOptions::new().deadline_for("set", 5 * MS - 1),
    );
    assert_eq!(misses(&r).len(), 1);
    assert!(misses(&r)[0].message.contains("`set`"));
}

#[test]
fn an_unbounded_service_misses_any_deadline_with_a_trace_into_its_loop() {
    let r = check_with(
        "r2_unpaused_chain",
        &CheckOptions::new().deadline_for("spin", 3600 * 1000 * MS),
    );
    let found = misses(&r);
    assert_eq!(found.len(), 1);
    let trace = found[0].trace.as_ref().expect("a trace");
    let c = r.component.as_ref().unwrap();
    replay_genom3_alive(c, 1, trace, "spin").unwrap_or_else(|e| panic!("replay: {e}"));
    assert!(trace.steps.last().unwrap().text.contains("forever"));
}

#[test]
fn a_deadline_without_wcets_is_undecided() {
    let path = Path::new(DIR).join("r1_paused_chain.gen");
    let options = CheckOptions::new().deadline_for("go", MS);
    let r = check_path(&path, &Inputs::default(), &options).unwrap();
    let found: Vec<_> = r
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::Incomplete)
        .collect();
    assert_eq!(found.len(), 1);
    assert!(found[0].message.contains("deadline of `go`"));
    assert!(misses(&r).is_empty());
}

#[test]
fn a_deadline_naming_no_service_is_a_usage_error() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_genom-check"))
        .args(["--deadline", "gp=1ms", "--wcet"])
        .arg(Path::new(DIR).join("r1_paused_chain.wcet"))
        .arg(Path::new(DIR).join("r1_paused_chain.gen"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no service `gp`"), "{err}");
}

/// `set_speed`'s codel (5 ms) waits for `servo`'s (6 ms, same data): 11 ms.
/// GenoM3's FIFO serves the waiting control thread before `servo`'s next
/// codel, even when `servo`'s task overruns and wakes again at once (its
/// tick coalesced): without the FIFO the control thread could wait for
/// `servo` twice (17 ms).
#[test]
fn a_waiting_control_thread_keeps_its_place_in_the_lock_queue() {
    let r = check_in(
        TIMING,
        "f7_control_lock",
        &CheckOptions::new().response_times(true),
    );
    assert_eq!(worst(&r, "set_speed"), Bound::Exact(11 * MS));
    assert_eq!(worst(&r, "servo"), Bound::Unbounded);
    // The schedulability verdict is unchanged: `t` overruns.
    assert!(r.diagnostics.iter().any(|d| d.code == Code::ThreadOverrun));
}

/// `reader` (2 ms, task `u`) is accepted just after `u`'s tick and waits for
/// the permanent codel of task `t` (9 ms, same data) at the next one:
/// 10 + 9 + 2 = 21 ms; `u` overruns meanwhile, its tick coalesced.
#[test]
fn response_times_hold_through_coalesced_overruns() {
    let deadline = 21 * MS - 1;
    let options = CheckOptions::new().deadline_for("reader", deadline);
    let r = check_in(TIMING, "f3_permanent_lock", &options);
    assert_eq!(worst(&r, "reader"), Bound::Exact(21 * MS));
    let found = misses(&r);
    assert_eq!(found.len(), 1);
    let trace = found[0].trace.as_ref().expect("a trace");
    let c = r.component.as_ref().unwrap();
    let age = replay_genom3_alive(c, 1, trace, "reader").unwrap_or_else(|e| panic!("{e}"));
    assert!(age > deadline && age <= 21 * MS, "{age}");
}

#[test]
fn a_validate_that_never_waits_counts_its_wcet() {
    let r = check_with(
        "r4_validate_and_codel",
        &CheckOptions::new().deadline_for("set", 6 * MS - 1),
    );
    assert_eq!(worst(&r, "set"), Bound::Exact(6 * MS));
    let found = misses(&r);
    assert_eq!(found.len(), 1);
    // The trace names the codel that waited (the second control codel).
    let trace = found[0].trace.as_ref().expect("a trace");
    assert!(
        trace
            .steps
            .iter()
            .any(|s| s.text.contains("begins `set`'s control codel `r3_set`")),
        "{trace:#?}"
    );
}

/// A limit that stops the response-time exploration is `incomplete` (the
/// run is not fully verified, exit 1) and names the services whose worst
/// case it left unknown; before, only the table said "exploration
/// incomplete" and the summary counted it complete.
#[test]
fn a_stopped_response_exploration_is_incomplete_and_names_what_it_left() {
    let r = check_with(
        "r3_function_lock",
        &CheckOptions::new().response_times(true).max_states(5),
    );
    // The function keeps a static bound (semantics 16.8): its codel's
    // 1 ms plus one contended codel of task `t` (4 ms), the exact worst
    // case here; the activity is left unknown.
    assert_eq!(worst(&r, "set"), Bound::AtMost(5_000_000));
    assert_eq!(worst(&r, "watch"), Bound::Unknown);
    let found: Vec<_> = r
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::Incomplete)
        .collect();
    assert_eq!(found.len(), 1, "{:#?}", r.diagnostics);
    let help = found[0].help.as_deref().unwrap_or_default();
    assert!(
        help.contains("the worst-case response times of `watch`"),
        "{help}"
    );
    assert!(
        help.contains("upper bounds on the response times of `set`"),
        "{help}"
    );
    assert!(help.contains("Stopped after"), "{help}");
    assert!(!r.statistics.as_ref().expect("explored").complete);
    // With room, no `incomplete`.
    let full = times("r3_function_lock");
    assert!(full.diagnostics.iter().all(|d| d.code != Code::Incomplete));
}

#[test]
fn a_static_bound_decides_a_deadline_the_stopped_exploration_could_not() {
    // `set`'s bound, 5 ms, meets a 5 ms deadline: no `incomplete` for it
    // (only the exploration's own); a 4 ms deadline stays undecided.
    let stopped = |d: u64| {
        let options = CheckOptions::new()
            .response_times(true)
            .max_states(5)
            .deadline_for("set", d);
        check_with("r3_function_lock", &options)
    };
    let met = stopped(5_000_000);
    assert!(misses(&met).is_empty());
    let undecided = |r: &CheckResult| {
        r.diagnostics
            .iter()
            .filter(|d| d.code == Code::Incomplete && d.message.contains("deadline of `set`"))
            .count()
    };
    assert_eq!(undecided(&met), 0, "{:#?}", met.diagnostics);
    let tight = stopped(4_000_000);
    assert!(misses(&tight).is_empty(), "a bound proves no miss");
    assert_eq!(undecided(&tight), 1, "{:#?}", tight.diagnostics);
    // With room, the exploration finds the 4 ms deadline missed.
    let options = CheckOptions::new()
        .response_times(true)
        .deadline_for("set", 4_000_000);
    assert_eq!(misses(&check_with("r3_function_lock", &options)).len(), 1);
}

#[test]
fn a_loop_seen_before_the_limit_is_unbounded_with_its_trace() {
    // The smallest state limit at which the stopped exploration has seen
    // `watch`'s instance alive in its loop: `unbounded` then (semantics
    // 16.2, a found fact), still `incomplete`, and a deadline on it is
    // missed with a trace into the loop that replays.
    let deadline = 3600 * 1000 * MS;
    let stopped = |n: usize| {
        let options = CheckOptions::new()
            .response_times(true)
            .max_states(n)
            .deadline_for("watch", deadline);
        check_with("r3_function_lock", &options)
    };
    let (r, n) = (5..500)
        .map(|n| (stopped(n), n))
        .find(|(r, _)| worst(r, "watch") != Bound::Unknown)
        .expect("the loop is seen before the whole exploration ends");
    assert_eq!(worst(&r, "watch"), Bound::Unbounded, "at {n} states");
    assert!(
        !r.statistics.as_ref().expect("explored").complete,
        "at {n} states"
    );
    let found = misses(&r);
    assert_eq!(found.len(), 1, "{:#?}", r.diagnostics);
    let trace = found[0].trace.as_ref().expect("a trace");
    let c = r.component.as_ref().unwrap();
    replay_genom3_alive(c, 1, trace, "watch").unwrap_or_else(|e| panic!("replay: {e}"));
}
