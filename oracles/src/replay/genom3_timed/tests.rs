//! Tests of the timed GenoM3 replay: every overrun trace the timed engine
//! finds on the timing fixtures replays; tampered ones are rejected for
//! the right reason.
#![allow(clippy::expect_used, clippy::unwrap_used)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use genom_model::component::Component;
use genom_model::trace::{Event, Trace, TraceStep};

use genom_engine::genom3::machine::Machine;
use genom_engine::genom3::timed::analysis::analyse_timing;
use genom_engine::kernel::explore::Limits;

use super::replay_genom3_timed;
use crate::testing::load_genom3_wcet;

const MS: u64 = 1_000_000;

fn fixture(name: &str) -> Component {
    let dir = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/fixtures/genom3/timing/"
    );
    let path = PathBuf::from(dir).join(name);
    let text = std::fs::read_to_string(path.with_extension("gen")).unwrap();
    let wcet = std::fs::read_to_string(path.with_extension("wcet")).unwrap();
    load_genom3_wcet(&text, &wcet)
}

/// The overrun traces of `c` read with `n` instances, each with its task.
fn overruns(c: &Component, n: usize) -> Vec<(String, Trace)> {
    let m = Machine::new(c, n).unwrap();
    let a = analyse_timing(&m, Limits::default()).unwrap();
    assert!(a.stopped.is_none(), "complete");
    a.overruns
        .into_iter()
        .map(|o| (m.tasks[o.task].name.clone(), o.trace))
        .collect()
}

fn fixture_names() -> Vec<String> {
    let dir = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/fixtures/genom3/timing/"
    );
    let mut out: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "gen"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    out.sort();
    out
}

#[test]
fn every_fixture_overrun_replays() {
    let mut replayed: BTreeMap<String, (usize, usize)> = BTreeMap::new();
    for name in fixture_names() {
        let c = fixture(&name);
        for n in [1, 2] {
            for (task, trace) in overruns(&c, n) {
                let tick = &trace.steps[trace.steps.len() - 2];
                assert_eq!(tick.thread.as_deref(), Some(task.as_str()), "{name}");
                if let Err(e) = replay_genom3_timed(&c, n, &trace) {
                    panic!("{name} (n = {n}, task {task}): {e}\n{trace:#?}");
                }
                let e = replayed.entry(name.clone()).or_default();
                if n == 1 {
                    e.0 += 1;
                } else {
                    e.1 += 1;
                }
            }
        }
    }
    // Overrun traces (one per task and cause) with one and two instances.
    let expected = [
        ("f10_restart", (1, 3)),
        ("f10_restart_fixed", (0, 2)),
        ("f11_hidden", (2, 3)),
        ("f11_hidden_fixed", (0, 1)),
        ("f11_permanent_long", (1, 1)),
        ("f1b_chain_overrun", (1, 2)),
        ("f1b_chain_paused", (0, 1)),
        ("f3_permanent_lock", (2, 2)),
        ("f4_instances", (0, 1)),
        ("f7_attribute_copy", (1, 1)),
        ("f7_control_free", (0, 1)),
        ("f7_control_lock", (1, 2)),
        ("f9_fifo", (1, 1)),
        ("f9_granularity", (4, 3)),
        ("f9_writers", (0, 2)),
    ];
    let expected: BTreeMap<String, (usize, usize)> = expected
        .iter()
        .map(|(k, v)| ((*k).to_owned(), *v))
        .collect();
    assert_eq!(replayed, expected);
}

fn demo() -> Component {
    let dir = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../genom3-frontend/tests/fixtures/valid/"
    );
    let path = Path::new(dir).join("demo.gen");
    let text = std::fs::read_to_string(&path).unwrap();
    let wcet = std::fs::read_to_string(path.with_extension("wcet")).unwrap();
    let options = genom3_frontend::Genom3Options {
        use_env_include_path: false,
        ..genom3_frontend::Genom3Options::default()
    };
    let mut out = genom3_frontend::load_text(&path, text, &options).unwrap();
    genom3_frontend::add_wcet_file(&mut out, &path.with_extension("wcet"), wcet);
    let errors = out
        .diagnostics
        .iter()
        .filter(|d| d.severity == genom_model::Severity::Error)
        .count();
    assert_eq!(errors, 0, "{:#?}", out.diagnostics);
    out.component.unwrap()
}

