//! The symbolic sets against the explicit explorer on small models: the
//! same states, each visited once, shortest paths that lead to them.

use std::collections::BTreeSet;

use super::*;
use crate::kernel::explore::{Limits, explore};

/// Three counters, modulo `m0`, `m1` and `m2`, each action adding one to
/// one of them, or (action 3) swapping the first two when both are below
/// `m0`; packed in 4 bits each, in one word (or, `wide`, one word each).
struct Counters {
    m: [u64; 3],
    wide: bool,
}

impl Model for Counters {
    type State = [u64; 3];
    type Action = u8;
    type Zone = ();
    fn width(&self) -> usize {
        if self.wide { 3 } else { 1 }
    }
    fn bits(&self) -> usize {
        if self.wide { 64 * 2 + 4 } else { 12 }
    }
    fn init_states(&self) -> Vec<[u64; 3]> {
        vec![[0, 0, 0]]
    }
    fn actions(&self, _: &[u64; 3], out: &mut Vec<u8>) {
        out.extend([0, 1, 2, 3]);
    }
    fn next_state(&self, s: &[u64; 3], a: u8) -> Option<[u64; 3]> {
        let mut n = *s;
        match a {
            3 if s[0] < self.m[0] && s[1] < self.m[0] => n.swap(0, 1),
            3 => return None,
            k => {
                let k = usize::from(k);
                n[k] = (n[k] + 1) % self.m[k];
            }
        }
        (n != *s).then_some(n)
    }
    fn encode(&self, s: &[u64; 3], out: &mut Vec<u64>) {
        if self.wide {
            out.extend(s);
        } else {
            out.push(s[0] | s[1] << 4 | s[2] << 8);
        }
    }
    fn decode(&self, w: &[u64], (): &()) -> [u64; 3] {
        if self.wide {
            [w[0], w[1], w[2]]
        } else {
            [w[0] & 15, (w[0] >> 4) & 15, (w[0] >> 8) & 15]
        }
    }
    fn zone(&self, _: &[u64; 3]) {}
}

fn replay(m: &Counters, path: &[u8]) -> [u64; 3] {
    path.iter()
        .fold([0, 0, 0], |s, &a| m.next_state(&s, a).unwrap())
}

#[test]
fn the_sets_reach_the_explicit_states_each_visited_once() {
    for (m, wide) in [([3, 4, 5], false), ([2, 7, 3], true), ([1, 1, 1], false)] {
        let model = Counters { m, wide };
        let mut explicit = BTreeSet::new();
        let e = explore(&model, Limits::default(), |_, s| {
            explicit.insert(*s);
        });
        let mut seen = Vec::new();
        let s = explore_sets_until(&model, SetLimits::default(), |id, st| {
            seen.push((id, *st));
            Found::Open
        });
        assert!(s.stopped.is_none() && e.stopped.is_none());
        let visited: BTreeSet<[u64; 3]> = seen.iter().map(|&(_, st)| st).collect();
        assert_eq!(visited, explicit, "{m:?}");
        assert_eq!(seen.len(), explicit.len(), "each state visited once");
        assert_eq!(s.states, explicit.len() as u64);
        assert_eq!(s.visited, explicit.len() as u64);
        assert_eq!(s.transitions, e.transitions, "the same transitions fired");
        let ids: Vec<StateId> = seen.iter().map(|&(id, _)| id).collect();
        assert_eq!(ids, (0..seen.len() as StateId).collect::<Vec<_>>());
    }
}

#[test]
fn paths_are_shortest_and_lead_to_their_state() {
    let model = Counters {
        m: [3, 4, 5],
        wide: false,
    };
    let mut explicit = Vec::new();
    let e = explore(&model, Limits::default(), |id, st| explicit.push((id, *st)));
    let mut seen = Vec::new();
    let s = explore_sets_until(&model, SetLimits::default(), |id, st| {
        seen.push((id, *st));
        Found::Open
    });
    for &(id, st) in &seen {
        let path = s.path(&model, id);
        assert_eq!(replay(&model, &path), st, "state {id}");
        assert_eq!(s.state(&model, id), Some(st));
        let (eid, _) = explicit.iter().find(|&&(_, x)| x == st).unwrap();
        assert_eq!(path.len(), e.path(&model, *eid).len(), "shortest to {st:?}");
    }
    // Layers are visited in order of distance.
    let lengths: Vec<usize> = seen
        .iter()
        .map(|&(id, _)| s.path(&model, id).len())
        .collect();
    assert!(lengths.windows(2).all(|w| w[0] <= w[1]));
    assert_eq!(s.depth(), lengths.last().unwrap() + 1);
}

#[test]
fn a_visit_that_found_everything_stops_early_and_complete() {
    let model = Counters {
        m: [3, 4, 5],
        wide: false,
    };
    let mut visits = 0;
    let s = explore_sets_until(&model, SetLimits::default(), |_, st| {
        visits += 1;
        if *st == [1, 1, 0] {
            Found::All
        } else {
            Found::Open
        }
    });
    assert!(s.stopped.is_none());
    assert!(visits < 60 && s.visited == visits);
}

#[test]
fn limits_stop_the_exploration_and_say_so() {
    let model = Counters {
        m: [9, 9, 9],
        wide: true,
    };
    let past = SetLimits {
        deadline: Some(Instant::now()),
        ..SetLimits::default()
    };
    let s = explore_sets_until(&model, past, |_, _| Found::Open);
    assert_eq!(s.stopped, Some(Stop::Time));
    assert!(s.visited < 9 * 9 * 9);
    let few_nodes = SetLimits {
        max_nodes: 5,
        ..SetLimits::default()
    };
    let s = explore_sets_until(&model, few_nodes, |_, _| Found::Open);
    assert_eq!(s.stopped, Some(Stop::Memory));
}

#[test]
fn a_built_set_holds_exactly_its_keys() {
    let mut keys = build::Keys::new(2, 70);
    let states: Vec<[u64; 2]> = vec![[5, 1], [0, 0], [u64::MAX, 63], [5, 1], [1 << 40, 2]];
    for s in &states {
        keys.push(s);
    }
    let set = keys.take_bdd();
    assert_eq!(count(&set), 4);
    let mut got: Vec<[u64; 2]> = set
        .sat_valuations()
        .map(|v| {
            let mut w = Vec::new();
            unpack(&v, 2, &mut w);
            [w[0], w[1]]
        })
        .collect();
    got.sort_unstable();
    let mut want = states.clone();
    want.sort_unstable();
    want.dedup();
    assert_eq!(got, want);
    assert!(keys.take_bdd().is_false(), "the batch is emptied");
}
