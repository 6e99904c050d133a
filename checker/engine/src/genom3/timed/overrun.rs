//! What an overrun of the timed GenoM3 model is, once found: its cause
//! read off the path to it (docs/genom3-semantics.md 15.9, "Causes of an
//! overrun"), the sentence that closes its trace, and the trace itself
//! with the threads that play no part set aside. Shared by the whole
//! exploration ([`super::analysis`]) and the search with restricted
//! clients ([`super::hunt`]).

use std::collections::BTreeMap;
use std::collections::btree_map::Entry;

use genom_model::duration::format_ns;
use genom_model::trace::{Event, Trace, TraceStep};

use super::aside::Waits;
use super::trace::timed_trace_seeing;
use super::{TG3Action, TG3State, TimedEngine, Who};
use crate::genom3::machine::{Machine, Owner, Target};
use crate::genom3::state::{Inst, mark};
use crate::genom3::trace::describe;
use crate::kernel::explore::Exploration;
use crate::kernel::store::StateId;
use crate::zones::dbm::Dbm;

/// A task that can overrun for one cause, with its trace.
#[derive(Debug, Clone)]
pub struct TaskOverrun {
    /// Index of the task in [`Machine::tasks`].
    pub task: usize,
    /// What made the tick find the work unfinished.
    pub cause: Cause,
    /// The trace, ending at the tick that finds work unfinished.
    pub trace: Trace,
}

/// Why a task's tick finds the work of its previous wake-up unfinished.
/// Each cause is reported with its own trace, so that one does not hide
/// another.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Cause {
    /// A codel (its owner's machine, its state) whose WCET is longer than
    /// the period still runs: the codel alone overruns (`codel-overrun`).
    LongCodel(Owner, u8),
    /// A codel of the task took a ticket in GenoM3's resource FIFO in that
    /// wake-up: it waited for a lock.
    LockWait,
    /// An instance ran several codels joined without `pause::` in that
    /// wake-up.
    Chain,
    /// The codels of several instances (the permanent activity's included)
    /// shared the wake-up.
    Shared,
}

/// The violations an exploration meets, kept for their cause: per task
/// and long codel, the first state where that codel still runs at the
/// tick; per task, the first `examined` others (breadth-first, so the
/// shortest), whose cause is read off their path once the exploration
/// ends ([`Violations::first`]).
#[derive(Debug, Default)]
pub(super) struct Violations {
    long: BTreeMap<(usize, Cause), StateId>,
    other: BTreeMap<usize, Vec<StateId>>,
    examined: usize,
}

impl Violations {
    /// None seen yet; `examined` others kept per task at most.
    pub(super) fn new(examined: usize) -> Self {
        Violations {
            examined,
            ..Violations::default()
        }
    }

    /// Keeps state `id`, `st`, if it is a violation (of the task it
    /// returns).
    pub(super) fn see(
        &mut self,
        te: &TimedEngine<'_>,
        id: StateId,
        st: &TG3State,
    ) -> Option<usize> {
        let t = usize::from(st.violation?);
        match long_codel(te, st, t) {
            Some(cause) => {
                self.long.entry((t, cause)).or_insert(id);
            }
            None => {
                let ids = self.other.entry(t).or_default();
                if ids.len() < self.examined {
                    ids.push(id);
                }
            }
        }
        Some(t)
    }

    /// Whether task `t` has shown long codel `cause` still running at a
    /// tick.
    pub(super) fn has_long(&self, t: usize, cause: Cause) -> bool {
        self.long.contains_key(&(t, cause))
    }

    /// Whether task `t` has shown as many other violations as are
    /// examined.
    pub(super) fn examined_all(&self, t: usize) -> bool {
        self.other
            .get(&t)
            .is_some_and(|ids| ids.len() >= self.examined)
    }

    /// The first violation kept of each (task, cause) that `keep` accepts,
    /// with its trace: a long codel still running first, then the others
    /// in order, their cause read off their path.
    pub(super) fn first(
        self,
        te: &TimedEngine<'_>,
        e: &Exploration<TG3Action, Dbm>,
        keep: impl Fn(usize, Cause) -> bool,
    ) -> BTreeMap<(usize, Cause), TaskOverrun> {
        // The violation kept per (task, cause), with its path once read.
        type Kept = (StateId, Option<Vec<TG3Action>>);
        let mut first: BTreeMap<(usize, Cause), Kept> = self
            .long
            .into_iter()
            .filter(|&((t, c), _)| keep(t, c))
            .map(|(key, id)| (key, (id, None)))
            .collect();
        for (t, ids) in self.other {
            for id in ids {
                let path = e.path(te, id);
                let c = cause_on_path(te, &path, t);
                if let (true, Entry::Vacant(v)) = (keep(t, c), first.entry((t, c))) {
                    v.insert((id, Some(path)));
                }
            }
        }
        first
            .into_iter()
            .map(|((task, cause), (id, path))| {
                let path = path.unwrap_or_else(|| e.path(te, id));
                let end = e.store_config(te, id);
                let trace = overrun_trace(te, &path, &end, task);
                ((task, cause), TaskOverrun { task, cause, trace })
            })
            .collect()
    }
}

