//! Explores the timed GenoM3 model of a component group by group (tasks
//! coupled by locks or by their services' links, [`super::groups`]) and
//! reads the schedulability verdict off it: which tasks can reach a tick
//! with the work of their previous wake-up unfinished, each with the
//! concrete timed trace of the first such tick found (breadth-first: a
//! shortest one).

use std::collections::{BTreeMap, BTreeSet};

use super::groups::groups;
use super::hunt::{Hunted, Wanted};
use super::locks::Locks;
use super::overrun::Violations;
pub use super::overrun::{Cause, TaskOverrun};
use super::{TG3State, TimedEngine, unit_ns};
use crate::genom3::machine::Machine;
use crate::kernel::explore::{Found, Limits, Stop, explore_until};
use crate::kernel::store::Footprint;

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
    /// Per periodic task of an unfinished group that the bound does not
    /// clear: the causes of overrun the static bound leaves possible and
    /// that no exploration found (docs/genom3-semantics.md 15.14); empty
    /// once each has shown an overrun.
    pub open_causes: BTreeMap<usize, BTreeSet<Cause>>,
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
    /// Decided by finding every cause of overrun the static bound leaves
    /// possible (docs/genom3-semantics.md 15.14), before its whole
    /// exploration finished.
    pub witnessed: bool,
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
    analyse_timing_tuned(m, limits, reduce, early, Tuning::DEFAULT)
}

/// The sizes the analysis works with (tests choose their own).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Tuning {
    /// States of a group's probe ([`decide_group`]).
    pub probe: usize,
    /// Violations of a task examined for their cause ([`EXAMINED`]).
    pub examined: usize,
}

impl Tuning {
    /// The analysis's own.
    pub const DEFAULT: Tuning = Tuning {
        probe: PROBE,
        examined: EXAMINED,
    };
}

