//! GenoM3's timing, point by point (issue 13, points 1, 3, 4, 7 and 9): each
//! fixture of `tests/fixtures/genom3/timing/` is checked with its WCET file
//! through the whole pipeline; the `thread-overrun` verdicts of the timed
//! GenoM3 engine differ from those of the LANGUAGE.md timed engine run on
//! the same lowered model (the "naive" reading), a paired fixture shows
//! what removes the overrun, and every trace is replayed by the independent
//! replay (`genom_oracles::replay::genom3_timed`).

#![allow(clippy::expect_used, clippy::unwrap_used)] // test support code outside #[test] functions

use crate::common;

use std::path::{Path, PathBuf};

use genom_check::{CheckOptions, CheckResult, Inputs, check_path};
use genom_checker::dialect::Limits;
use genom_checker::timed::analyse_timed;
use genom_model::stats::Method;
use genom_model::trace::Event;
use genom_model::{Code, Severity};
use genom_oracles::replay::genom3_timed::replay_genom3_timed;

const DIR: &str = "tests/fixtures/genom3/timing";

fn check_n(name: &str, instances: usize) -> CheckResult {
    let path = Path::new(DIR).join(format!("{name}.gen"));
    let inputs = Inputs {
        wcet_file: Some(PathBuf::from(DIR).join(format!("{name}.wcet"))),
        ..Inputs::default()
    };
    let options = CheckOptions::new().max_instances(instances);
    check_path(&path, &inputs, &options).unwrap()
}

fn check(name: &str) -> CheckResult {
    check_n(name, 1)
}

/// The tasks the check reports as overrunning, sorted.
fn overrunning(r: &CheckResult) -> Vec<String> {
    let mut v: Vec<String> = r
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::ThreadOverrun)
        .map(|d| d.message.split('`').nth(1).unwrap_or_default().to_owned())
        .collect();
    v.sort();
    v
}

/// The threads the LANGUAGE.md timed engine finds overrunning on the same
/// lowered model.
fn naive_overrunning(r: &CheckResult) -> Vec<String> {
    let c = r.component.as_ref().expect("a component");
    let (_, facts) = analyse_timed(c, Limits::default());
    let mut v: Vec<String> = facts
        .overruns
        .iter()
        .map(|o| c.threads[o.thread].name.name.clone())
        .collect();
    v.sort();
    v
}

/// No error besides overruns, every overrun with a timed trace that ends
/// with its violation and that the independent replay accepts.
fn assert_clean_traces(r: &CheckResult) {
    assert_traces_n(r, 1);
}

fn assert_traces_n(r: &CheckResult, instances: usize) {
    let c = r.component.as_ref().expect("a component");
    for d in &r.diagnostics {
        let overrun = matches!(d.code, Code::ThreadOverrun | Code::CodelOverrun);
        assert!(d.severity != Severity::Error || overrun, "{d:#?}");
        if !overrun {
            continue;
        }
        let t = d.trace.as_ref().expect("a trace");
        let last = t.steps.last().unwrap();
        assert_eq!(last.event, Event::Violation);
        assert!(t.steps.iter().all(|s| s.time_ns.is_some()), "{t:#?}");
        let times: Vec<u64> = t.steps.iter().map(|s| s.time_ns.unwrap()).collect();
        assert!(times.windows(2).all(|w| w[0] <= w[1]), "{times:?}");
        replay_genom3_timed(c, instances, t).unwrap_or_else(|e| panic!("{e}\n{t:#?}"));
    }
}

#[test]
fn point_1_an_unpaused_chain_overruns_where_one_codel_per_period_does_not() {
    let r = check("f1b_chain_overrun");
    assert_eq!(overrunning(&r), ["t"]);
    assert!(naive_overrunning(&r).is_empty());
    assert_clean_traces(&r);
    let paused = check("f1b_chain_paused");
    assert!(overrunning(&paused).is_empty());
}

