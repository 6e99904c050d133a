//! A static bound on a periodic task's wake-up (docs/genom3-semantics.md
//! 15.12): when the longest work a tick can give the task, each of its
//! codels delayed by the longest wait GenoM3's resource FIFO allows, ends
//! before the next tick, the task cannot overrun, and the timed
//! exploration has nothing to look for in it.
//!
//! The bound holds in the runs the exploration keeps: a `thread-overrun`
//! ends a run, so while task T's wake-up lasts, every other periodic task
//! of its group finishes each wake-up's work before its next tick.
//!
//! - **Share of a thread.** A codel that cannot begin at once takes a
//!   ticket. From then on no codel begins before it but those already
//!   running or queued ahead (a thread that wants to begin one later
//!   queues behind it), and until it begins some *contended* codel among
//!   those runs (the queue's head waits for locks that a running codel
//!   holds, and a codel holding a lock someone waits for is contended).
//!   Each other thread has at most one of them (it runs one codel, or
//!   holds one ticket), which runs at most its WCET and, for a periodic
//!   task of the group, ends before that task's next tick: at most one
//!   period from now.
//! - **Wait of a codel.** At most the sum of the other threads' shares.
//!   Or, split at the instant the codel reaches the head of the queue:
//!   before, the last thread queued ahead of it is still to begin (a
//!   periodic task within its period, another thread within its own
//!   wait); after, no codel begins but `async` ones (no lock), so it waits
//!   only for the running codels it conflicts with, one per thread. The
//!   smaller of the two.
//! - **Work.** In one wake-up every instance of the task runs a chain of
//!   codels joined without `pause::` (an interrupted one goes on with its
//!   `stop` path), from whatever state it is in: per state machine, the
//!   longest such chain, each codel its WCET plus its wait; times the
//!   instances an activity may have at once. Activities that all
//!   interrupt each other and themselves run one instance among them per
//!   wake-up (a new one waits until the interrupted one ended, and starts
//!   only at a tick): the longest of their chains. A chain through a
//!   cycle, or through an `async` codel (no upper bound), has no bound.
//!
//! The sum must be shorter than the period: a codel ending at the very
//! instant of the tick may be found unfinished. (A periodic task runs
//! nothing before its first tick, at `delay`: its wake-ups are the
//! periods that follow its ticks.)

use std::collections::BTreeSet;

use genom_model::graph::heaviest_path;

use super::TimedEngine;
use super::locks::Locks;
use super::overrun::{Cause, longer_than_period};
use crate::genom3::machine::{Machine, Owner, Target};

/// Per task: whether the static bound shows that it cannot overrun.
pub fn cannot_overrun(te: &TimedEngine<'_>) -> Vec<bool> {
    wake_up_bounds(te)
        .iter()
        .zip(&te.period)
        .map(|(work, period)| matches!((work, period), (Some(w), Some(p)) if w < p))
        .collect()
}

/// Per task: the static bound on one wake-up's work, in model units
/// (`None`: unbounded, or not a periodic task of the group). Below the
/// period, the task cannot overrun.
pub fn wake_up_bounds(te: &TimedEngine<'_>) -> Vec<Option<i64>> {
    let waits = Waits::new(te);
    (0..te.m().tasks.len())
        .map(|t| {
            te.period[t]?;
            if !te.in_group[t] {
                return None;
            }
            wake_up_work(te, t, |k| waits.of(t, k), &|_, _| false)
        })
        .collect()
}