#[test]
fn the_demo_component_overruns_replay() {
    let c = demo();
    for n in [1, 2] {
        for (task, trace) in overruns(&c, n) {
            if let Err(e) = replay_genom3_timed(&c, n, &trace) {
                panic!("demo (n = {n}, task {task}): {e}\n{trace:#?}");
            }
        }
    }
}

/// A step on `thread` at `ms` milliseconds.
fn at(
    event: Event,
    ms: u64,
    thread: &str,
    codel: Option<&str>,
    outcome: Option<&str>,
) -> TraceStep {
    let mut s = TraceStep::new(event, "");
    s.time_ns = Some(ms * MS);
    s.thread = Some(thread.to_owned());
    s.codel = codel.map(str::to_owned);
    s.outcome = outcome.map(str::to_owned);
    s
}

#[test]
fn the_demo_io_task_overruns_in_its_async_codel() {
    // `io` (period 20 ms, delay 1 ms) runs its `async` permanent codel,
    // unbounded, from its first tick past its second. (The timed engine
    // does not find this one: its initial state lets no time pass, so the
    // first tick at 1 ms never comes in `io`'s group.)
    let c = demo();
    let mut t = Trace::default();
    let mut start = TraceStep::new(Event::ComponentStart, "");
    start.time_ns = Some(0);
    t.steps.push(start);
    t.steps.push(at(Event::WakeUp, 1, "io", None, Some("tick")));
    t.steps
        .push(at(Event::CodelStart, 1, "io", Some("start"), None));
    t.steps
        .push(at(Event::WakeUp, 21, "io", None, Some("tick")));
    let mut v = TraceStep::new(Event::Violation, "");
    v.time_ns = Some(21 * MS);
    t.steps.push(v);
    replay_genom3_timed(&c, 1, &t).unwrap();
    // Its first tick is at its delay, not at 0.
    for s in &mut t.steps[1..] {
        s.time_ns = s.time_ns.map(|x| x - MS);
    }
    rejected(&c, 1, &t, "tick is at 1000000 ns");
}

/// The first overrun trace of fixture `name` with `n` instances for task
/// `task`.
fn trace_of(name: &str, n: usize, task: &str) -> (Component, Trace) {
    let c = fixture(name);
    let t = overruns(&c, n)
        .into_iter()
        .find(|(t, _)| t == task)
        .unwrap()
        .1;
    replay_genom3_timed(&c, n, &t).unwrap();
    (c, t)
}

/// Position of the first step of `event` on `thread` at `codel`.
fn find(t: &Trace, event: Event, thread: &str, codel: Option<&str>) -> usize {
    t.steps
        .iter()
        .position(|s| {
            s.event == event && s.thread.as_deref() == Some(thread) && s.codel.as_deref() == codel
        })
        .unwrap()
}

fn rejected(c: &Component, n: usize, t: &Trace, why: &str) {
    let e = replay_genom3_timed(c, n, t).expect_err("tampered");
    assert!(e.contains(why), "expected `{why}`, got: {e}");
}

#[test]
fn an_early_last_tick_is_rejected() {
    let (c, mut t) = trace_of("f1b_chain_overrun", 1, "t");
    let k = t.steps.len() - 2;
    t.steps[k].time_ns = Some(9 * MS);
    t.steps[k + 1].time_ns = Some(9 * MS);
    rejected(&c, 1, &t, "tick is at 10000000 ns");
}

#[test]
fn a_codel_beyond_its_wcet_is_rejected() {
    let (c, mut t) = trace_of("f1b_chain_overrun", 1, "t");
    // `start` (WCET 6 ms) ends at 7 ms; `exec` begins then.
    let end = find(&t, Event::CodelEnd, "t", Some("start"));
    t.steps[end].time_ns = Some(7 * MS);
    t.steps[end + 1].time_ns = Some(7 * MS);
    rejected(&c, 1, &t, "runs past its WCET 6000000 ns");
}

#[test]
fn conflicting_codels_overlapping_are_rejected() {
    // `reader` (task u, reads x) runs 0-2 ms, then `t`'s `main` (writes x).
    let (c, mut t) = trace_of("f3_permanent_lock", 1, "t");
    let end = find(&t, Event::CodelEnd, "u", Some("start"));
    let main = find(&t, Event::CodelStart, "t", Some("main"));
    assert_eq!(main, end + 1);
    let mut s = t.steps.remove(main);
    s.time_ns = Some(MS + MS / 2);
    t.steps.insert(end, s);
    rejected(&c, 1, &t, "which it waits for");
}

