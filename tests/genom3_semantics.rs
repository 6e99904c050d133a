//! GenoM3's execution semantics, point by point (issue 13): each fixture of
//! `tests/fixtures/genom3/semantics/` has the verdict GenoM3's engine gives
//! it, which differs from the verdict of the LANGUAGE.md semantics run on
//! the same lowered model (the "naive" reading). Every trace is replayed by
//! the independent replay (`genom_oracles::replay::genom3`), and the
//! verdicts do not change with more instances of each activity.

#![allow(clippy::expect_used, clippy::unwrap_used)] // test support code outside #[test] functions

use std::path::{Path, PathBuf};

use genom_check::{CheckOptions, CheckResult, Inputs, check_path};
use genom_checker::dialect::{Limits, analyse_with};
use genom_checker::genom3::{G3Analysis, Owner, analyse_genom3};
use genom_model::component::Component;
use genom_model::trace::Event;
use genom_model::{Code, Diagnostic, Severity};

mod common;

const DIR: &str = "tests/fixtures/genom3/semantics";

fn check(name: &str) -> CheckResult {
    let path = Path::new(DIR).join(name);
    check_path(&path, &Inputs::default(), &CheckOptions::new()).unwrap()
}

/// Error and warning codes with the first word in backquotes of their
/// message (the service or activity), sorted.
fn findings(r: &CheckResult) -> Vec<(Code, String)> {
    let mut v: Vec<(Code, String)> = r
        .diagnostics
        .iter()
        .filter(|d| d.severity != Severity::Advice && d.code != Code::NoTermination)
        .map(|d| (d.code, named(d)))
        .collect();
    v.sort();
    v
}

fn named(d: &Diagnostic) -> String {
    d.message.split('`').nth(1).unwrap_or_default().to_owned()
}

fn component(r: &CheckResult) -> &Component {
    r.component.as_ref().expect("a component")
}

fn analysis(c: &Component, n: usize) -> G3Analysis {
    analyse_genom3(c, n, Limits::default()).expect("a GenoM3 component")
}

/// Every trace of a GenoM3 verdict replays, and a lasso ends with its
/// violation.
fn assert_traces_replay(r: &CheckResult) {
    let c = component(r);
    for d in &r.diagnostics {
        let Some(t) = &d.trace else { continue };
        if t.steps.is_empty() {
            continue;
        }
        genom_oracles::replay::genom3::replay_genom3(c, t)
            .unwrap_or_else(|e| panic!("{}: {e}\n{t:#?}", d.message));
        if matches!(d.code, Code::Livelock | Code::UnpausedLoop) {
            assert!(t.loop_start.is_some());
            assert_eq!(t.steps.last().map(|s| s.event), Some(Event::Violation));
        }
    }
}

#[test]
fn point_1_an_unpaused_cycle_is_a_livelock_with_a_replayed_lasso() {
    let r = check("f1a_livelock.gen");
    assert_eq!(findings(&r), [(Code::Livelock, "spin".to_owned())]);
    assert_traces_replay(&r);
    let d = r
        .diagnostics
        .iter()
        .find(|d| d.code == Code::Livelock)
        .unwrap();
    let t = d.trace.as_ref().unwrap();
    let round = &t.steps[t.loop_start.unwrap()..t.steps.len() - 1];
    assert_eq!(round.len(), 1);
    assert_eq!(
        (round[0].codel.as_deref(), round[0].outcome.as_deref()),
        (Some("step"), Some("step"))
    );
    // With a way out of the cycle: a warning, not an error.
    let r = check("f1c_unpaused_loop.gen");
    assert_eq!(findings(&r), [(Code::UnpausedLoop, "count".to_owned())]);
    assert_traces_replay(&r);
}

#[test]
fn point_2_pause_on_an_aperiodic_task_is_no_loop() {
    let r = check("f2_pause_aperiodic.gen");
    assert_eq!(findings(&r), []);
    let a = analysis(component(&r), 1);
    assert!(a.livelocks.is_empty());
    // `sleep` is run (the paused instance resumes).
    assert!(
        a.reached
            .iter()
            .any(|(o, s)| matches!(o, Owner::Activity(_)) && *s > 0)
    );
}

