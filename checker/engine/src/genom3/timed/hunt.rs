//! Looking for the overruns a stopped exploration did not reach
//! (docs/genom3-semantics.md 15.13). When a group's exploration stops at a
//! limit with a periodic task neither cleared by the static bound nor
//! found overrunning, the group is explored again for a client that sends
//! requests of one or two services only: the empty client first, then one
//! service at a time, then pairs (an activity of a task looked for with
//! one other service). Every run of such a client is a run of the
//! component (a client may leave any service unrequested), so an overrun
//! found there is real, with a trace that replays; the search proves
//! nothing else, and the group stays unfinished. Its explorations are
//! small: each within a tenth of the state limit, all within the limit.

use std::collections::{BTreeMap, BTreeSet};
use std::time::Instant;

use super::groups::Group;
use super::locks::Locks;
use super::overrun::{Cause, TaskOverrun, Violations};
use super::{TG3State, TimedEngine};
use crate::genom3::machine::Machine;
use crate::kernel::explore::{Found, Limits, explore_until};

/// What the search found and spent.
#[derive(Debug, Default)]
pub struct Hunted {
    /// The first overrun found for each (task, cause) looked for.
    pub overruns: Vec<TaskOverrun>,
    /// States stored, over all its explorations.
    pub states: u64,
    /// Transitions fired.
    pub transitions: u64,
}

/// The causes looked for, per periodic task of the group.
pub type Wanted = BTreeMap<usize, BTreeSet<Cause>>;

/// Violations of a task examined for their cause in one exploration, at
/// most (the first ones, breadth-first).
const EXAMINED: usize = 64;

/// A service a restricted client may request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Service {
    Activity(usize),
    Control(usize),
}

/// Looks for an overrun of each task of `wanted` with each of its causes
/// (periodic tasks of `group`) with restricted clients, within `limits`:
/// each exploration within `each` states, all of them within
/// `limits.max_states`.
pub fn hunt(
    m: &Machine<'_>,
    group: &Group,
    locks: &Locks,
    wanted: &Wanted,
    limits: Limits,
    each: usize,
) -> Hunted {
    let mut left = wanted.clone();
    left.retain(|_, c| !c.is_empty());
    let mut out = Hunted::default();
    let tasks: BTreeSet<usize> = left.keys().copied().collect();
    for client in clients(m, group, &tasks) {
        let spent = usize::try_from(out.states).unwrap_or(usize::MAX);
        let late = limits.deadline.is_some_and(|d| Instant::now() >= d);
        if left.is_empty() || spent >= limits.max_states || late {
            break;
        }
        let sub = restricted(group, &client);
        let Some(mut te) = TimedEngine::with_locks(m.clone(), &sub, locks.clone()) else {
            continue;
        };
        te.dominate_calls();
        let budget = Limits {
            max_states: each.max(1).min(limits.max_states - spent),
            ..limits
        };
        for o in explore_for(&te, budget, &left, &mut out) {
            if let Some(c) = left.get_mut(&o.task) {
                c.remove(&o.cause);
            }
            out.overruns.push(o);
        }
        left.retain(|_, c| !c.is_empty());
    }
    out
}

/// Explores `te` until each (task, cause) of `left` has shown an overrun,
/// or the limits, or each task with causes other than a long codel left
/// has shown [`EXAMINED`] violations; returns the first overrun of each
/// (task, cause) of `left` found, breadth-first.
fn explore_for(
    te: &TimedEngine<'_>,
    limits: Limits,
    left: &Wanted,
    out: &mut Hunted,
) -> Vec<TaskOverrun> {
    let mut seen = Violations::new(EXAMINED);
    let e = explore_until(te, limits, |id, st: &TG3State| {
        let wanted = st
            .violation
            .is_some_and(|t| left.contains_key(&usize::from(t)));
        if wanted && seen.see(te, id, st).is_some() && all_seen(left, &seen) {
            Found::All
        } else {
            Found::Open
        }
    });
    out.states += e.store.len() as u64;
    out.transitions += e.transitions;
    let keep = |t: usize, c: Cause| left.get(&t).is_some_and(|w| w.contains(&c));
    seen.first(te, &e, keep).into_values().collect()
}

/// Whether each (task, cause) of `left` has shown an overrun (a long
/// codel) or could be among the violations `seen` examines (the others).
fn all_seen(left: &Wanted, seen: &Violations) -> bool {
    left.iter().all(|(&t, causes)| {
        causes.iter().all(|&c| match c {
            Cause::LongCodel(..) => seen.has_long(t, c),
            _ => seen.examined_all(t),
        })
    })
}

/// The restricted clients, in the order they are tried: no request, each
/// service alone, then each activity of a task of `wanted` with each
/// other service (every pair when no such activity exists).
fn clients(m: &Machine<'_>, group: &Group, wanted: &BTreeSet<usize>) -> Vec<Vec<Service>> {
    let acts = (0..group.acts.len())
        .filter(|&a| group.acts[a] && !m.is_builtin(m.activities[a].service))
        .map(Service::Activity);
    let ctls = (0..group.ctls.len())
        .filter(|&k| group.ctls[k] && !m.controls[k].builtin)
        .map(Service::Control);
    let all: Vec<Service> = acts.chain(ctls).collect();
    let key = |s: &Service| match *s {
        Service::Activity(a) => wanted.contains(&m.activities[a].task),
        Service::Control(_) => false,
    };
    let mut out: Vec<Vec<Service>> = vec![Vec::new()];
    out.extend(all.iter().map(|&s| vec![s]));
    let any_key = all.iter().any(key);
    for (i, &s) in all.iter().enumerate() {
        for &r in &all[i + 1..] {
            if !any_key || key(&s) || key(&r) {
                out.push(vec![s, r]);
            }
        }
    }
    out
}

/// `group` with only `client`'s services requested.
fn restricted(group: &Group, client: &[Service]) -> Group {
    let mut g = Group {
        tasks: group.tasks.clone(),
        acts: vec![false; group.acts.len()],
        ctls: vec![false; group.ctls.len()],
    };
    for s in client {
        match *s {
            Service::Activity(a) => g.acts[a] = true,
            Service::Control(k) => g.ctls[k] = true,
        }
    }
    g
}