#[test]
fn point_3_permanent_codels_take_their_share_of_the_period() {
    let r = check("f3_permanent_lock");
    assert_eq!(overrunning(&r), ["t", "u"]);
    assert!(naive_overrunning(&r).is_empty());
    assert_clean_traces(&r);
}

#[test]
fn point_4_instances_of_one_activity_share_the_period() {
    let one = check("f4_instances");
    assert!(overrunning(&one).is_empty());
    let two = check_n("f4_instances", 2);
    assert_eq!(overrunning(&two), ["t"]);
    assert_traces_n(&two, 2);
    assert!(naive_overrunning(&two).is_empty());
    let self_interrupting = check_n("f4_self_interrupt", 2);
    assert!(overrunning(&self_interrupting).is_empty());
}

#[test]
fn a_client_restarting_an_activity_that_interrupts_itself_is_explored_by_default() {
    // The default (`--max-instances 1`) explores a second request for
    // `track` while an instance runs: its validate waits for
    // `plan_compute`, the running instance's codel queues behind it.
    let r = check("f10_restart");
    assert_eq!(overrunning(&r), ["driver"]);
    assert_clean_traces(&r);
    let d = r
        .diagnostics
        .iter()
        .find(|d| d.code == Code::ThreadOverrun)
        .unwrap();
    let t = d.trace.as_ref().unwrap();
    let validates = t
        .steps
        .iter()
        .filter(|s| s.service.as_deref() == Some("track") && s.thread.as_deref() == Some("control"))
        .filter(|s| s.codel.as_deref() == Some("validate"))
        .count();
    assert!(validates >= 2, "two requests for `track` validate: {t:#?}");
    // The verdict says what it rests on.
    let stats = r.statistics.as_ref().unwrap();
    let kinds: Vec<_> = stats.assumptions.iter().map(|a| a.kind).collect();
    assert_eq!(kinds, ["wcet", "instances"]);
    assert!(stats.assumptions[1].text.contains("interrupts itself"));
    assert_eq!(stats.assumptions[1].bound, Some(1));
    // Fixed: the validate reads nothing `plan_compute` holds.
    let fixed = check("f10_restart_fixed");
    assert!(overrunning(&fixed).is_empty(), "{:#?}", fixed.diagnostics);
    assert_eq!(fixed.statistics.as_ref().unwrap().assumptions.len(), 2);
}

#[test]
fn one_overrun_does_not_hide_another_and_each_has_its_trace() {
    let r = check("f11_hidden");
    assert_clean_traces(&r);
    let of = |code| -> Vec<&str> {
        r.diagnostics
            .iter()
            .filter(|d| d.code == code)
            .map(|d| d.message.as_str())
            .collect()
    };
    // The chain of `sweep` (60 ms in a 50 ms period) is reported beside
    // the long codel of `calibrate`, not hidden by it.
    assert_eq!(
        of(Code::ThreadOverrun),
        ["task `t` can overrun its 50ms period: a chain of codels without `pause::`"]
    );
    let chain = first_overrun_trace(&r);
    assert!(
        chain
            .steps
            .iter()
            .any(|s| s.service.as_deref() == Some("sweep")),
        "{chain:#?}"
    );
    assert!(
        chain
            .steps
            .iter()
            .all(|s| s.service.as_deref() != Some("calibrate")),
        "the chain's trace needs no `calibrate`: {chain:#?}"
    );
    assert_eq!(
        of(Code::CodelOverrun),
        ["codel `cal_run` of activity `calibrate` may take 70ms but task `t` wakes up every 50ms"]
    );
    let fixed = check("f11_hidden_fixed");
    assert!(fixed.diagnostics.is_empty(), "{:#?}", fixed.diagnostics);
}