/// [`analyse_timing_early`] with `tuning`.
pub(crate) fn analyse_timing_tuned(
    m: &Machine<'_>,
    limits: Limits,
    reduce: bool,
    early: bool,
    tuning: Tuning,
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
        let (states, complete, witnessed) = if by_bound {
            (0, true, false)
        } else if early {
            decide_group(&te, &group, limits, &safe, tuning, &mut out)
        } else {
            let run = explore_group(&te, limits, false, &safe, tuning.examined);
            let complete = run.stopped.is_none();
            (out.take(run), complete, false)
        };
        out.records.push(GroupRecord {
            tasks: (0..group.tasks.len()).filter(|&t| group.tasks[t]).collect(),
            services: m.requested(&group.acts, &group.ctls),
            states,
            complete,
            by_bound,
            witnessed,
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

/// States of a group's first, capped exploration (the probe of
/// [`decide_group`]): most groups finish within it.
const PROBE: usize = 1 << 18;

/// States of each exploration of the search with restricted clients, at
/// most, and of all of them together ([`super::hunt`]).
const HUNT_EACH: usize = 1 << 17;
const HUNT_ALL: usize = 1 << 21;

/// Decides one group with the early stop, and adds its findings (docs/
/// genom3-semantics.md 15.11-15.14): its exploration capped at [`PROBE`]
/// states; if that does not finish, the search with restricted clients for
/// every cause of overrun still possible (the static bound's
/// [`possible_causes`](super::bound::possible_causes) not yet found): once
/// each is found, nothing more could be reported and the group is decided.
/// Otherwise its whole exploration, within `limits`, and what the search
/// found besides if that too stops. Returns its states, whether it is
/// decided, and whether by the search.
fn decide_group(
    te: &TimedEngine<'_>,
    group: &super::groups::Group,
    limits: Limits,
    safe: &[bool],
    tuning: Tuning,
    out: &mut TimingAnalysis,
) -> (u64, bool, bool) {
    let probe_limits = Limits {
        max_states: limits.max_states.min(tuning.probe),
        ..limits
    };
    let probe = explore_group(te, probe_limits, true, safe, tuning.examined);
    if probe.stopped.is_none() {
        return (out.take(probe), true, false);
    }
    let wanted = still_possible(te, safe, &probe);
    let found = if probe.stopped == Some(Stop::Memory) {
        Hunted::default()
    } else {
        let all = Limits {
            max_states: limits.max_states.min(HUNT_ALL),
            ..limits
        };
        let each = (limits.max_states / 10).min(HUNT_EACH);
        super::hunt::hunt(te.m(), group, &te.locks, &wanted, all, each)
    };
    let searched = (found.states, found.transitions);
    let found: BTreeMap<(usize, Cause), TaskOverrun> = found
        .overruns
        .into_iter()
        .map(|o| ((o.task, o.cause), o))
        .collect();
    let witnessed = wanted
        .iter()
        .all(|(&t, causes)| causes.iter().all(|&c| found.contains_key(&(t, c))));
    let capped = probe.stopped == Some(Stop::States) && limits.max_states > tuning.probe;
    let late = limits
        .deadline
        .is_some_and(|d| std::time::Instant::now() >= d);
    let (mut run, spent) = if witnessed {
        let mut run = probe;
        run.stopped = None;
        (run, searched)
    } else if capped && !late {
        let whole = explore_group(te, limits, true, safe, tuning.examined);
        (
            whole,
            (searched.0 + probe.states, searched.1 + probe.transitions),
        )
    } else {
        (probe, searched)
    };
    run.states += spent.0;
    run.transitions += spent.1;
    let complete = run.stopped.is_none();
    // A whole exploration that finished reports what it found alone.
    if witnessed || !complete {
        let looked: Vec<usize> = te.periodic_tasks().filter(|&t| !safe[t]).collect();
        add_found(out, &mut run, found, &wanted, &looked);
    }
    (out.take(run), complete, witnessed)
}

/// Per periodic task of the group that the bound does not clear: the
/// causes of overrun the bound leaves possible that `probe` did not show.
fn still_possible(te: &TimedEngine<'_>, safe: &[bool], probe: &GroupRun) -> Wanted {
    let mut wanted: Wanted = BTreeMap::new();
    for (t, mut causes) in super::bound::possible_causes(te).into_iter().enumerate() {
        causes.retain(|&c| !probe.overruns.contains_key(&(t, c)));
        if !safe[t] && !causes.is_empty() {
            wanted.insert(t, causes);
        }
    }
    wanted
}

/// Adds to `run` what the search `found` besides, keeping the
/// exploration's own trace of a cause both found; for a run that did not
/// finish, what is still possible of `wanted` goes to
/// [`TimingAnalysis::open_causes`], for each of the tasks `looked` for
/// (nothing, for a task that has shown every cause).
fn add_found(
    out: &mut TimingAnalysis,
    run: &mut GroupRun,
    found: BTreeMap<(usize, Cause), TaskOverrun>,
    wanted: &Wanted,
    looked: &[usize],
) {
    for (key, o) in found {
        run.overruns.entry(key).or_insert(o);
    }
    if run.stopped.is_none() {
        return;
    }
    for &t in looked {
        let open: BTreeSet<Cause> = wanted
            .get(&t)
            .into_iter()
            .flatten()
            .filter(|&&c| !run.overruns.contains_key(&(t, c)))
            .copied()
            .collect();
        out.open_causes.insert(t, open);
    }
}

/// One exploration of a group: per task and [`Cause`], its first
/// violation.
#[derive(Debug, Default)]
struct GroupRun {
    overruns: BTreeMap<(usize, Cause), TaskOverrun>,
    states: u64,
    transitions: u64,
    footprint: Footprint,
    stopped: Option<Stop>,
}

impl TimingAnalysis {
    /// Adds `run`'s findings and figures; returns its states.
    fn take(&mut self, run: GroupRun) -> u64 {
        self.overruns.extend(run.overruns.into_values());
        self.states += run.states;
        self.transitions += run.transitions;
        self.footprint.join(run.footprint);
        self.stopped = self.stopped.or(run.stopped);
        run.states
    }
}

/// Explores one group: per task, the first violation of each [`Cause`].
/// With `early`, the exploration stops (complete) once nothing it could
/// still find would change them ([`everything_found`]).
fn explore_group(
    te: &TimedEngine<'_>,
    limits: Limits,
    early: bool,
    safe: &[bool],
    examined: usize,
) -> GroupRun {
    let mut seen = Violations::new(examined);
    let mut findable = findable_long_codels(te);
    findable.retain(|&t, _| !safe[t]);
    let e = explore_until(te, limits, |id, st: &TG3State| {
        if seen.see(te, id, st).is_some() && early && everything_found(&findable, &seen) {
            Found::All
        } else {
            Found::Open
        }
    });
    let overruns = seen.first(te, &e, |_, _| true);
    let mut footprint = Footprint::default();
    footprint.add(&e.store);
    GroupRun {
        overruns,
        states: e.store.len() as u64,
        transitions: e.transitions,
        footprint,
        stopped: e.stopped,
    }
}

/// Per periodic task of the group explored, the long-codel causes a
/// violation could show: its codels whose WCET is longer than its period
/// (docs/genom3-semantics.md 15.11).
fn findable_long_codels(te: &TimedEngine<'_>) -> BTreeMap<usize, Vec<Cause>> {
    let possible = super::bound::possible_causes(te);
    te.periodic_tasks()
        .map(|t| {
            let long = possible[t].iter().copied();
            (
                t,
                long.filter(|c| matches!(c, Cause::LongCodel(..))).collect(),
            )
        })
        .collect()
}

/// Whether exploring further can change no finding of the group (the early
/// stop, docs/genom3-semantics.md 15.11): every periodic task of it has
/// shown [`EXAMINED`] violations whose cause is read off their path (the
/// first ones, breadth-first, which are all that is ever examined) and
/// every long codel it has, still running at a tick. What is reported then
/// is what the whole exploration would report; only the state count is
/// smaller. A group with a task that never overruns is explored to the
/// end, which is what proves it.
fn everything_found(findable: &BTreeMap<usize, Vec<Cause>>, seen: &Violations) -> bool {
    !findable.is_empty()
        && findable
            .iter()
            .all(|(&t, causes)| seen.examined_all(t) && causes.iter().all(|&c| seen.has_long(t, c)))
}