#[test]
fn a_dropped_tick_is_rejected() {
    // `t`'s tick at 10 ms comes while `set_speed`'s codel runs (to 15 ms).
    let (c, mut t) = trace_of("f7_control_lock", 1, "t");
    let k = t
        .steps
        .iter()
        .position(|s| s.event == Event::WakeUp && s.time_ns == Some(10 * MS))
        .unwrap();
    t.steps.remove(k);
    // With it goes the ticket `t` took at that tick for `main`.
    if t.steps[k].event == Event::LockWait {
        t.steps.remove(k);
    }
    rejected(&c, 1, &t, "task `t` missed its tick at 10000000 ns");
}

#[test]
fn a_dropped_final_tick_is_rejected() {
    let (c, mut t) = trace_of("f1b_chain_overrun", 1, "t");
    let k = t.steps.len() - 2;
    t.steps.remove(k);
    rejected(&c, 1, &t, "the violation follows a tick");
}

#[test]
fn a_wrong_yield_is_rejected() {
    let (c, mut t) = trace_of("f1b_chain_overrun", 1, "t");
    let end = find(&t, Event::CodelEnd, "t", Some("start"));
    t.steps[end].outcome = Some("pause::exec".into());
    rejected(&c, 1, &t, "does not yield `pause::exec`");
}

#[test]
fn a_finished_task_at_its_last_tick_is_rejected() {
    // `exec` ends at 10 ms (its WCET is 6 ms: it began at 6 ms, so 4 ms).
    let (c, mut t) = trace_of("f1b_chain_overrun", 1, "t");
    let k = t.steps.len() - 2;
    let mut end = t.steps[k - 1].clone();
    end.event = Event::CodelEnd;
    end.outcome = Some("wait".into());
    end.time_ns = Some(10 * MS);
    t.steps.insert(k, end);
    rejected(&c, 1, &t, "no codel running before its WCET");
}

#[test]
fn idling_with_a_free_due_codel_is_rejected() {
    // `exec` begins 1 ms after `start` ended, though nothing holds its locks.
    let (c, mut t) = trace_of("f1b_chain_overrun", 1, "t");
    let start = find(&t, Event::CodelStart, "t", Some("exec"));
    t.steps[start].time_ns = Some(7 * MS);
    rejected(
        &c,
        1,
        &t,
        "time passes while task `t` neither begins state `exec` nor takes a ticket for it",
    );
}

#[test]
fn a_control_thread_idling_with_its_locks_free_is_rejected() {
    // `set_speed`'s request taken at 5 ms, its codel begun only at 10 ms.
    let (c, mut t) = trace_of("f7_control_lock", 1, "t");
    let k = t
        .steps
        .iter()
        .position(|s| s.event == Event::Request)
        .unwrap();
    t.steps[k].time_ns = Some(5 * MS);
    rejected(
        &c,
        1,
        &t,
        "time passes while the control thread neither begins its codel nor takes a ticket",
    );
}

#[test]
fn a_codel_begun_out_of_ticket_order_is_rejected() {
    // `b` took its ticket before `c`; both begin at 18 ms, `b` first.
    let (c, mut t) = trace_of("f9_fifo", 1, "c");
    let b = t
        .steps
        .iter()
        .rposition(|s| s.event == Event::CodelStart && s.thread.as_deref() == Some("b"))
        .unwrap();
    assert_eq!(t.steps[b + 1].thread.as_deref(), Some("c"), "{t:#?}");
    t.steps.swap(b, b + 1);
    rejected(&c, 1, &t, "not at the head of the resource queue");
}

#[test]
fn a_ticket_taken_with_the_locks_free_and_no_queue_is_rejected() {
    // Without `b`'s ticket, `c`'s codel could begin at once.
    let (c, mut t) = trace_of("f9_fifo", 1, "c");
    let b = t
        .steps
        .iter()
        .position(|s| s.event == Event::LockWait && s.thread.as_deref() == Some("b"))
        .unwrap();
    t.steps.remove(b);
    rejected(&c, 1, &t, "the codel may begin now");
}
