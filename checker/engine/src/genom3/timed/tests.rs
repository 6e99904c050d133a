//! The timed GenoM3 engine on the timing fixtures of
//! `tests/fixtures/genom3/timing/`: which task overruns, and what its
//! trace shows.

use genom_model::component::Component;
use genom_model::trace::{Event, Trace};

use super::analysis::{TimingAnalysis, analyse_timing};
use crate::genom3::machine::Machine;
use crate::kernel::explore::Limits;
use crate::testing::load_genom3_wcet;

macro_rules! fixture {
    ($name:literal) => {
        (
            include_str!(concat!(
                "../../../../../tests/fixtures/genom3/timing/",
                $name,
                ".gen"
            )),
            include_str!(concat!(
                "../../../../../tests/fixtures/genom3/timing/",
                $name,
                ".wcet"
            )),
        )
    };
}

fn timing((text, wcet): (&str, &str), instances: usize) -> (TimingAnalysis, Vec<String>) {
    let c = load_genom3_wcet(text, wcet);
    let m = Machine::new(&c, instances).expect("a GenoM3 component");
    let names = m.tasks.iter().map(|t| t.name.clone()).collect();
    let a = analyse_timing(&m, Limits::default()).expect("few tasks");
    assert!(a.stopped.is_none(), "complete");
    (a, names)
}

fn overrunning(a: &TimingAnalysis, names: &[String]) -> Vec<String> {
    a.overruns.iter().map(|o| names[o.task].clone()).collect()
}

/// Instants of the steps with `event`.
fn times_of(t: &Trace, event: Event) -> Vec<u64> {
    t.steps
        .iter()
        .filter(|s| s.event == event)
        .filter_map(|s| s.time_ns)
        .collect()
}

/// Instants of the codel steps of `service`'s `codel`: (start, end).
fn codel_times(t: &Trace, codel: &str) -> Vec<(Event, u64)> {
    t.steps
        .iter()
        .filter(|s| s.codel.as_deref() == Some(codel))
        .filter(|s| matches!(s.event, Event::CodelStart | Event::CodelEnd))
        .map(|s| (s.event, s.time_ns.expect("timed")))
        .collect()
}

#[test]
fn an_unpaused_chain_runs_in_one_period_and_overruns() {
    let (a, names) = timing(fixture!("f1b_chain_overrun"), 1);
    assert_eq!(overrunning(&a, &names), ["t"]);
    let t = &a.overruns[0].trace;
    // `start` and `exec` run back to back after one tick, and the next tick
    // (10 ms later) comes while `exec` runs.
    let start = codel_times(t, "start");
    let exec = codel_times(t, "exec");
    assert_eq!(start.len(), 2, "{t:#?}");
    assert_eq!(exec.first().map(|x| x.0), Some(Event::CodelStart));
    let ticks = times_of(t, Event::WakeUp);
    let tick = ticks[ticks.len() - 2];
    let end = t.steps.last().and_then(|s| s.time_ns).expect("timed");
    assert_eq!(end - tick, 10_000_000, "one period after the tick");
    assert!(exec[0].1 < end && start[0].1 >= tick);
    assert_eq!(t.steps.last().map(|s| s.event), Some(Event::Violation));
}

#[test]
fn a_paused_chain_fits_its_period() {
    // The static bound of the task's wake-up clears it (15.12), and the
    // whole exploration agrees.
    let (a, names) = timing(fixture!("f1b_chain_paused"), 1);
    assert!(overrunning(&a, &names).is_empty());
    assert_eq!(a.bounded, [0]);
    assert_eq!((a.states, a.records[0].by_bound), (0, true));
    let (text, wcet) = fixture!("f1b_chain_paused");
    let c = load_genom3_wcet(text, wcet);
    let m = Machine::new(&c, 1).expect("GenoM3");
    let whole = super::analysis::analyse_timing_early(&m, Limits::default(), true, false)
        .expect("few tasks");
    assert!(whole.stopped.is_none() && whole.overruns.is_empty());
    assert!(whole.states > 3 && whole.bounded.is_empty());
}

