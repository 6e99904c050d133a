//! Tests of the compositional exploration: the parts and their order, the
//! projection of a part's graph to the automaton of its interface, and
//! explorations in product with it.

use genom_model::behaviour::Behaviour;

use super::*;
use crate::kernel::explore::{Limits, explore};
use crate::testing::{HEADER, check};

fn component(body: &str) -> Component {
    check(&format!("{HEADER}{body}"))
        .component
        .expect("a component")
}

/// The resolved component, without exploring it.
fn resolved(body: &str) -> Component {
    component(body)
}

fn svc(name: &str, rules: &str) -> String {
    format!(
        "service {name} {{ thread: main; {rules}\n\
         start codel {{ exec: f(); next: run; }}\n\
         exec codel run {{ exec: g(); next: run, end; }} }}\n"
    )
}

fn names(c: &Component, parts: &[Vec<ServiceId>]) -> Vec<Vec<String>> {
    parts
        .iter()
        .map(|p| p.iter().map(|&s| c.services[s].name.name.clone()).collect())
        .collect()
}

/// `a` delays `b`, `b` forbids `c`, `c` and `d` stop each other.
fn chain() -> Component {
    let body = [
        svc("a", "delays: b;"),
        svc("b", "forbids: c;"),
        svc("c", "stops: d;"),
        svc("d", "stops: c;"),
    ]
    .concat();
    component(&body)
}

#[test]
fn parts_follow_dependencies_upstream_first() {
    let c = chain();
    let all: Vec<ServiceId> = c.services.ids().collect();
    let plan = Plan::new(&c, &all);
    assert_eq!(
        names(&c, &plan.parts),
        [vec!["a"], vec!["b"], vec!["c", "d"]]
    );
    // Cones: each part with what it depends on, directly or not.
    assert_eq!(
        names(&c, &[plan.cone(0), plan.cone(2)]),
        [vec!["a"], vec!["a", "b", "c", "d"]]
    );
    // Only `b` is read by `c`; `a` by `b`; interfaces carry them.
    assert_eq!(names(&c, &plan.inputs), [vec![], vec!["a"], vec!["b"]]);
    let interfaces: Vec<Vec<ServiceId>> = (0..3).map(|k| plan.interface(k).to_vec()).collect();
    assert_eq!(names(&c, &interfaces), [vec!["a"], vec!["b"], vec![]]);
}

#[test]
fn interfaces_wider_than_an_environment_value_do_not_fit() {
    // 33 services each delaying `sink`: `sink`'s part reads all of them.
    let mut body: String = (0..33)
        .map(|i| svc(&format!("u{i}"), "delays: sink;"))
        .collect();
    body.push_str(&svc("sink", ""));
    let c = resolved(&body);
    let all: Vec<ServiceId> = c.services.ids().collect();
    let plan = Plan::new(&c, &all);
    assert_eq!(plan.parts.len(), 34);
    assert!(!plan.fits());
    let fewer = resolved(&[svc("u0", "delays: sink;"), svc("sink", "")].concat());
    let all: Vec<ServiceId> = fewer.services.ids().collect();
    assert!(Plan::new(&fewer, &all).fits());
}

#[test]
fn a_stop_cycle_is_one_part() {
    let c = component(&[svc("x", "stops: y;"), svc("y", "delays: x;")].concat());
    let all: Vec<ServiceId> = c.services.ids().collect();
    assert_eq!(names(&c, &parts(&c, &all)), [vec!["x", "y"]]);
}

#[test]
fn silent_steps_vanish_and_equivalent_states_merge() {
    // 0 -(0)-> 1 -(0)-> 2 -(1)-> 3 -(0)-> 4; 4 -(1)-> 5; 2 -(2)-> 6.
    let values = [0, 0, 0, 1, 0, 1, 2];
    let succ: Vec<Vec<StateId>> = vec![
        vec![1],
        vec![2],
        vec![3, 6],
        vec![4],
        vec![5],
        vec![],
        vec![],
    ];
    let (value, next) = determinize(&values, &succ, 100).expect("small");
    // {0,1,2} -1-> {3} -0-> {4} -1-> {5}; {0,1,2} -2-> {6}.
    assert_eq!(value, [0, 1, 2, 0, 1]);
    assert_eq!(next[0].len(), 2);
    let (value, next) = minimize(&value, &next);
    // {5} and {6} have no successors but different values; {3} and {5}
    // differ by their successors: nothing merges.
    assert_eq!(value.len(), 5);
    assert!(
        next.iter()
            .all(|s| s.iter().all(|&q| (q as usize) < value.len()))
    );
    // Two identical branches merge.
    let (value, next) = minimize(&[0, 1, 1], &[vec![1, 2], vec![], vec![]]);
    assert_eq!(value, [0, 1]);
    assert_eq!(next, [vec![1], vec![]]);
}

#[test]
fn determinization_gives_up_past_its_bound() {
    let values = [0, 1, 2, 3];
    let succ: Vec<Vec<StateId>> = vec![vec![1, 2, 3], vec![], vec![], vec![]];
    assert!(determinize(&values, &succ, 2).is_none());
}

#[test]
fn the_environment_shows_what_upstream_does() {
    let c = chain();
    let b = Behaviour::new(&c);
    let all: Vec<ServiceId> = c.services.ids().collect();
    let parts = parts(&c, &all);
    let env = Env::empty();
    let sys = System::with_inputs(&c, &b, &parts[0], &[], false);
    let model = Composed::new(sys, &env).expect("no inputs");
    let e = explore(&model, Limits::default(), |_, _| {});
    let up = project(&model, &e, &parts[0], 100).expect("small");
    // `a` idle, then with an instance that may loop forever, then idle
    // again: two values, each reachable from the other.
    assert_eq!(up.value[up.init as usize], 0);
    assert_eq!(up.len(), 2);
    let other = up.succ[0][0] as usize;
    assert_eq!(up.value[other], 0b11);
    assert_eq!(up.succ[other], [up.init]);
    // `b` explored with that environment: `a`'s instance delays it.
    let inputs = inputs(&c, &all, &parts[1]);
    let sys = System::with_inputs(&c, &b, &parts[1], &inputs, false);
    let model = Composed::new(sys, &up).expect("`a` is in the layout");
    let mut delayed = false;
    let e = explore(&model, Limits::default(), |_, (cfg, _)| {
        let i = model.sys.member_index(parts[1][0]).expect("member");
        delayed |= cfg.pending[i].is_some() && cfg.main[i] == genom_model::behaviour::IDLE;
    });
    assert!(e.stopped.is_none());
    assert!(delayed, "`b` waits while `a` has an instance");
}