#[test]
fn a_permanent_codel_longer_than_the_period_is_a_codel_overrun_with_a_trace() {
    let r = check("f11_permanent_long");
    assert_clean_traces(&r);
    assert!(overrunning(&r).is_empty());
    let d: Vec<_> = r
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::CodelOverrun)
        .collect();
    assert_eq!(d.len(), 1);
    assert_eq!(
        d[0].message,
        "codel `t_main` of the permanent activity of task `t` may take 70ms but task `t` wakes up every 50ms"
    );
    let t = d[0].trace.as_ref().expect("a trace");
    assert!(
        t.steps.iter().any(|s| s.codel.as_deref() == Some("main")),
        "{t:#?}"
    );
}

#[test]
fn point_7_control_codels_hold_their_locks() {
    let r = check("f7_control_lock");
    assert_eq!(overrunning(&r), ["t"]);
    assert_clean_traces(&r);
    let free = check("f7_control_free");
    assert!(overrunning(&free).is_empty());
}

#[test]
fn point_9_the_resource_fifo_delays_a_codel_that_conflicts_with_nothing() {
    // `c` waits behind `b`'s ticket, not for a lock of its own.
    let waits = only_c_overruns_behind_tickets("f9_fifo");
    let threads: Vec<&str> = waits.iter().map(|w| w.0.as_str()).collect();
    assert_eq!(threads, ["b", "c"], "{waits:#?}");
    assert!(waits[1].2.contains("older tickets"), "{}", waits[1].2);
}

/// The trace of the first `thread-overrun`.
fn first_overrun_trace(r: &CheckResult) -> &genom_model::trace::Trace {
    let d = r
        .diagnostics
        .iter()
        .find(|d| d.code == Code::ThreadOverrun)
        .unwrap();
    d.trace.as_ref().unwrap()
}

/// Checks that in fixture `name` only task `c` overruns, only because of
/// GenoM3's FIFO (the naive reading finds nothing), with traces that
/// replay; the `lock-wait` steps of its trace: thread, codel, text.
fn only_c_overruns_behind_tickets(name: &str) -> Vec<(String, String, String)> {
    let r = check(name);
    assert_eq!(overrunning(&r), ["c"]);
    assert!(naive_overrunning(&r).is_empty());
    assert_clean_traces(&r);
    let t = first_overrun_trace(&r);
    t.steps
        .iter()
        .filter(|s| s.event == Event::LockWait)
        .map(|s| {
            let text = |x: &Option<String>| x.clone().unwrap_or_default();
            (text(&s.thread), text(&s.codel), s.text.clone())
        })
        .collect()
}

#[test]
fn point_7_an_attribute_ids_copy_takes_its_ticket_in_the_fifo() {
    // The copy waits for `fa`, `c` waits behind the copy's ticket.
    let waits = only_c_overruns_behind_tickets("f7_attribute_copy");
    let who: Vec<(&str, &str)> = waits.iter().map(|w| (w.0.as_str(), w.1.as_str())).collect();
    assert_eq!(who, [("control", "ids-copy"), ("c", "start")], "{waits:#?}");
}

#[test]
fn point_9_locks_at_genom3_granularity() {
    let readers = check("f9_granularity");
    assert!(!overrunning(&readers).is_empty());
    assert_clean_traces(&readers);
    let writers = check("f9_writers");
    assert!(overrunning(&writers).is_empty());
    // The naive reading locks the whole ids for each writer and nothing for
    // a port: the reverse.
    assert!(!naive_overrunning(&writers).is_empty());
}

#[test]
fn a_permanent_codel_without_wcet_is_named_by_missing_wcet() {
    let r = check("f3_partial");
    let d = r
        .diagnostics
        .iter()
        .find(|d| d.code == Code::MissingWcet)
        .expect("missing-wcet");
    let labels: Vec<&str> = d.labels.iter().map(|l| l.message.as_str()).collect();
    assert!(
        labels
            .iter()
            .any(|l| l.contains("task `t`") && l.contains("main")),
        "{labels:?}"
    );
    assert!(
        d.help.as_deref().unwrap_or("").contains("thread `t`"),
        "{d:#?}"
    );
    assert!(overrunning(&r).is_empty());
}

