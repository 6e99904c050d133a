//! Tests of the GenoM3 engine's rules on small components: interrupters
//! waiting for stop paths, the `kill` shutdown, the boot order, and the
//! words of a trace whose codel ends with an exception.

use genom_model::component::{Component, Idx};

use super::machine::{Machine, Role};
use super::state::{G3State, Phase, Status};
use super::steps::{Engine, G3Action};
use crate::kernel::explore::Model;

fn load(text: &str) -> Component {
    crate::testing::load_genom3(text)
}

const H: &str = "component h {
  task t { period 10 ms; };
  activity servo() {
    task t;
    codel<start, main> h_main() yield pause::main;
    codel<stop> h_stop() yield pause::stop, ether;
  };
  activity halt() { task t; interrupts servo; codel<start> h_halt() yield ether; };
};";

fn activity(e: &Engine<'_>, name: &str) -> usize {
    let sid = e.m.c.service_named(name).unwrap();
    match e.m.role[&sid] {
        Role::Activity(a) => a,
        Role::Control(_) => panic!("{name} is no activity"),
    }
}

/// The one enabled action matching `pick`, applied.
fn step(e: &Engine<'_>, s: &G3State, pick: impl Fn(&G3Action) -> bool) -> G3State {
    let mut actions = Vec::new();
    e.actions(s, &mut actions);
    let a = *actions.iter().find(|a| pick(a)).expect("enabled");
    e.next_state(s, a).expect("a change")
}

#[test]
fn every_waiting_interrupter_starts_when_the_stop_path_ends() {
    let c = load(H);
    let e = Engine::new(Machine::new(&c, 3).unwrap());
    let (servo, halt) = (activity(&e, "servo"), activity(&e, "halt"));
    let accept = |x: usize| move |a: &G3Action| *a == G3Action::Accept(x as u16);
    let mut s = e.initial();
    assert_eq!(s.phase, Phase::Run);
    s = step(&e, &s, accept(servo));
    s = step(
        &e,
        &s,
        |a| matches!(a, G3Action::Start(x, _, _) if usize::from(*x) == servo),
    );
    s = step(&e, &s, accept(halt));
    s = step(&e, &s, accept(halt));
    assert_eq!(s.inst[servo][0].status, Status::Stop);
    assert!(s.inst[halt].iter().all(|i| i.status == Status::Delayed));
    // `stop` yields `ether` (outcome 1): both `halt`s are released.
    s = step(
        &e,
        &s,
        |a| matches!(a, G3Action::Codel(x, _, 1) if usize::from(*x) == servo),
    );
    assert!(s.inst[servo].is_empty());
    assert_eq!(s.inst[halt].len(), 2);
    assert!(s.inst[halt].iter().all(|i| i.status == Status::Ready));
    // Its completion is seen; no `after`/`before` reads it, so the state
    // does not keep it.
    let sv = e.m.activities[servo].service.index();
    assert_eq!(e.completions_seen()[sv / 64] >> (sv % 64) & 1, 1);
    assert!(!s.is_done(sv));
}

#[test]
fn kill_drains_then_runs_the_permanent_stop_paths_last_task_first() {
    let c = load(
        "component k {
          task a { codel<start> k_a() yield pause::start; codel<stop> k_as() yield ether; };
          task b { codel<start> k_b() yield pause::start; codel<stop> k_bs() yield ether; };
        };",
    );
    let e = Engine::new(Machine::new(&c, 1).unwrap());
    let mut s = e.initial();
    assert_eq!(s.phase, Phase::Boot);
    // Task `b` waits for `a`'s first codel.
    let mut actions = Vec::new();
    e.actions(&s, &mut actions);
    assert!(actions.iter().all(|a| matches!(a, G3Action::Perm(0, _))));
    s = step(&e, &s, |a| *a == G3Action::Perm(0, 0));
    s = step(&e, &s, |a| *a == G3Action::Perm(1, 0));
    assert_eq!(s.phase, Phase::Run);
    let kill =
        e.m.controls
            .iter()
            .position(|k| e.m.service_name(k.service) == "kill");
    s = step(&e, &s, |a| *a == G3Action::Call(kill.unwrap() as u16));
    assert_eq!(s.phase, Phase::PermStop(1));
    s = step(&e, &s, |a| *a == G3Action::Perm(1, 0));
    assert_eq!(s.phase, Phase::PermStop(0));
    s = step(&e, &s, |a| *a == G3Action::Perm(0, 0));
    assert_eq!(s.phase, Phase::Stopped);
    actions.clear();
    e.actions(&s, &mut actions);
    assert!(actions.is_empty());
}