/// The trace of `path`, which ends in `end` with task `task`'s overrun;
/// the threads that play no part in it set aside ([`super::aside`]).
pub(super) fn overrun_trace(
    te: &TimedEngine<'_>,
    path: &[TG3Action],
    end: &TG3State,
    task: usize,
) -> Trace {
    let last = TraceStep::new(Event::Violation, unfinished_text(te, end, task));
    let mut waits = Waits::default();
    let mut trace = timed_trace_seeing(te, path, last, None, |b, a| waits.see(te, b, a));
    waits.mark(te, task, &mut trace);
    trace
}

/// A codel of task `t` longer than its period, still running in `st`.
pub(super) fn long_codel(te: &TimedEngine<'_>, st: &TG3State, t: usize) -> Option<Cause> {
    te.instances(&st.g, t)
        .filter(|(_, i)| i.has(mark::BUSY))
        .find_map(|(who, i)| longer_than_period(te.m(), t, who.owner(), i.state))
}

/// [`Cause::LongCodel`] when the codel of `owner` in `state` (a codel of
/// task `t`) has a WCET longer than `t`'s period.
pub(super) fn longer_than_period(
    m: &Machine<'_>,
    t: usize,
    owner: Owner,
    state: u8,
) -> Option<Cause> {
    let period = m.tasks[t].period_ns?;
    let wcet = m.fsm(owner).states[usize::from(state)].wcet_ns?;
    (wcet > period).then_some(Cause::LongCodel(owner, state))
}

/// The cause of the violation of task `t` that `path` ends with, read off
/// the steps of the wake-up it overran (those after `t`'s previous tick).
pub(super) fn cause_on_path(te: &TimedEngine<'_>, path: &[TG3Action], t: usize) -> Cause {
    let m = te.m();
    let mine = |who: Who| m.task_of(who.owner()) == t;
    let ticks = path
        .iter()
        .enumerate()
        .filter(|(_, a)| matches!(a, TG3Action::Tick(x) if usize::from(*x) == t))
        .map(|(k, _)| k);
    let from = ticks.rev().nth(1).unwrap_or(0);
    let wake = &path[from..];
    // A codel longer than the period that ran in the wake-up is the cause
    // (though it ended, what followed it could not fit).
    let long = wake.iter().find_map(|a| match *a {
        TG3Action::Begin(who, v) if mine(who) => {
            longer_than_period(m, t, who.owner(), Inst::unpack(v)?.state)
        }
        _ => None,
    });
    if let Some(cause) = long {
        return cause;
    }
    if wake
        .iter()
        .any(|a| matches!(*a, TG3Action::Ticket(who, _) if mine(who)))
    {
        return Cause::LockWait;
    }
    let unpaused = |who: Who, v: u16, o: u8| {
        let Some(i) = Inst::unpack(v) else {
            return false;
        };
        let st = &m.fsm(who.owner()).states[usize::from(i.state)];
        matches!(
            st.yields.get(usize::from(o)),
            Some(Target::State { pause: false, .. })
        )
    };
    if wake
        .iter()
        .any(|a| matches!(*a, TG3Action::End(who, v, o) if mine(who) && unpaused(who, v, o)))
    {
        return Cause::Chain;
    }
    Cause::Shared
}

/// What the tick of task `t` finds unfinished in `st`.
pub(super) fn unfinished_text(te: &TimedEngine<'_>, st: &TG3State, t: usize) -> String {
    let m = te.m();
    let task = &m.tasks[t];
    let period = format_ns(task.period_ns.unwrap_or(0));
    let mut what = Vec::new();
    for (who, i) in te.instances(&st.g, t) {
        let owner = who.owner();
        let state = &m.fsm(owner).states[usize::from(i.state)].name;
        let st = &m.fsm(owner).states[usize::from(i.state)];
        if i.has(mark::BUSY) && st.is_async {
            what.push(format!(
                "{} still runs `async` codel `{state}`, which has no upper bound (it waits for an external event)",
                describe(&te.e, owner)
            ));
        } else if i.has(mark::BUSY) {
            what.push(format!("{} still runs `{state}`", describe(&te.e, owner)));
        } else if i.has(mark::DUE) {
            what.push(format!(
                "{} has not run `{state}` yet (it waits for a lock)",
                describe(&te.e, owner)
            ));
        }
    }
    format!(
        "task `{}` reaches its next tick ({period} after the previous one) with the work of that wake-up unfinished: {}",
        task.name,
        what.join("; ")
    )
}