/// A real component (when the corpus is on this machine): `uavatt.gen` with
/// its WCET file overruns its 1 kHz task while the `log` function's 2 ms
/// codel holds the `log` member that `control` needs; the trace replays.
#[test]
fn uavatt_overruns_behind_the_log_function_and_the_trace_replays() {
    let Some(root) = common::genom3_corpus() else {
        return;
    };
    let file = root.join("uavatt-genom3/uavatt.gen");
    let inputs = Inputs {
        include_dirs: vec![PathBuf::from("tests/fixtures/genom3/include")],
        wcet_file: Some(PathBuf::from("tests/fixtures/genom3/wcet/uavatt.wcet")),
        ..Inputs::default()
    };
    let r = check_path(&file, &inputs, &CheckOptions::new()).unwrap();
    assert_eq!(overrunning(&r), ["main"]);
    assert_clean_traces(&r);
    let t = first_overrun_trace(&r);
    assert!(
        t.steps
            .iter()
            .any(|s| s.thread.as_deref() == Some("control") && s.service.as_deref() == Some("log")),
        "{t:#?}"
    );
}

#[test]
fn an_unfinished_timed_exploration_names_what_it_left_unproven() {
    // Stopped early: task `a` is cleared by the static bound of its
    // wake-up (semantics 15.12), so it is proven, not left open; task `c`
    // is left open; the `incomplete` help says so task by task.
    let help_of = |r: &CheckResult| {
        r.diagnostics
            .iter()
            .find(|d| d.code == Code::Incomplete)
            .and_then(|d| d.help.clone())
            .expect("incomplete")
    };
    let checked = |name: &str, max_states: usize| {
        let path = Path::new(DIR).join(format!("{name}.gen"));
        let inputs = Inputs {
            wcet_file: Some(PathBuf::from(DIR).join(format!("{name}.wcet"))),
            ..Inputs::default()
        };
        check_path(&path, &inputs, &CheckOptions::new().max_states(max_states)).unwrap()
    };
    let r = checked("f7_attribute_copy", 60);
    let help = help_of(&r);
    assert!(!help.contains("whether task `a` can overrun"), "{help}");
    assert!(help.contains("whether task `c` can overrun"), "{help}");
    assert!(help.contains("Proven: task `a` never overruns"), "{help}");
    // What was proven (the untimed exploration finished) and spent.
    assert!(
        help.contains(
            "never overruns; the untimed verdicts (dead services, codel reachability, livelocks)"
        ),
        "{help}"
    );
    assert!(
        help.contains("Stopped after ") && help.contains(" timed states in "),
        "{help}"
    );
    assert!(
        !help.contains("task `c` never overruns"),
        "an undecided task is not proven: {help}"
    );
    // Task `t`'s chain overruns; a shared wake-up is still possible (15.14)
    // and no exploration found one yet: the help names that cause.
    let r = checked("f1b_chain_overrun", 30);
    let help = help_of(&r);
    assert!(
        help.contains("other causes of overrun of task `t` (an overrun was found; still possible: its instances' codels together)"),
        "{help}"
    );
    assert!(!help.contains("task `t` never overruns"), "{help}");
    assert_eq!(overrunning(&r), ["t"]);
    let c = r.component.as_ref().expect("a component");
    for d in r
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::ThreadOverrun)
    {
        let t = d.trace.as_ref().expect("a trace");
        replay_genom3_timed(c, 1, t).unwrap_or_else(|e| panic!("{e}\n{t:#?}"));
    }
}