/// The path that takes, from the initial state, the first enabled action
/// matching each of `picks` in turn.
fn path(e: &Engine<'_>, picks: &[&dyn Fn(&G3Action) -> bool]) -> Vec<G3Action> {
    let mut s = e.initial();
    let mut out = Vec::new();
    for pick in picks {
        let mut actions = Vec::new();
        e.actions(&s, &mut actions);
        let a = *actions.iter().find(|a| pick(a)).expect("enabled");
        s = e.next_state(&s, a).expect("a change");
        out.push(a);
    }
    out
}

#[test]
fn a_codel_exception_names_the_exceptions_it_stands_for() {
    let c = load(
        "component x {
          exception e_refused;
          exception e_busy;
          exception e_hw;
          task t { period 10 ms; throw e_hw; codel<start> x_boot() yield pause::start; };
          activity go() { task t; throw e_refused, e_busy; codel<start> x_go() yield ether; };
          activity bare() { task t; codel<start> x_bare() yield ether; };
        };",
    );
    let e = Engine::new(Machine::new(&c, 1).unwrap());
    let texts = |p: &[G3Action]| -> Vec<String> {
        let t = super::trace::render(&e, p);
        genom_oracles::replay::genom3::replay_genom3(&c, &t)
            .unwrap_or_else(|err| panic!("{err}\n{t:#?}"));
        t.steps.iter().map(|s| s.text.clone()).collect()
    };
    let exception_of = |name: &str| {
        let x = activity(&e, name) as u16;
        // One past the start codel's one yield (`ether`): the exception.
        move |a: &G3Action| matches!(*a, G3Action::Start(y, _, 1) if y == x)
    };
    let accept = |name: &str| {
        let x = activity(&e, name) as u16;
        move |a: &G3Action| *a == G3Action::Accept(x)
    };
    let boot = |a: &G3Action| *a == G3Action::Perm(0, 0);
    let go = texts(&path(&e, &[&boot, &accept("go"), &exception_of("go")]));
    assert_eq!(
        go.last().unwrap(),
        "activity `go` runs codel `x_go` in state `start`, which yields an exception (`x::e_busy`, `x::e_refused` or a built-in `genom::…` one): the instance ends with it"
    );
    let bare = texts(&path(&e, &[&boot, &accept("bare"), &exception_of("bare")]));
    assert!(
        bare.last().unwrap().ends_with(
            "which yields an exception (a built-in `genom::…` one, since no `throw` is declared): the instance ends with it"
        ),
        "{bare:?}"
    );
    // The permanent codel names its task's `throw`; it fails the start.
    let perm = texts(&path(&e, &[&|a: &G3Action| *a == G3Action::Perm(0, 1)]));
    assert!(
        perm.last().unwrap().contains(
            "which yields an exception (`x::e_hw` or a built-in `genom::…` one): the instance ends with it; the component fails to start"
        ),
        "{perm:?}"
    );
}

#[test]
fn the_early_stop_changes_no_fact_and_no_trace() {
    // Generated untimed components: with and without stopping each part
    // once every fact it can show is found, the same services start and
    // complete, the same codels are reached, the same livelocks are found
    // with the same traces, and the boot is the same path.
    let mut stopped_early = 0;
    for seed in 0..80 {
        let mut cfg = genom_generate::Genom3Config::small(seed);
        cfg.timed = false;
        let g = genom_generate::generate_genom3(&cfg);
        let c = crate::testing::load_genom3(&g.r#gen);
        let m = Machine::new(&c, 1).expect("GenoM3");
        let limits = crate::kernel::explore::Limits {
            max_states: 200_000,
            ..Default::default()
        };
        let fast = super::analysis::analyse_machine_with(&m, limits, true);
        let full = super::analysis::analyse_machine_with(&m, limits, false);
        if full.stopped.is_some() {
            continue;
        }
        assert!(fast.stopped.is_none(), "seed {seed}");
        assert!(fast.states <= full.states, "seed {seed}");
        stopped_early += usize::from(fast.states < full.states);
        assert_eq!(fast.started, full.started, "seed {seed}");
        assert_eq!(fast.completed, full.completed, "seed {seed}");
        assert_eq!(fast.reached, full.reached, "seed {seed}");
        assert_eq!(fast.boot, full.boot, "seed {seed}");
        let lassos = |a: &super::G3Analysis| format!("{:?}", a.livelocks);
        assert_eq!(lassos(&fast), lassos(&full), "seed {seed}");
    }
    assert!(
        stopped_early >= 10,
        "the early stop applied to {stopped_early} components only"
    );
}