/// Per task: the causes an overrun of it can show (empty for a task that
/// is not a periodic task of the group; docs/genom3-semantics.md 15.14).
/// A [`Cause::LongCodel`] for each of its codels longer than its period;
/// the others unless the bound of a wake-up in which none of those begins
/// rules them out: [`Cause::LockWait`] unless that bound is shorter than
/// the period or no codel waits for another, [`Cause::Chain`] and [`Cause::Shared`] unless the same
/// bound without waits is (a codel that waits takes a ticket, which makes
/// the cause a lock wait), and [`Cause::Chain`] only for a task with a
/// codel joined to another without `pause::`.
pub fn possible_causes(te: &TimedEngine<'_>) -> Vec<BTreeSet<Cause>> {
    let waits = Waits::new(te);
    let m = te.m();
    // Without a codel that waits for another, no one takes a ticket.
    let tickets = (0..te.locks.len()).any(|k| !te.locks.waits_for(k).is_empty());
    (0..m.tasks.len())
        .map(|t| {
            let mut out = BTreeSet::new();
            let Some(period) = te.period[t].filter(|_| te.in_group[t]) else {
                return out;
            };
            let long_cause =
                |o: Owner, s: usize| longer_than_period(m, t, o, u8::try_from(s).ok()?);
            let long = |o: Owner, s: usize| long_cause(o, s).is_some();
            let owners = task_owners(te, t);
            out.extend(
                owners.iter().flat_map(|&o| {
                    (0..m.fsm(o).states.len()).filter_map(move |s| long_cause(o, s))
                }),
            );
            let fits = |work: Option<i64>| work.is_some_and(|w| w < period);
            if fits(wake_up_work(te, t, |k| waits.of(t, k), &long)) {
                return out;
            }
            if tickets {
                out.insert(Cause::LockWait);
            }
            if fits(wake_up_work(te, t, |_| 0, &long)) {
                return out;
            }
            out.insert(Cause::Shared);
            let unpaused = |o: Owner| {
                m.fsm(o).states.iter().enumerate().any(|(s, st)| {
                    !long(o, s)
                        && st
                            .yields
                            .iter()
                            .any(|y| matches!(y, Target::State { pause: false, .. }))
                })
            };
            if owners.iter().any(|&o| unpaused(o)) {
                out.insert(Cause::Chain);
            }
            out
        })
        .collect()
}

/// The state machines task `t` runs: its permanent activity's, then its
/// activities'.
fn task_owners(te: &TimedEngine<'_>, t: usize) -> Vec<Owner> {
    let perm = te.m().tasks[t].perm.as_ref().map(|_| Owner::Task(t));
    let acts = te.acts_of[t].iter().map(|&a| Owner::Activity(a));
    perm.into_iter().chain(acts).collect()
}

/// What the other threads can make a codel wait (see the module doc).
struct Waits<'l> {
    locks: &'l Locks,
    /// Per thread (the tasks, then the control thread): the most one of
    /// its codels, running or queued, can hold up another's, in units.
    share: Vec<i64>,
    /// Per thread: the most its period lets one of its codels last from
    /// now on (`i64::MAX` for a thread without one in the group).
    cap: Vec<i64>,
    /// Per thread: the longest it can take to begin a codel it queued for.
    begin: Vec<i64>,
}

impl<'l> Waits<'l> {
    fn new(te: &'l TimedEngine<'_>) -> Waits<'l> {
        let m = te.m();
        let n = m.tasks.len();
        let cap: Vec<i64> = (0..=n)
            .map(|u| match te.period.get(u) {
                Some(&Some(p)) if te.in_group[u] => p,
                _ => i64::MAX,
            })
            .collect();
        let share: Vec<i64> = longest_contended(m, &te.locks)
            .iter()
            .zip(&cap)
            .map(|(&w, &c)| w.min(c))
            .collect();
        let begin = (0..=n).map(|u| cap[u].min(sum_but(&share, u))).collect();
        Waits {
            locks: &te.locks,
            share,
            cap,
            begin,
        }
    }

    /// The longest wait of codel `k` of task `t` for its locks.
    fn of(&self, t: usize, k: usize) -> i64 {
        let all = sum_but(&self.share, t);
        let ahead = (0..self.begin.len())
            .filter(|&u| u != t)
            .map(|u| self.begin[u])
            .max()
            .unwrap_or(0);
        let n = self.share.len() - 1;
        let mut conflicting = vec![0i64; self.share.len()];
        for &j in self.locks.waits_for(k) {
            let u = self.locks.key_task[j].min(n);
            let w = self.locks.wcet_of(j).unwrap_or(0).min(self.cap[u]);
            conflicting[u] = conflicting[u].max(w);
        }
        let at_head = sum_but(&conflicting, t);
        all.min(ahead.saturating_add(at_head))
    }
}

/// The sum of `v` but its `skip`-th entry (saturating).
fn sum_but(v: &[i64], skip: usize) -> i64 {
    v.iter()
        .enumerate()
        .filter(|&(u, _)| u != skip)
        .fold(0i64, |a, (_, &w)| a.saturating_add(w))
}

/// Per thread (the tasks, then the control thread last): its longest
/// contended codel, in units (0 without one).
pub(super) fn longest_contended(m: &Machine<'_>, locks: &Locks) -> Vec<i64> {
    let mut out = vec![0i64; m.tasks.len() + 1];
    for k in (0..locks.len()).filter(|&k| locks.contended(k)) {
        let thread = locks.key_task[k].min(m.tasks.len());
        // An `async` codel holds no lock and makes no one wait.
        if let Some(w) = locks.wcet_of(k) {
            out[thread] = out[thread].max(w);
        }
    }
    out
}