/// Every overrun trace (`thread-overrun`, `codel-overrun`) of the timing
/// fixtures, with its fixture's name and component.
fn fixture_overrun_traces() -> Vec<(
    String,
    genom_model::component::Component,
    genom_model::trace::Trace,
)> {
    let mut names: Vec<String> = std::fs::read_dir(DIR)
        .unwrap()
        .filter_map(|e| {
            let p = e.ok()?.path();
            (p.extension()? == "wcet").then(|| p.file_stem()?.to_str().map(str::to_owned))?
        })
        .collect();
    names.sort();
    let mut out = Vec::new();
    for name in names {
        let r = check(&name);
        let c = r.component.clone().expect("a component");
        for d in r
            .diagnostics
            .iter()
            .filter(|d| matches!(d.code, Code::ThreadOverrun | Code::CodelOverrun))
        {
            out.push((name.clone(), c.clone(), d.trace.clone().expect("a trace")));
        }
    }
    out
}

/// Issue 32, traces: an overrun's witness holds no step that could be
/// folded out. Every step of a task other than the overrunning one (and
/// the control thread, which takes the requests, and the tasks a
/// `lock-wait` step names as holding the lock: they share it with the
/// involved ones) is needed: dropping it makes the trace fail the
/// independent replay (a tick is urgent, so the trace would miss it; the
/// start codels run before any request is handled). Checked one step at a
/// time on every timing fixture that overruns.
#[test]
fn overrun_traces_hold_no_step_of_another_task_that_could_be_folded_out() {
    let mut others = 0;
    for (name, c, t) in &fixture_overrun_traces() {
        let overrunning = t
            .steps
            .iter()
            .rev()
            .find_map(|s| s.thread.clone())
            .expect("a task's step");
        // The tasks a `lock-wait` step names hold the lock waited for:
        // they are part of the finding.
        let holders: Vec<&str> = t
            .steps
            .iter()
            .filter(|s| s.event == Event::LockWait)
            .flat_map(|s| s.text.split("task `").skip(1))
            .filter_map(|rest| rest.split('`').next())
            .collect();
        for (i, s) in t.steps.iter().enumerate() {
            let Some(thread) = s.thread.as_deref() else {
                continue;
            };
            if thread == overrunning || thread == "control" || holders.contains(&thread) {
                continue;
            }
            others += 1;
            let mut folded = t.clone();
            folded.steps.remove(i);
            assert!(
                replay_genom3_timed(c, 1, &folded).is_err(),
                "{name}: step {} of task `{thread}` could be folded out of\n{t:#?}",
                i + 1
            );
        }
    }
    assert!(others > 0, "some fixture's trace has another task's steps");
}

/// The timed replay checks that a lock is released: dropping the step
/// where a codel ends (a task's or the control thread's) from an overrun
/// trace leaves that codel running, holding its locks past its WCET or
/// while a codel waiting for it begins, and the replay must refuse it.
/// Checked one step at a time on every timing fixture that overruns.
#[test]
fn an_overrun_trace_without_a_codel_end_is_refused() {
    let mut dropped = 0;
    for (name, c, t) in &fixture_overrun_traces() {
        assert!(
            replay_genom3_timed(c, 1, t).is_ok(),
            "{name}: the trace replays"
        );
        for (i, s) in t.steps.iter().enumerate() {
            if s.event != Event::CodelEnd {
                continue;
            }
            dropped += 1;
            let mut cut = t.clone();
            cut.steps.remove(i);
            assert!(
                replay_genom3_timed(c, 1, &cut).is_err(),
                "{name}: the trace without step {} ({}) replays",
                i + 1,
                s.text
            );
        }
    }
    assert!(dropped > 20, "{dropped} codel ends dropped");
}

/// Checks corpus component `file` with its WCET file `wcet`.wcet at
/// `max_states`; `None` (and a note) when the corpus is absent.
#[allow(clippy::print_stderr)] // a skipped test says why
fn check_corpus(file: &str, wcet: &str, max_states: usize) -> Option<(PathBuf, CheckResult)> {
    let Some(corpus) = common::genom3_corpus() else {
        eprintln!("SKIPPED: the GenoM3 corpus is absent");
        return None;
    };
    let path = corpus.join(file);
    let inputs = Inputs {
        include_dirs: vec![PathBuf::from("tests/fixtures/genom3/include")],
        wcet_file: Some(PathBuf::from(format!(
            "tests/fixtures/genom3/wcet/{wcet}.wcet"
        ))),
        ..Inputs::default()
    };
    let options = CheckOptions::new().max_states(max_states);
    let r = check_path(&path, &inputs, &options).unwrap();
    Some((path, r))
}