#[test]
fn instances_of_one_activity_share_the_period() {
    let (one, names) = timing(fixture!("f4_instances"), 1);
    assert!(overrunning(&one, &names).is_empty());
    let (two, names) = timing(fixture!("f4_instances"), 2);
    assert_eq!(overrunning(&two, &names), ["t"]);
    let runs = codel_times(&two.overruns[0].trace, "run");
    assert!(runs.iter().filter(|r| r.0 == Event::CodelStart).count() >= 2);
    let (self_int, names) = timing(fixture!("f4_self_interrupt"), 2);
    assert!(overrunning(&self_int, &names).is_empty());
}

#[test]
fn port_readers_exclude_each_other_disjoint_writers_do_not() {
    let (a, names) = timing(fixture!("f9_granularity"), 1);
    let over = overrunning(&a, &names);
    assert!(!over.is_empty());
    let (w, names) = timing(fixture!("f9_writers"), 1);
    assert!(overrunning(&w, &names).is_empty());
    // The overrun waits for the port: one reader starts only after the
    // other's 6 ms.
    let t = &a.overruns[0].trace;
    let starts = times_of(t, Event::CodelStart);
    assert!(
        starts.windows(2).any(|w| w[1] - w[0] >= 4_000_000),
        "{t:#?}"
    );
}

#[test]
fn a_permanent_codel_holds_its_lock_every_period() {
    let (a, names) = timing(fixture!("f3_permanent_lock"), 1);
    // Both ways: `reader` may wait 9 ms for `f3_main`, and `f3_main` 2 ms
    // for `reader` (GenoM3's exclusion lists are symmetric here).
    assert_eq!(overrunning(&a, &names), ["t", "u"]);
    let u = &a.overruns[1].trace;
    let main_end = codel_times(u, "main");
    let read = codel_times(u, "start");
    assert!(
        read.iter().any(|r| r.0 == Event::CodelStart
            && main_end
                .iter()
                .any(|m| m.0 == Event::CodelEnd && m.1 <= r.1)),
        "{u:#?}"
    );
}

#[test]
fn a_control_codel_holds_its_locks_against_tasks() {
    let (a, names) = timing(fixture!("f7_control_lock"), 1);
    assert_eq!(overrunning(&a, &names), ["t"]);
    let t = &a.overruns[0].trace;
    let ctl: Vec<_> = t
        .steps
        .iter()
        .filter(|s| s.thread.as_deref() == Some("control") && s.codel.as_deref() == Some("codel"))
        .collect();
    assert!(ctl.iter().any(|s| s.event == Event::CodelStart), "{t:#?}");
    let (free, names) = timing(fixture!("f7_control_free"), 1);
    assert!(overrunning(&free, &names).is_empty());
}

#[test]
fn the_time_unit_divides_every_duration() {
    let (text, wcet) = fixture!("f7_control_lock");
    let c = load_genom3_wcet(text, wcet);
    let te = super::TimedEngine::new(Machine::new(&c, 1).expect("GenoM3")).expect("few tasks");
    // 10 ms, 6 ms and the control codel's 5 ms: 1 ms.
    assert_eq!(te.unit, 1_000_000);
}

#[test]
fn a_first_tick_after_a_delay_comes_and_an_async_codel_on_a_periodic_task_overruns() {
    // Task `io` wakes first at 1 ms; its `async` codel has no upper bound.
    let text = "component a {\n  task main { period 5 ms; };\n  task io { period 20 ms; delay 1 ms;\n    async codel<start> io_poll() yield pause::start, ether; };\n};\n";
    let (a, _) = timing((text, "io.start 1us\n"), 1);
    assert_eq!(a.overruns.len(), 1);
    let t = &a.overruns[0].trace;
    let ticks = times_of(t, Event::WakeUp);
    assert_eq!(ticks, [1_000_000, 21_000_000], "{t:#?}");
}

#[test]
fn two_tasks_that_waited_for_each_others_lock_do_not_block_each_other() {
    // Both tasks' codels wait behind the control thread's 5 ms codel, then
    // conflict with each other: one goes first (2 ms each), no overrun.
    let text = "component w {\n  ids { long x; };\n  task a { period 10 ms; };\n  task b { period 10 ms; };\n  activity ra() { task a; codel<start, s> fa(inout x) yield pause::s, ether; };\n  activity rb() { task b; codel<start, s> fb(inout x) yield pause::s, ether; };\n  function set(in long v) { codel fs(in v, out x); };\n};\n";
    let (a, _) = timing((text, "ra.s 2ms\nrb.s 2ms\nset.codel 5ms\n"), 1);
    assert!(
        a.overruns.is_empty(),
        "{:#?}",
        a.overruns.first().map(|o| &o.trace)
    );
}