#[test]
fn point_3_permanent_codels_run_from_start_to_shutdown() {
    let r = check("f3_permanent.gen");
    assert_eq!(findings(&r), []);
    let a = analysis(component(&r), 1);
    // Task `t` (the first) runs start, main and, at kill, stop.
    let perm: Vec<u8> = a
        .reached
        .iter()
        .filter(|(o, _)| *o == Owner::Task(0))
        .map(|(_, s)| *s)
        .collect();
    assert_eq!(perm.len(), 3, "{perm:?}");
}

#[test]
fn point_5_an_after_cycle_makes_its_services_dead() {
    let r = check("f5_after_cycle.gen");
    assert_eq!(
        findings(&r),
        [
            (Code::DeadService, "left".to_owned()),
            (Code::DeadService, "right".to_owned())
        ]
    );
    let d = &r.diagnostics[0];
    assert!(
        d.help.as_deref().unwrap().contains("genom::disallowed"),
        "{d:?}"
    );
    // Naive (after/before ignored): nothing is dead.
    let naive = analyse_with(component(&r), Limits::default(), true);
    assert!(naive.dead.is_empty());
}

#[test]
fn point_6_a_stop_path_reaching_ether_is_a_success() {
    let r = check("f6_interrupt_stop.gen");
    assert_eq!(findings(&r), []);
    // Without a stop codel the interrupted `servo` never succeeds.
    let r = check("f6b_interrupt_no_stop.gen");
    assert_eq!(findings(&r), [(Code::DeadService, "next".to_owned())]);
    let naive = analyse_with(component(&r), Limits::default(), true);
    assert!(naive.dead.is_empty());
}

#[test]
fn point_8_a_cycle_through_an_async_codel_is_no_livelock() {
    let r = check("f8_async.gen");
    assert_eq!(findings(&r), []);
    // The same component without `async`: task `io` livelocks, in two
    // loops that together go through `poll` and `got`.
    let text = std::fs::read_to_string(Path::new(DIR).join("f8_async.gen"))
        .unwrap()
        .replace("async codel", "codel");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("f8_sync.gen");
    std::fs::write(&path, text).unwrap();
    let r = check_path(&path, &Inputs::default(), &CheckOptions::new()).unwrap();
    assert_eq!(
        findings(&r),
        [
            (Code::Livelock, "io".to_owned()),
            (Code::Livelock, "io".to_owned())
        ]
    );
    assert_traces_replay(&r);
    let rounds: Vec<_> = with_code(&r, Code::Livelock)
        .into_iter()
        .map(round)
        .collect();
    assert_eq!(
        rounds,
        [
            vec![("poll", "got"), ("got", "poll")],
            vec![("poll", "poll")]
        ]
    );
}

/// The `(codel, outcome)` steps of the round a lasso repeats.
fn round(d: &Diagnostic) -> Vec<(&str, &str)> {
    let t = d.trace.as_ref().expect("a trace");
    let start = t.loop_start.expect("a lasso");
    t.steps[start..t.steps.len() - 1]
        .iter()
        .map(|s| {
            let codel = s.codel.as_deref().unwrap_or_default();
            (codel, s.outcome.as_deref().unwrap_or_default())
        })
        .collect()
}

/// The diagnostics of `r` with `code`, in report order.
fn with_code(r: &CheckResult, code: Code) -> Vec<&Diagnostic> {
    r.diagnostics.iter().filter(|d| d.code == code).collect()
}

