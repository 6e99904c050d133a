//! Witness traces: a path replayed in the whole component from its start
//! with every event, and a service's local codel loop (the cycle a
//! starvation or unbounded-interrupt trace repeats).

use std::collections::{BTreeMap, BTreeSet};

use genom_model::behaviour::{Effect, PosId};
use genom_model::component::ServiceId;
use genom_model::trace::{Event, Trace, TraceStep};

use super::system::{Action, Config, System};

/// Replays `path` in the whole component from its start, recording every
/// event; with `looping`, appends that service's codel loop as the cycle
/// that may repeat forever.
pub(crate) fn replay(
    global: &System<'_>,
    path: &[Action],
    looping: Option<ServiceId>,
    last: TraceStep,
) -> Trace {
    let mut steps = vec![TraceStep::new(
        Event::ComponentStart,
        "the component starts",
    )];
    let mut cfg = global.initial(false, &mut Some(&mut steps));
    for &a in path {
        match global.apply(&cfg, a, &mut Some(&mut steps)) {
            Some(next) => cfg = next,
            None => break,
        }
    }
    let mut loop_start = None;
    if let Some(s) = looping.and_then(|s| global.member_index(s).map(|i| (s, i))) {
        let (mut before, mut cycle) = local_loop(global, &cfg, s.1);
        if !applicable(global, &cfg, before.iter().chain(&cycle)) {
            // Another service's codel holds the thread or a lock the loop
            // needs: let the running codels finish first.
            settle(global, &mut cfg, s.1, &mut steps);
            (before, cycle) = local_loop(global, &cfg, s.1);
        }
        for a in before {
            if let Some(next) = global.apply(&cfg, a, &mut Some(&mut steps)) {
                cfg = next;
            }
        }
        let at = steps.len();
        let mut ok = !cycle.is_empty();
        for a in cycle {
            match global.apply(&cfg, a, &mut Some(&mut steps)) {
                Some(next) => cfg = next,
                None => ok = false,
            }
        }
        if ok {
            loop_start = Some(at);
        }
    }
    steps.push(last);
    Trace { steps, loop_start }
}

/// Whether `actions` can be applied one after the other from `cfg`.
fn applicable<'a>(
    sys: &System<'_>,
    cfg: &Config,
    actions: impl Iterator<Item = &'a Action>,
) -> bool {
    let mut cur = cfg.clone();
    for &a in actions {
        match sys.apply(&cur, a, &mut None) {
            Some(next) => cur = next,
            None => return false,
        }
    }
    true
}

/// Finishes the codel every member but `keep` is running, each the first
/// way that leads to another codel (else its first way), recording the
/// steps: what a starving service waits for only needs its blocker to go
/// on looping, which the others' running codels may prevent.
fn settle(sys: &System<'_>, cfg: &mut Config, keep: usize, steps: &mut Vec<TraceStep>) {
    for j in (0..sys.len()).filter(|&j| j != keep) {
        if !sys.position(cfg, j).is_running() {
            continue;
        }
        let ways = &sys.machine_of(j).finish[usize::from(cfg.main[j])];
        let k = ways
            .iter()
            .position(|f| matches!(f.effect, Effect::Goto(_)))
            .unwrap_or(0);
        let action = Action::Finish(sys.service(j), u8::try_from(k).unwrap_or(0));
        if let Some(next) = sys.apply(cfg, action, &mut Some(steps)) {
            *cfg = next;
        }
    }
}

/// A path of codel steps of member `i` from its position to a position on a
/// cycle, and the cycle itself (empty when there is none).
pub(crate) fn local_loop(sys: &System<'_>, cfg: &Config, i: usize) -> (Vec<Action>, Vec<Action>) {
    let start = cfg.main[i];
    let mut seen = vec![start];
    let mut k = 0;
    while k < seen.len() {
        let p = seen[k];
        k += 1;
        if let Some(cycle) = local_path(sys, i, p, p) {
            let before = local_path(sys, i, start, p)
                .filter(|_| p != start)
                .unwrap_or_default();
            return (before, cycle);
        }
        for (_, q) in local_steps(sys, i, p) {
            if !seen.contains(&q) {
                seen.push(q);
            }
        }
    }
    (Vec::new(), Vec::new())
}

/// The codel steps of member `i` from position `p`.
fn local_steps(sys: &System<'_>, i: usize, p: PosId) -> Vec<(Action, PosId)> {
    let m = sys.machine_of(i);
    let s = sys.service(i);
    let mut v = Vec::new();
    if let Some(q) = m.begin[usize::from(p)] {
        v.push((Action::Begin(s), q));
    }
    for (k, f) in m.finish[usize::from(p)].iter().enumerate() {
        if let (Effect::Goto(q), Ok(k)) = (f.effect, u8::try_from(k)) {
            v.push((Action::Finish(s, k), q));
        }
    }
    v
}

/// The shortest non-empty path of codel steps from `from` to `to`.
fn local_path(sys: &System<'_>, i: usize, from: PosId, to: PosId) -> Option<Vec<Action>> {
    let mut prev: BTreeMap<PosId, (PosId, Action)> = BTreeMap::new();
    let mut queue = std::collections::VecDeque::from([from]);
    let mut visited = BTreeSet::from([from]);
    while let Some(p) = queue.pop_front() {
        for (a, q) in local_steps(sys, i, p) {
            if q == to {
                let mut acts = vec![a];
                let mut cur = p;
                while cur != from {
                    let &(back, act) = prev.get(&cur)?;
                    acts.push(act);
                    cur = back;
                }
                acts.reverse();
                return Some(acts);
            }
            if visited.insert(q) {
                prev.insert(q, (p, a));
                queue.push_back(q);
            }
        }
    }
    None
}