#[test]
fn quiet_requests_left_out_change_no_overrun() {
    // Generated timed components with attributes and functions: the tasks
    // that can overrun are the same with and without the quiet-request
    // reduction, and every trace of the reduced run replays.
    let mut quiet = 0;
    let cases = generated_timed(0..40, |_, cfg| {
        cfg.asyncs = false;
        cfg.tasks = cfg.tasks.min(2);
        cfg.activities = cfg.activities.min(2);
        cfg.states = cfg.states.min(2);
        cfg.attributes = cfg.attributes.max(2);
    });
    for (seed, c) in &cases {
        let m = Machine::new(c, 1).expect("GenoM3");
        let limits = Limits {
            max_states: 200_000,
            ..Limits::default()
        };
        let (Some(fast), Some(full)) = (
            analyse_timing(&m, limits),
            super::analysis::analyse_timing_with(&m, limits, false),
        ) else {
            continue;
        };
        if fast.stopped.is_some() || full.stopped.is_some() {
            continue;
        }
        assert!(fast.states <= full.states, "{seed}");
        quiet += usize::from(fast.states < full.states);
        let tasks = |a: &TimingAnalysis| {
            a.overruns
                .iter()
                .map(|o| o.task)
                .collect::<std::collections::BTreeSet<_>>()
        };
        assert_eq!(tasks(&fast), tasks(&full), "{seed}");
        replays(seed, c, 1, &fast);
    }
    assert!(
        quiet >= 5,
        "the reduction applied to {quiet} components only"
    );
}

/// Small generated timed components, shaped by `shape`, named by seed.
pub(super) fn generated_timed(
    seeds: std::ops::Range<u64>,
    shape: impl Fn(u64, &mut genom_generate::Genom3Config),
) -> Vec<(String, Component)> {
    seeds
        .map(|seed| {
            let mut cfg = genom_generate::Genom3Config::small(seed);
            cfg.timed = true;
            shape(seed, &mut cfg);
            let g = genom_generate::generate_genom3(&cfg);
            let wcet = g.wcet.clone().expect("timed");
            (format!("seed {seed}"), load_genom3_wcet(&g.r#gen, &wcet))
        })
        .collect()
}

/// 40 generated timed components with locks, attributes and, every
/// `async_every`-th seed, `async` codels; 20 with many `interrupts`
/// (activities that restart themselves or one another: one instance among
/// them per wake-up); each with `tasks` tasks at least and at most; then
/// the timing fixtures.
pub(super) fn mixed_cases(tasks: (usize, usize), async_every: u64) -> Vec<(String, Component)> {
    let (least, most) = tasks;
    let mut cases = generated_timed(0..40, |seed, cfg| {
        cfg.asyncs = seed % async_every == 0;
        cfg.tasks = cfg.tasks.clamp(least, most);
        cfg.activities = cfg.activities.min(3);
        cfg.states = cfg.states.min(3);
        cfg.attributes = cfg.attributes.max(1);
    });
    cases.extend(generated_timed(40..60, |_, cfg| {
        cfg.tasks = cfg.tasks.clamp(least, most);
        cfg.activities = cfg.activities.clamp(2, 3);
        cfg.states = cfg.states.min(3);
        cfg.density = 3.0;
    }));
    cases.extend(timing_fixtures());
    cases
}

/// The timing fixtures with a WCET file, by file stem.
pub(super) fn timing_fixtures() -> Vec<(String, Component)> {
    let dir = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/fixtures/genom3/timing"
    );
    let mut paths: Vec<_> = std::fs::read_dir(dir)
        .expect("fixtures")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "gen"))
        .collect();
    paths.sort();
    paths
        .into_iter()
        .filter_map(|path| {
            let wcet = std::fs::read_to_string(path.with_extension("wcet")).ok()?;
            let text = std::fs::read_to_string(&path).expect("fixture");
            let stem = path.file_stem()?.to_string_lossy().into_owned();
            Some((stem, load_genom3_wcet(&text, &wcet)))
        })
        .collect()
}

/// Every overrun trace of `a` replays in the independent oracle.
pub(super) fn replays(name: &str, c: &Component, instances: usize, a: &TimingAnalysis) {
    for o in &a.overruns {
        genom_oracles::replay::genom3_timed::replay_genom3_timed(c, instances, &o.trace)
            .unwrap_or_else(|e| panic!("{name}: {e}\n{:#?}", o.trace));
    }
}

