//! A static bound on a periodic task's wake-up (docs/genom3-semantics.md
//! 15.12): when the longest work a tick can give the task, each of its
//! codels delayed by the longest wait GenoM3's resource FIFO allows, ends
//! before the next tick, the task cannot overrun, and the timed
//! exploration has nothing to look for in it.
//!
//! - **Wait.** A codel that cannot begin at once takes a ticket. From then
//!   on no codel begins before it but those already running or queued
//!   ahead (a thread that wants to begin one later queues behind it), and
//!   until it begins some *contended* codel among those runs (the queue's
//!   head waits for locks that a running codel holds, and a codel holding
//!   a lock someone waits for is contended). Each other thread has at
//!   most one of them (it runs one codel, or holds one ticket), so the
//!   wait is at most the sum over the other threads (tasks and the control
//!   thread) of their longest contended codel.
//! - **Work.** In one wake-up every instance of the task runs a chain of
//!   codels joined without `pause::` (an interrupted one goes on with its
//!   `stop` path), from whatever state it is in: per state machine, the
//!   longest such chain, each codel its WCET plus the wait; times the
//!   instances an activity may have at once. A chain through a cycle, or
//!   through an `async` codel (no upper bound), has no bound.
//!
//! The sum must be shorter than the period: a codel ending at the very
//! instant of the tick may be found unfinished. (A periodic task runs
//! nothing before its first tick, at `delay`: its wake-ups are the
//! periods that follow its ticks.)

use genom_model::graph::heaviest_path;

use super::TimedEngine;
use super::locks::Locks;
use crate::genom3::machine::{Machine, Owner, Target};

/// Per task: whether the static bound shows that it cannot overrun.
pub fn cannot_overrun(te: &TimedEngine<'_>) -> Vec<bool> {
    let m = te.m();
    let wait = longest_contended(m, &te.locks);
    (0..m.tasks.len())
        .map(|t| {
            let Some(period) = te.period[t] else {
                return false;
            };
            let others: i64 = wait
                .iter()
                .enumerate()
                .filter(|&(u, _)| u != t)
                .map(|(_, w)| w)
                .sum();
            let Some(work) = wake_up_work(te, t, others) else {
                return false;
            };
            work < period
        })
        .collect()
}

/// Per thread (the tasks, then the control thread last): its longest
/// contended codel, in units (0 without one).
fn longest_contended(m: &Machine<'_>, locks: &Locks) -> Vec<i64> {
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

/// The longest work of one wake-up of task `t`, each codel waiting at
/// most `wait`; `None` when unbounded.
fn wake_up_work(te: &TimedEngine<'_>, t: usize, wait: i64) -> Option<i64> {
    let m = te.m();
    let perm = m.tasks[t].perm.as_ref().map(|_| (Owner::Task(t), 1));
    let acts = te.acts_of[t]
        .iter()
        .map(|&a| (Owner::Activity(a), m.instance_bound(a)));
    let mut total = 0i64;
    for (owner, copies) in perm.into_iter().chain(acts) {
        let chain = longest_chain(te, owner, wait)?;
        total = total.checked_add(chain.checked_mul(i64::try_from(copies).ok()?)?)?;
    }
    Some(total)
}

/// The longest chain of codels of `owner`'s state machine one wake-up can
/// run, from any state; `None` through a cycle or an `async` codel.
fn longest_chain(te: &TimedEngine<'_>, owner: Owner, wait: i64) -> Option<i64> {
    let fsm = te.m().fsm(owner);
    let n = fsm.states.len();
    let normal = before_stop(fsm);
    let next = |s: usize| {
        let yields = fsm.states[s].yields.iter().filter_map(|y| match *y {
            Target::State {
                state,
                pause: false,
            } => Some(usize::from(state)),
            _ => None,
        });
        // Interrupted (or, for a permanent activity, shut down), an
        // instance not yet on its stop path goes to `stop` after this codel.
        let stop = fsm.stop.map(usize::from).filter(|_| normal[s]);
        yields.chain(stop)
    };
    let wait = u64::try_from(wait).ok()?;
    let cost = |k: usize| {
        let w = te.locks.wcet(owner, u8::try_from(k).ok()?)?;
        u64::try_from(w).ok()?.checked_add(wait)
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