/// The longest work of one wake-up of task `t`, its codel of key `k`
/// waiting at most `wait(k)`, in a wake-up where no codel `skip` names
/// (owner, state) begins; `None` when unbounded.
fn wake_up_work(
    te: &TimedEngine<'_>,
    t: usize,
    wait: impl Fn(usize) -> i64,
    skip: &dyn Fn(Owner, usize) -> bool,
) -> Option<i64> {
    let m = te.m();
    let chain = |o: Owner| longest_chain(te, o, &wait, &|s| skip(o, s));
    let mut total = match m.tasks[t].perm {
        Some(_) => chain(Owner::Task(t))?,
        None => 0,
    };
    for class in exclusive_classes(m, &te.acts_of[t]) {
        let work = match class.as_slice() {
            [a] if !m.interrupts_itself(*a) => {
                let copies = i64::try_from(m.instance_bound(*a)).ok()?;
                chain(Owner::Activity(*a))?.checked_mul(copies)?
            }
            _ => class
                .iter()
                .map(|&a| chain(Owner::Activity(a)))
                .try_fold(0i64, |acc, w| Some(acc.max(w?)))?,
        };
        total = total.checked_add(work)?;
    }
    Some(total)
}

/// `acts` split into classes of activities that each interrupt
/// themselves and one another (one instance among a class runs in a
/// wake-up), an activity that interrupts nothing of the kind alone.
fn exclusive_classes(m: &Machine<'_>, acts: &[usize]) -> Vec<Vec<usize>> {
    let both = |a: usize, b: usize| {
        m.activities[a].interrupts.contains(&b) && m.activities[b].interrupts.contains(&a)
    };
    let mut classes: Vec<Vec<usize>> = Vec::new();
    for &a in acts {
        let home = classes
            .iter_mut()
            .find(|c| m.interrupts_itself(a) && c.iter().all(|&b| both(a, b) && both(b, b)));
        match home {
            Some(c) => c.push(a),
            None => classes.push(vec![a]),
        }
    }
    classes
}

/// The longest chain of codels of `owner`'s state machine one wake-up can
/// run, from any state, codel of key `k` waiting `wait(k)`; a codel of a
/// state `skip` names does not begin (the chain may end waiting for it);
/// `None` through a cycle or an `async` codel.
fn longest_chain(
    te: &TimedEngine<'_>,
    owner: Owner,
    wait: &impl Fn(usize) -> i64,
    skip: &dyn Fn(usize) -> bool,
) -> Option<i64> {
    let fsm = te.m().fsm(owner);
    let n = fsm.states.len();
    let normal = before_stop(fsm);
    let next = |s: usize| {
        // A skipped codel does not begin: the chain ends waiting for it.
        let ends = skip(s);
        let yields = fsm.states[s]
            .yields
            .iter()
            .filter(move |_| !ends)
            .filter_map(|y| match *y {
                Target::State {
                    state,
                    pause: false,
                } => Some(usize::from(state)),
                _ => None,
            });
        // Interrupted (or, for a permanent activity, shut down), an
        // instance not yet on its stop path goes to `stop` after this codel.
        let stop = fsm.stop.map(usize::from).filter(|_| normal[s] && !ends);
        yields.chain(stop)
    };
    let cost = |k: usize| {
        let state = u8::try_from(k).ok()?;
        let delay = wait(te.locks.key(owner, state));
        let w = if skip(k) {
            0
        } else {
            te.locks.wcet(owner, state)?
        };
        u64::try_from(w.checked_add(delay)?).ok()
    };
    i64::try_from(heaviest_path(n, 0..n, next, cost)?).ok()
}

/// Per state of `fsm`: whether an instance can be there before its stop
/// path (reached from `start` without going through `stop`; every state
/// when there is no `start`).
fn before_stop(fsm: &crate::genom3::machine::Fsm) -> Vec<bool> {
    let n = fsm.states.len();
    let Some(start) = fsm.start else {
        return vec![true; n];
    };
    let stop = fsm.stop.map(usize::from);
    let mut seen = vec![false; n];
    let mut todo = vec![usize::from(start)];
    while let Some(s) = todo.pop() {
        if seen[s] || Some(s) == stop {
            continue;
        }
        seen[s] = true;
        todo.extend(fsm.states[s].yields.iter().filter_map(|y| match *y {
            Target::State { state, .. } => Some(usize::from(state)),
            Target::Ether => None,
        }));
    }
    seen
}