#[test]
fn the_early_stop_changes_no_finding_and_no_trace() {
    // Generated timed components and the timing fixtures: with and
    // without the early stop (15.11), the same tasks, causes and traces
    // (word for word), and the early stop stores no more states; it stops
    // some explorations early (those whose tasks all overrun).
    let mut cases = generated_timed(0..30, |_, cfg| {
        cfg.tasks = cfg.tasks.min(2);
        cfg.activities = cfg.activities.min(2);
        cfg.states = cfg.states.min(2);
    });
    cases.extend(timing_fixtures().into_iter().filter(|(name, _)| {
        ["f9_granularity", "f1b_chain_overrun", "f10_restart"].contains(&name.as_str())
    }));
    let limits = Limits {
        max_states: 200_000,
        ..Limits::default()
    };
    let mut stopped_early = 0;
    for (name, c) in &cases {
        let m = Machine::new(c, 1).expect("GenoM3");
        let (Some(early), Some(whole)) = (
            super::analysis::analyse_timing_early(&m, limits, true, true),
            super::analysis::analyse_timing_early(&m, limits, true, false),
        ) else {
            continue;
        };
        if whole.stopped.is_some() {
            continue;
        }
        assert!(early.stopped.is_none(), "{name}");
        assert!(early.states <= whole.states, "{name}");
        stopped_early += usize::from(early.states < whole.states);
        let findings = |a: &TimingAnalysis| {
            a.overruns
                .iter()
                .map(|o| (o.task, o.cause, format!("{:?}", o.trace)))
                .collect::<Vec<_>>()
        };
        assert_eq!(findings(&early), findings(&whole), "{name}");
        replays(name, c, 1, &early);
    }
    assert!(
        stopped_early >= 3,
        "the early stop applied {stopped_early} times"
    );
}

#[test]
fn a_task_the_static_bound_clears_never_overruns() {
    // Generated timed components (locks, functions, attributes, several
    // tasks; some with `async` codels) and the timing fixtures: every task
    // the static bound of 15.12 clears has no overrun in the whole
    // exploration (no early stop, no bound), and the bound clears some
    // tasks, so the comparison is not vacuous.
    let cases = mixed_cases((2, 3), 3);
    let limits = Limits {
        max_states: 60_000,
        ..Limits::default()
    };
    let (mut cleared, mut compared) = (0, 0);
    for (name, c) in &cases {
        for instances in [1, 2] {
            let m = Machine::new(c, instances).expect("GenoM3");
            let Some(bounded) = analyse_timing(&m, limits) else {
                continue;
            };
            let Some(whole) = super::analysis::analyse_timing_early(&m, limits, true, false) else {
                continue;
            };
            if whole.stopped.is_some() {
                continue;
            }
            compared += 1;
            for &t in &bounded.bounded {
                cleared += 1;
                assert!(
                    whole.overruns.iter().all(|o| o.task != t),
                    "{name}, {instances} instance(s): task {} cleared by the bound overruns",
                    m.tasks[t].name
                );
            }
            let tasks = |a: &TimingAnalysis| {
                a.overruns
                    .iter()
                    .map(|o| (o.task, o.cause))
                    .collect::<Vec<_>>()
            };
            assert_eq!(tasks(&bounded), tasks(&whole), "{name}");
            replays(name, c, instances, &bounded);
        }
    }
    assert!(compared >= 60, "{compared} complete explorations compared");
    assert!(cleared >= 40, "the bound cleared {cleared} tasks only");
    eprintln!("{compared} complete explorations compared, {cleared} tasks cleared");
}

