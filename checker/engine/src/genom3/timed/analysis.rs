//! Explores the timed GenoM3 model of a component group by group (tasks
//! coupled by locks or by their services' links, [`super::groups`]) and
//! reads the schedulability verdict off it: which tasks can reach a tick
//! with the work of their previous wake-up unfinished, each with the
//! concrete timed trace of the first such tick found (breadth-first: a
//! shortest one).

use std::collections::BTreeMap;

use genom_model::render::human::format_ns;
use genom_model::trace::{Event, Trace, TraceStep};

use super::groups::groups;
use super::locks::Locks;
use super::trace::timed_trace;
use super::{TG3State, TimedEngine, unit_ns};
use crate::engine::explore::{Limits, Stop, explore};
use crate::engine::store::StateId;
use crate::genom3::analysis::describe;
use crate::genom3::machine::Machine;
use crate::genom3::state::mark;

/// A task that can overrun, with its trace.
#[derive(Debug, Clone)]
pub struct TaskOverrun {
    /// Index of the task in [`Machine::tasks`].
    pub task: usize,
    /// The trace, ending at the tick that finds work unfinished.
    pub trace: Trace,
}

/// What the timed exploration found.
#[derive(Debug, Clone, Default)]
pub struct TimingAnalysis {
    /// Symbolic states stored.
    pub states: u64,
    /// Transitions fired.
    pub transitions: u64,
    /// Clocks of the largest model.
    pub clocks: usize,
    /// Groups explored.
    pub groups: usize,
    /// Why the exploration stopped early, if it did.
    pub stopped: Option<Stop>,
    /// Tasks that can overrun, in task order.
    pub overruns: Vec<TaskOverrun>,
}

/// Explores the timed model of `m`, group by group ([`super::groups`]);
/// `None` when it has too many tasks for one (see [`super::MAX_TASKS`]).
pub fn analyse_timing(m: &Machine<'_>, limits: Limits) -> Option<TimingAnalysis> {
    if m.tasks.len() > super::MAX_TASKS {
        return None;
    }
    let locks = Locks::new(m, unit_ns(m));
    let mut out = TimingAnalysis::default();
    for group in groups(m, &locks) {
        let te = TimedEngine::with_locks(m.clone(), &group, locks.clone())?;
        out.clocks = out.clocks.max(te.clock_count());
        explore_group(&te, limits, &mut out);
        out.groups += 1;
        // A group at the state limit leaves the others worth exploring.
        if matches!(out.stopped, Some(Stop::Time | Stop::Memory)) {
            break;
        }
    }
    out.overruns.sort_by_key(|o| o.task);
    Some(out)
}

/// Explores one group and adds its findings.
fn explore_group(te: &TimedEngine<'_>, limits: Limits, out: &mut TimingAnalysis) {
    let mut first: BTreeMap<usize, StateId> = BTreeMap::new();
    let e = explore(te, limits, |id, st: &TG3State| {
        if let Some(t) = st.violation {
            first.entry(usize::from(t)).or_insert(id);
        }
    });
    out.overruns.extend(first.iter().map(|(&task, &id)| {
        let path = e.store.path(id);
        let end = e.store_config(te, id);
        let last = TraceStep::new(Event::Violation, unfinished_text(te, &end, task));
        TaskOverrun {
            task,
            trace: timed_trace(te, &path, last),
        }
    }));
    out.states += e.store.len() as u64;
    out.transitions += e.transitions;
    out.stopped = out.stopped.or(e.stopped);
}

/// What the tick of task `t` finds unfinished in `st`.
fn unfinished_text(te: &TimedEngine<'_>, st: &TG3State, t: usize) -> String {
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