#[test]
fn point_8_an_async_codel_exempts_only_the_cycles_through_it() {
    let r = check("f8b_async_drain.gen");
    assert_eq!(findings(&r), [(Code::UnpausedLoop, "drain".to_owned())]);
    assert_traces_replay(&r);
    let d = with_code(&r, Code::UnpausedLoop)[0];
    assert_eq!(
        d.message,
        "activity `drain` may loop through `recv` → `recv` without `pause::`: task `io` has no period, so it busy-spins until the loop ends"
    );
    assert_eq!(round(d), [("recv", "recv")]);
    let t = d.trace.as_ref().unwrap();
    assert!(
        t.steps[t.steps.len() - 1]
            .text
            .ends_with("task `io`, which has no period, busy-spins between events"),
        "{t:#?}"
    );
    // The twin: `recv` waits (`pause::recv`) or goes through the async `wait`.
    let r = check("f8c_async_drain_paused.gen");
    assert_eq!(findings(&r), []);
    assert!(analysis(component(&r), 1).livelocks.is_empty());
}

#[test]
fn point_1_every_state_that_can_spin_is_on_a_reported_loop() {
    let r = check("f1d_every_loop.gen");
    assert_eq!(
        findings(&r),
        [
            (Code::UnpausedLoop, "walk".to_owned()),
            (Code::UnpausedLoop, "walk".to_owned())
        ]
    );
    assert_traces_replay(&r);
    let loops = with_code(&r, Code::UnpausedLoop);
    let messages: Vec<&str> = loops.iter().map(|d| d.message.as_str()).collect();
    assert_eq!(
        messages,
        [
            "activity `walk` may loop through `a` → `b` → `a` without `pause::`",
            "activity `walk` may loop through `b` → `c` → `b` without `pause::`"
        ]
    );
    assert_eq!(round(loops[0]), [("a", "b"), ("b", "a")]);
    assert_eq!(round(loops[1]), [("b", "c"), ("c", "b")]);
    assert_eq!(findings(&check("f1e_every_loop_paused.gen")), []);
}

#[test]
fn point_2_a_loop_on_an_aperiodic_task_is_a_busy_spin() {
    let r = check("f2b_busy_aperiodic.gen");
    assert_eq!(findings(&r), [(Code::Livelock, "poller".to_owned())]);
    assert_traces_replay(&r);
    let d = with_code(&r, Code::Livelock)[0];
    assert_eq!(
        d.message,
        "the permanent codels of task `poller` loop through `check` → `check` forever without `pause::`: task `poller` has no period and busy-spins"
    );
    let help = d.help.as_deref().unwrap();
    assert!(
        help.contains("`async`")
            && help.contains("give task `poller` a `period`")
            && help.contains("can stall the task"),
        "{help}"
    );
    assert_eq!(round(d), [("check", "check")]);
    // The twin: `check` blocks on its event (`async`).
    assert_eq!(findings(&check("f2c_busy_aperiodic_async.gen")), []);
}

#[test]
fn point_10_an_activity_ending_only_by_exception_never_completes() {
    let r = check("f10_exceptions.gen");
    assert_eq!(findings(&r), [(Code::DeadService, "next".to_owned())]);
    assert_traces_replay(&r);
    let naive = analyse_with(component(&r), Limits::default(), true);
    assert!(naive.dead.is_empty());
}

#[test]
fn the_tasks_start_in_order_before_any_request() {
    let r = check("perm_boot.gen");
    assert_eq!(findings(&r), [(Code::UnpausedLoop, "n".to_owned())]);
    assert_traces_replay(&r);
    let d = &r
        .diagnostics
        .iter()
        .find(|d| d.code == Code::UnpausedLoop)
        .unwrap();
    let t = d.trace.as_ref().unwrap();
    // Task `m` starts first (its start codel, not an exception), then `n`.
    assert_eq!(t.steps[1].thread.as_deref(), Some("m"));
    assert_eq!(t.steps[1].outcome.as_deref(), Some("main"));
}

/// Each fixture's source and its rendered report (colour off, width 100),
/// traces included.
#[test]
fn point_6_a_new_instance_runs_its_first_codel_before_any_interruption() {
    let r = check("f6c_start_runs_first.gen");
    assert_eq!(
        findings(&r),
        [(Code::UnreachableCodel, "f6c_stop".to_owned())]
    );
    let c = component(&r);
    let a = analysis(c, 1);
    let quick = c.service_named("quick").unwrap();
    assert!(a.started.contains(&quick) && a.completed.contains(&quick));
    assert_eq!(
        a.reached.len(),
        2,
        "both `start` codels run: {:?}",
        a.reached
    );
}