#[test]
fn a_request_stands_for_one_with_the_same_locks_and_a_shorter_codel() {
    // `brief` and `lengthy` write `x`, which the task's 6 ms codel reads:
    // `lengthy`'s 5 ms codel can delay it past its 10 ms period, `brief`'s
    // 1 ms cannot. For schedulability `lengthy` stands for `brief` (every
    // run of `brief` is one of `lengthy`'s): the same overrun, from fewer
    // states, and its trace replays; response times keep both.
    let text = "component d {\n  ids { long x; };\n  task t { period 10 ms; };\n  activity r() { task t; codel<start, s> fr(in x) yield pause::s, ether; };\n  function brief(in long v) { codel fb(in v, out x); };\n  function lengthy(in long v) { codel fl(in v, out x); };\n};\n";
    let wcet = "r.s 6ms\nbrief.codel 1ms\nlengthy.codel 5ms\n";
    let c = load_genom3_wcet(text, wcet);
    let m = Machine::new(&c, 1).expect("GenoM3");
    let name = |k: u16| {
        m.service_name(m.controls[usize::from(k)].service)
            .to_string()
    };
    let mut te = super::TimedEngine::new(m.clone()).expect("few tasks");
    let exact: Vec<String> = te.canon.iter().take(2).map(|&k| name(k)).collect();
    assert_eq!(
        exact,
        ["brief", "lengthy"],
        "different WCETs: not the same runs"
    );
    te.dominate_calls();
    let dominated: Vec<String> = te.canon.iter().take(2).map(|&k| name(k)).collect();
    assert_eq!(dominated, ["lengthy", "lengthy"]);
    let limits = Limits::default();
    let fast = analyse_timing(&m, limits).expect("few tasks");
    let full = super::analysis::analyse_timing_with(&m, limits, false).expect("few tasks");
    assert!(fast.stopped.is_none() && full.stopped.is_none());
    assert!(fast.states < full.states, "{} {}", fast.states, full.states);
    let tasks = |a: &TimingAnalysis| {
        a.overruns
            .iter()
            .map(|o| (o.task, o.cause))
            .collect::<Vec<_>>()
    };
    assert_eq!(tasks(&fast), tasks(&full));
    assert_eq!(fast.overruns.len(), 1);
    let trace = &fast.overruns[0].trace;
    assert!(
        trace.steps.iter().any(|s| s.codel.as_deref() == Some("codel")
            && s.service.as_deref() == Some("lengthy")),
        "{trace:#?}"
    );
    genom_oracles::replay::genom3_timed::replay_genom3_timed(&c, 1, trace)
        .unwrap_or_else(|e| panic!("{e}\n{trace:#?}"));
}

#[test]
fn an_overrun_found_with_a_restricted_client_is_one_of_the_whole_exploration() {
    // The search with restricted clients (15.13), asked for every periodic
    // task of every group of generated components: each overrun it finds
    // is one of the whole exploration, and its trace replays in the
    // independent oracle. (On the corpus it finds rmp440's `TrackTask`,
    // tests/genom3/genom3_timing.rs.)
    let cases = generated_timed(0..50, |_, cfg| {
        cfg.tasks = cfg.tasks.clamp(2, 3);
        cfg.activities = cfg.activities.min(3);
        cfg.states = cfg.states.min(2);
    });
    let budget = Limits {
        max_states: 60_000,
        ..Limits::default()
    };
    let (mut hunted, mut compared) = (0, 0);
    for (name, c) in &cases {
        let m = Machine::new(c, 1).expect("GenoM3");
        let every = super::analysis::Tuning {
            probe: usize::MAX,
            examined: usize::MAX,
        };
        let Some(whole) = super::analysis::analyse_timing_tuned(&m, budget, true, false, every)
        else {
            continue;
        };
        if whole.stopped.is_some() {
            continue;
        }
        compared += 1;
        let locks = super::locks::Locks::new(&m, super::unit_ns(&m));
        let mut found = TimingAnalysis::default();
        for group in super::groups::groups(&m, &locks) {
            let te = super::TimedEngine::with_locks(m.clone(), &group, locks.clone()).expect("few");
            let wanted: super::hunt::Wanted = super::bound::possible_causes(&te)
                .into_iter()
                .enumerate()
                .filter(|&(t, _)| group.tasks[t] && m.tasks[t].period_ns.is_some())
                .collect();
            let h = super::hunt::hunt(&m, &group, &locks, &wanted, budget, budget.max_states / 10);
            found.overruns.extend(h.overruns);
        }
        for o in &found.overruns {
            hunted += 1;
            assert!(
                whole
                    .overruns
                    .iter()
                    .any(|w| (w.task, w.cause) == (o.task, o.cause)),
                "{name}: task {} found overrunning ({:?}) by the search only",
                m.tasks[o.task].name,
                o.cause
            );
        }
        replays(name, c, 1, &found);
    }
    assert!(compared >= 20, "{compared} whole explorations compared");
    assert!(hunted >= 10, "the search found {hunted} overruns only");
    eprintln!("{compared} whole explorations, {hunted} overruns found by the search");
}