/// A limit below what the whole exploration needs (120 states of 135):
/// the search with restricted clients finds task `c`'s one possible cause,
/// a lock wait (docs/genom3-semantics.md 15.14), so the run is complete,
/// decided by `witnesses`, with the unlimited run's findings; the trace
/// replays.
#[test]
fn a_group_is_decided_by_witnesses_below_its_whole_exploration() {
    let path = Path::new(DIR).join("f7_attribute_copy.gen");
    let inputs = Inputs {
        wcet_file: Some(PathBuf::from(DIR).join("f7_attribute_copy.wcet")),
        ..Inputs::default()
    };
    let run = |options: &CheckOptions| check_path(&path, &inputs, options).unwrap();
    let limited = run(&CheckOptions::new().max_states(120));
    let whole = run(&CheckOptions::new());
    let findings = |r: &CheckResult| {
        r.diagnostics
            .iter()
            .map(|d| (d.code, d.message.clone()))
            .collect::<Vec<_>>()
    };
    assert_eq!(findings(&limited), findings(&whole));
    assert_eq!(overrunning(&limited), ["c"]);
    let how = |r: &CheckResult| {
        let stats = r.statistics.as_ref().expect("figures");
        stats
            .decided_by
            .iter()
            .filter(|d| d.engine == "zones")
            .map(|d| (d.method, d.complete))
            .collect::<Vec<_>>()
    };
    assert_eq!(how(&limited), [(Method::Witnesses, true)]);
    assert_eq!(how(&whole), [(Method::Zones, true)]);
    let c = limited.component.as_ref().expect("a component");
    for d in &limited.diagnostics {
        let t = d.trace.as_ref().expect("a trace");
        replay_genom3_timed(c, 1, t).unwrap_or_else(|e| panic!("{e}\n{t:#?}"));
    }
}

/// rmp440 with its WCET file (docs/genom3-semantics.md 15.13, 15.14): its
/// whole exploration is far too large, but both of its tasks can overrun,
/// and the search with restricted clients finds every cause of overrun
/// the static bound leaves possible: `MotionTask` for a chain, a lock wait
/// and its instances together, `TrackTask` for a lock wait (a restarting
/// `Track` request's `validate` queued behind `Init`'s codel, `Track`'s
/// codels behind it; a chain or a shared wake-up of `TrackTask` cannot
/// reach its period), and its three codels longer than their period. The
/// run is complete, its group decided by those witnesses, and every trace
/// replays in the independent oracle.
#[test]
fn rmp440_is_decided_by_a_witness_of_every_possible_cause() {
    let Some((_, r)) = check_corpus("infuse_rmp440-genom3/rmp440.gen", "rmp440", 10_000_000) else {
        return;
    };
    assert!(
        r.diagnostics.iter().all(|d| d.code != Code::Incomplete),
        "{:#?}",
        r.diagnostics
    );
    assert_eq!(
        overrunning(&r),
        ["MotionTask", "MotionTask", "MotionTask", "TrackTask"]
    );
    let codels = r
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::CodelOverrun)
        .count();
    assert_eq!(codels, 3);
    let stats = r.statistics.as_ref().expect("figures");
    let how: Vec<_> = stats.decided_by.iter().map(|d| d.method).collect();
    assert!(how.contains(&Method::Witnesses), "{how:?}");
    assert!(stats.states < 2_000_000, "{} states", stats.states);
    let c = r.component.as_ref().expect("a component");
    for d in r
        .diagnostics
        .iter()
        .filter(|d| matches!(d.code, Code::ThreadOverrun | Code::CodelOverrun))
    {
        let t = d.trace.as_ref().expect("a trace");
        replay_genom3_timed(c, 1, t).unwrap_or_else(|e| panic!("{}: {e}", d.message));
    }
    // At 50,000 states the search shows every cause of `MotionTask` but
    // not yet `TrackTask`'s overrun: the help says which is which.
    let Some((_, r)) = check_corpus("infuse_rmp440-genom3/rmp440.gen", "rmp440", 50_000) else {
        return;
    };
    let help = r
        .diagnostics
        .iter()
        .find(|d| d.code == Code::Incomplete)
        .and_then(|d| d.help.clone())
        .expect("incomplete");
    assert!(
        help.contains("whether task `TrackTask` can overrun"),
        "{help}"
    );
    assert!(
        help.contains("Proven: every cause of overrun of task `MotionTask` is shown"),
        "{help}"
    );
    assert!(
        !help.contains("other causes of overrun of task `MotionTask`"),
        "{help}"
    );
}

