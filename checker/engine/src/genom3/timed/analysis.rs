//! Explores the timed GenoM3 model of a component group by group (tasks
//! coupled by locks or by their services' links, [`super::groups`]) and
//! reads the schedulability verdict off it: which tasks can reach a tick
//! with the work of their previous wake-up unfinished, each with the
//! concrete timed trace of the first such tick found (breadth-first: a
//! shortest one).

use std::collections::BTreeMap;

use super::groups::groups;
use super::locks::Locks;
pub use super::overrun::{Cause, TaskOverrun};
use super::overrun::{cause_on_path, long_codel, longer_than_period, overrun_trace};
use super::{TG3Action, TG3State, TimedEngine, Who, unit_ns};
use crate::genom3::machine::Machine;
use crate::kernel::explore::{Found, Limits, Stop, explore_until};
use crate::kernel::store::{Footprint, StateId};

/// Violations of one task examined for their cause, at most (breadth
/// first, so the shortest come first); the long-codel cause is read off
/// the state and needs none.
const EXAMINED: usize = 256;

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
    /// Bytes per stored state, of the largest group.
    pub footprint: Footprint,
    /// Why the exploration stopped early, if it did.
    pub stopped: Option<Stop>,
    /// Tasks that can overrun, in task order.
    pub overruns: Vec<TaskOverrun>,
    /// Periodic tasks shown unable to overrun by the static bound of their
    /// wake-up (docs/genom3-semantics.md 15.12), in task order.
    pub bounded: Vec<usize>,
    /// What each group's exploration covered, in exploration order.
    pub records: Vec<GroupRecord>,
    /// Tasks found overrunning only by the search with restricted clients
    /// after their group's exploration stopped ([`super::hunt`]), in the
    /// order found.
    pub hunted: Vec<usize>,
}

/// One group's exploration ([`super::groups`]).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct GroupRecord {
    /// Its tasks.
    pub tasks: Vec<usize>,
    /// The services it requests, but the built-in ones.
    pub services: Vec<genom_model::component::ServiceId>,
    /// States stored.
    pub states: u64,
    /// Whether it finished.
    pub complete: bool,
    /// Decided by the static bound alone (every periodic task of it is in
    /// [`TimingAnalysis::bounded`]): not explored.
    pub by_bound: bool,
}

/// Explores the timed model of `m`, group by group ([`super::groups`]);
/// `None` when it has too many tasks for one (see [`super::MAX_TASKS`]).
pub fn analyse_timing(m: &Machine<'_>, limits: Limits) -> Option<TimingAnalysis> {
    analyse_timing_with(m, limits, true)
}

/// [`analyse_timing`], with or without the quiet-request reduction
/// ([`TimedEngine::changes_nothing`]) and the early stop (without, for
/// tests that compare).
pub(crate) fn analyse_timing_with(
    m: &Machine<'_>,
    limits: Limits,
    reduce: bool,
) -> Option<TimingAnalysis> {
    analyse_timing_early(m, limits, reduce, reduce)
}

/// [`analyse_timing_with`], the early stop ([`everything_found`]) chosen
/// apart.
pub(crate) fn analyse_timing_early(
    m: &Machine<'_>,
    limits: Limits,
    reduce: bool,
    early: bool,
) -> Option<TimingAnalysis> {
    if m.tasks.len() > super::MAX_TASKS {
        return None;
    }
    let locks = Locks::new(m, unit_ns(m));
    let mut out = TimingAnalysis::default();
    for group in groups(m, &locks) {
        let mut te = TimedEngine::with_locks(m.clone(), &group, locks.clone())?;
        if reduce {
            te.dominate_calls();
        } else {
            te.quiet.fill(None);
        }
        out.clocks = out.clocks.max(te.clock_count());
        // Tasks the static bound (15.12) shows cannot overrun: nothing to
        // find in them, and a group of such tasks needs no exploration.
        let safe = if early {
            super::bound::cannot_overrun(&te)
        } else {
            vec![false; m.tasks.len()]
        };
        out.bounded.extend(te.periodic_tasks().filter(|&t| safe[t]));
        let by_bound = te.periodic_tasks().all(|t| safe[t]);
        let (states, complete) = if by_bound {
            (0, true)
        } else {
            explore_group(&te, reserve(limits, early), early, &safe, &mut out)
        };
        if early && !complete && out.stopped != Some(Stop::Memory) {
            hunt_unfound(&te, &group, &safe, limits, &mut out);
        }
        out.records.push(GroupRecord {
            tasks: (0..group.tasks.len()).filter(|&t| group.tasks[t]).collect(),
            services: m.requested(&group.acts, &group.ctls),
            states,
            complete,
            by_bound,
        });
        out.groups += 1;
        // A group at the state limit leaves the others worth exploring.
        if matches!(out.stopped, Some(Stop::Time | Stop::Memory)) {
            break;
        }
    }
    out.overruns.sort_by_key(|o| (o.task, o.cause));
    out.bounded.sort_unstable();
    Some(out)
}

/// The limits of a group's whole exploration when the search of
/// [`super::hunt`] may follow it: a tenth of the time left is kept for
/// that search (the state limit holds for each exploration alone).
fn reserve(limits: Limits, early: bool) -> Limits {
    let now = std::time::Instant::now();
    let deadline = limits.deadline.filter(|_| early).map(|d| {
        d.checked_sub(d.saturating_duration_since(now) / 10)
            .unwrap_or(d)
    });
    Limits {
        deadline: deadline.or(limits.deadline),
        ..limits
    }
}