#[test]
fn each_fixture_report_is_snapshotted() {
    insta::glob!("fixtures/genom3/semantics/*.gen", |path| {
        // Relative, so that the snapshot does not name the checkout.
        let shown = format!("{DIR}/{}", path.file_name().unwrap().to_string_lossy());
        let result =
            check_path(Path::new(&shown), &Inputs::default(), &CheckOptions::new()).unwrap();
        let report = genom_render::FileReport {
            path: &shown,
            sources: &result.sources,
            diagnostics: &result.diagnostics,
            statistics: None,
            dialect: genom_model::Dialect::Genom3,
            pragmas: &[],
            response_times: &[],
        };
        let options = genom_render::human::HumanOptions {
            color: false,
            width: 100,
        };
        let mut text = std::fs::read_to_string(path).unwrap();
        text.push_str("\n----- report -----\n");
        text.push_str(&genom_render::human::render_diagnostics(&report, options));
        text.push_str(&genom_render::human::render_summary(
            &shown,
            report.counts(),
        ));
        insta::assert_snapshot!(text);
    });
}

#[test]
fn verdicts_do_not_change_with_more_instances() {
    for entry in std::fs::read_dir(DIR).unwrap() {
        let name = entry.unwrap().file_name().into_string().unwrap();
        let r = check(&name);
        let c = component(&r);
        let one = analysis(c, 1);
        for n in [2, 3] {
            let more = analysis(c, n);
            assert!(more.states >= one.states, "{name}");
            assert_eq!(
                (&more.started, &more.completed, &more.reached),
                (&one.started, &one.completed, &one.reached),
                "{name} with {n} instances"
            );
            let cycles = |a: &G3Analysis| -> Vec<_> {
                a.livelocks.iter().map(|l| l.cycle.clone()).collect()
            };
            assert_eq!(cycles(&more), cycles(&one), "{name}");
        }
    }
}

/// The unpaused loops of the corpus (docs/genom3.md, "The corpus under
/// GenoM3's semantics"): each state that can spin is on a reported loop,
/// and every trace replays.
#[test]
fn the_corpus_unpaused_loops_are_every_loop_and_replay() {
    let Some(dir) = common::genom3_corpus() else {
        return;
    };
    let inputs = Inputs {
        include_dirs: vec![PathBuf::from("tests/fixtures/genom3/include")],
        ..Inputs::default()
    };
    let mut found: Vec<(&str, Vec<String>)> = Vec::new();
    for file in [
        "arucotag-genom3/arucotag.gen",
        "foxglove-genom3/foxglove.gen",
        "nhfc-genom3/nhfc.gen",
        "rotorcraft-genom3/rotorcraft.gen",
        "WAMCtrl-genom3/wamctrl.gen",
    ] {
        let r = check_path(&dir.join(file), &inputs, &CheckOptions::new()).unwrap();
        assert_traces_replay(&r);
        let name = file.split('/').next_back().unwrap();
        for d in &r.diagnostics {
            assert_ne!(d.code, Code::Livelock, "{name}: {}", d.message);
            if d.code == Code::UnpausedLoop {
                found.push((
                    name,
                    round(d).iter().map(|(c, _)| (*c).to_owned()).collect(),
                ));
            }
        }
    }
    let expected: Vec<(&str, Vec<String>)> = [
        ("arucotag.gen", &["poll", "main", "log"][..]),
        ("arucotag.gen", &["poll", "main"]),
        ("arucotag.gen", &["poll"]),
        ("foxglove.gen", &["ready"]),
        ("foxglove.gen", &["publish"]),
        ("nhfc.gen", &["control", "emergency"]),
        ("rotorcraft.gen", &["recv"]),
        ("wamctrl.gen", &["control", "emergency"]),
    ]
    .into_iter()
    .map(|(f, r)| (f, r.iter().map(|s| (*s).to_owned()).collect()))
    .collect();
    assert_eq!(found, expected);
}