/// Issue 32, traces: an overrun trace sets aside the tasks that play no
/// part in it (none of the threads involved waited for their codels or
/// behind their tickets), and the independent replay checks that claim at
/// every ticket; setting aside a task that does play a part is refused.
/// On T265, `pose_port_refresh` plays no part in `apriltag_detection`'s
/// overrun: the human report leaves its steps out and says so.
#[test]
fn overrun_traces_set_aside_the_tasks_that_play_no_part() {
    let Some((path, r)) = check_corpus("T265-genom3/T265.gen", "T265", 10_000_000) else {
        return;
    };
    let c = r.component.as_ref().expect("a component");
    let (mut set_aside, mut refused) = (0, 0);
    for d in r
        .diagnostics
        .iter()
        .filter(|d| matches!(d.code, Code::ThreadOverrun | Code::CodelOverrun))
    {
        let t = d.trace.as_ref().expect("a trace");
        replay_genom3_timed(c, 1, t).unwrap_or_else(|e| panic!("{}: {e}", d.message));
        set_aside += t.aside_threads().len();
        // Every other task of the trace, set aside too, is refused unless
        // it plays no part either.
        for task in ["pose_port_refresh", "apriltag_detection", "image_display"] {
            if t.aside_threads().contains(&task) {
                continue;
            }
            let mut more = t.clone();
            for s in &mut more.steps {
                s.aside |= s.thread.as_deref() == Some(task);
            }
            if replay_genom3_timed(c, 1, &more).is_err() {
                refused += 1;
            }
        }
    }
    assert!(set_aside >= 3, "{set_aside} tasks set aside");
    assert!(refused >= 3, "{refused} wrong claims refused");
    let apriltag = r
        .diagnostics
        .iter()
        .find(|d| d.code == Code::ThreadOverrun && d.message.contains("`apriltag_detection`"))
        .and_then(|d| d.trace.as_ref())
        .expect("apriltag_detection overruns");
    assert_eq!(apriltag.aside_threads(), ["pose_port_refresh"]);
    // The human report: no step of `pose_port_refresh` under that finding.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_genom-check"))
        .args([
            "-I",
            "tests/fixtures/genom3/include",
            "--wcet",
            "tests/fixtures/genom3/wcet/T265.wcet",
        ])
        .arg(&path)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    let section = text
        .split("  × ")
        .find(|s| s.starts_with("task `apriltag_detection` can overrun"))
        .expect("the finding in the report");
    let steps: Vec<&str> = section
        .lines()
        .filter(|l| {
            l.trim_start()
                .split('.')
                .next()
                .is_some_and(|n| n.parse::<u32>().is_ok())
        })
        .collect();
    assert!(steps.len() >= 8, "{section}");
    assert!(
        steps.iter().all(|l| !l.contains("pose_port_refresh")),
        "{section}"
    );
    assert!(
        section.contains("the steps of task `pose_port_refresh`, which play no part"),
        "{section}"
    );
}