/// After a group's exploration stopped: looks for an overrun of each of
/// its periodic tasks that the bound did not clear and the exploration
/// did not find overrunning, with restricted clients ([`super::hunt`]).
fn hunt_unfound(
    te: &TimedEngine<'_>,
    group: &super::groups::Group,
    safe: &[bool],
    limits: Limits,
    out: &mut TimingAnalysis,
) {
    let found: std::collections::BTreeSet<usize> = out.overruns.iter().map(|o| o.task).collect();
    let wanted: Vec<usize> = te
        .periodic_tasks()
        .filter(|&t| !safe[t] && !found.contains(&t))
        .collect();
    if wanted.is_empty() {
        return;
    }
    let h = super::hunt::hunt(te.m(), group, &te.locks, &wanted, limits);
    out.hunted.extend(h.overruns.iter().map(|o| o.task));
    out.overruns.extend(h.overruns);
    out.states += h.states;
    out.transitions += h.transitions;
}

/// Explores one group and adds its findings: per task, the first
/// violation of each [`Cause`]. Returns its states and whether it
/// finished. With `early`, the exploration stops (complete) once nothing
/// it could still find would change them ([`everything_found`]).
fn explore_group(
    te: &TimedEngine<'_>,
    limits: Limits,
    early: bool,
    safe: &[bool],
    out: &mut TimingAnalysis,
) -> (u64, bool) {
    let mut long: BTreeMap<(usize, Cause), StateId> = BTreeMap::new();
    let mut other: BTreeMap<usize, Vec<StateId>> = BTreeMap::new();
    let mut findable = findable_long_codels(te);
    findable.retain(|&t, _| !safe[t]);
    let e = explore_until(te, limits, |id, st: &TG3State| {
        let Some(t) = st.violation.map(usize::from) else {
            return Found::Open;
        };
        match long_codel(te, st, t) {
            Some(cause) => {
                long.entry((t, cause)).or_insert(id);
            }
            None => {
                let ids = other.entry(t).or_default();
                if ids.len() < EXAMINED {
                    ids.push(id);
                }
            }
        }
        if early && everything_found(&findable, &long, &other) {
            Found::All
        } else {
            Found::Open
        }
    });
    let mut first = long;
    // Paths are found again from the parents (`Exploration::path`): keep
    // those of the violations kept, not to find them twice.
    let mut paths: BTreeMap<StateId, Vec<TG3Action>> = BTreeMap::new();
    for (&t, ids) in &other {
        for &id in ids {
            let path = e.path(te, id);
            if let std::collections::btree_map::Entry::Vacant(v) =
                first.entry((t, cause_on_path(te, &path, t)))
            {
                v.insert(id);
                paths.insert(id, path);
            }
        }
    }
    out.overruns
        .extend(first.iter().map(|(&(task, cause), &id)| {
            let path = paths.remove(&id).unwrap_or_else(|| e.path(te, id));
            let end = e.store_config(te, id);
            TaskOverrun {
                task,
                cause,
                trace: overrun_trace(te, &path, &end, task),
            }
        }));
    out.states += e.store.len() as u64;
    out.transitions += e.transitions;
    out.footprint.add(&e.store);
    out.stopped = out.stopped.or(e.stopped);
    (e.store.len() as u64, e.stopped.is_none())
}

/// Per periodic task of the group explored, the long-codel causes a
/// violation could show: its codels whose WCET is longer than its period
/// (docs/genom3-semantics.md 15.11).
fn findable_long_codels(te: &TimedEngine<'_>) -> BTreeMap<usize, Vec<Cause>> {
    let m = te.m();
    let mut out = BTreeMap::new();
    for t in te.periodic_tasks() {
        let perm = m.tasks[t].perm.as_ref().map(|_| Who::Perm(t as u8));
        let acts = te.acts_of[t].iter().map(|&a| Who::Act(a as u16));
        let causes = perm
            .into_iter()
            .chain(acts)
            .flat_map(|who| {
                let states = m.fsm(who.owner()).states.len();
                (0..states).filter_map(move |k| longer_than_period(m, t, who, k as u8))
            })
            .collect();
        out.insert(t, causes);
    }
    out
}

/// Whether exploring further can change no finding of the group (the early
/// stop, docs/genom3-semantics.md 15.11): every periodic task of it has
/// shown [`EXAMINED`] violations whose cause is read off their path (the
/// first ones, breadth-first, which are all that is ever examined) and
/// every long codel it has, still running at a tick. What is reported then
/// is what the whole exploration would report; only the state count is
/// smaller. A group with a task that never overruns is explored to the
/// end, which is what proves it.
fn everything_found(
    findable: &BTreeMap<usize, Vec<Cause>>,
    long: &BTreeMap<(usize, Cause), StateId>,
    other: &BTreeMap<usize, Vec<StateId>>,
) -> bool {
    !findable.is_empty()
        && findable.iter().all(|(&t, causes)| {
            other.get(&t).is_some_and(|ids| ids.len() >= EXAMINED)
                && causes.iter().all(|&c| long.contains_key(&(t, c)))
        })
}
