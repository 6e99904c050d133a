//! Runs the timed explorations and reads the timing facts off the symbolic
//! states, together with every behavioural verdict (decided on the timed
//! model when the component gives timing).
//!
//! Timed clusters are the connected components of the `stops`/`delays`/
//! `forbids` relation *and* of sharing a thread or a lock (timing couples
//! those). Each cluster is explored with the init service, which runs
//! before anything else; when the init service is not linked to the
//! cluster, it is frozen once it has completed.

use std::collections::{BTreeMap, BTreeSet};

use genom_model::behaviour::{Behaviour, Position};
use genom_model::component::{CodelId, Component, Outcome, ServiceId, ThreadId};
use genom_model::trace::{Event, Trace, TraceStep};

use super::model::{TState, TimedSystem, Violation};
use super::trace::{Target, exceeded_zone, timed_lasso, timed_trace};
use crate::dialect::analysis::{Analysis, Found, Witnesses, collect, finish_dead, visit};
use crate::dialect::system::System;
use crate::kernel::explore::{Limits, explore};
use crate::kernel::store::StateId;
use crate::zones::dbm::lt;

/// A thread overrun with its timed trace.
#[derive(Debug, Clone)]
pub struct Overrun {
    /// The thread.
    pub thread: ThreadId,
    /// The trace, ending at the wake-up that finds work unfinished.
    pub trace: Trace,
}

/// A codel whose WCET is longer than its thread's period
/// (`codel-overrun`), with a timed trace where it runs at a wake-up of its
/// thread.
#[derive(Debug, Clone)]
pub struct CodelOverrun {
    /// The codel.
    pub codel: CodelId,
    /// The trace: the codel starts, and its thread wakes up again before it
    /// can have finished (an overrun of the thread by that codel).
    pub trace: Trace,
}

/// A service that can miss its max-time.
#[derive(Debug, Clone)]
pub struct Exceeded {
    /// The service.
    pub service: ServiceId,
    /// The trace, ending when the max-time has passed with the instance
    /// still running.
    pub trace: Trace,
}

/// The timing facts of the timed explorations.
#[derive(Debug, Clone, Default)]
pub struct TimedFacts {
    /// Threads that can overrun, first trace each.
    pub overruns: Vec<Overrun>,
    /// Codels longer than their thread's period that run in some
    /// execution, first trace each (in codel order).
    pub codel_overruns: Vec<CodelOverrun>,
    /// Services that can miss their max-time, first trace each.
    pub exceeded: Vec<Exceeded>,
    /// Services some execution ends by itself within its max-time.
    pub in_time: BTreeSet<ServiceId>,
    /// Services acknowledged in some execution.
    pub acknowledged: BTreeSet<ServiceId>,
}

/// Witnesses of the timing facts in one exploration.
#[derive(Default)]
struct TFound {
    overruns: BTreeMap<ThreadId, StateId>,
    codel_overruns: BTreeMap<CodelId, StateId>,
    exceeded: BTreeMap<ServiceId, (StateId, usize, usize, i64)>,
    in_time: BTreeSet<ServiceId>,
    acknowledged: BTreeSet<ServiceId>,
}

/// The explorations of the timed model: the members of each timed cluster,
/// with the `init` service added when it is not one of them, and whether it
/// was added (it is then frozen once it has succeeded: see
/// [`TimedSystem::new`]).
pub fn timed_explorations(c: &Component) -> Vec<(Vec<ServiceId>, bool)> {
    let init = c.init_service();
    c.timed_clusters()
        .into_iter()
        .map(|mut members| {
            let added = init.filter(|i| !members.contains(i));
            if let Some(i) = added {
                members.push(i);
                members.sort();
            }
            (members, added.is_some())
        })
        .collect()
}

/// Explores the component's timed model.
pub fn analyse_timed(c: &Component, limits: Limits) -> (Analysis, TimedFacts) {
    let b = Behaviour::new(c);
    let mut out = Analysis::default();
    let mut facts = TimedFacts::default();
    let mut budget = limits;
    for (members, frozen) in timed_explorations(c) {
        // Past the deadline, a cluster is not even built (a large one takes
        // long to set up): it is left unproven.
        if genom_model::limits::out_of_time(budget.deadline) {
            out.stopped.get_or_insert(crate::dialect::Stop::Time);
            out.unproven.extend(members.iter().copied());
            continue;
        }
        explore_timed(c, &b, &members, frozen, &mut budget, &mut out, &mut facts);
    }
    let all: Vec<ServiceId> = c.services.ids().collect();
    let global = System::new(c, &b, &all, false);
    finish_dead(c, &global, &mut out);
    (out, facts)
}

fn explore_timed(
    c: &Component,
    b: &Behaviour,
    members: &[ServiceId],
    frozen: bool,
    budget: &mut Limits,
    out: &mut Analysis,
    facts: &mut TimedFacts,
) {
    let ts = TimedSystem::new(c, b, members, frozen);
    let mut found = Found::default();
    let mut tfound = TFound::default();
    let e = explore(&ts, *budget, |id, st| {
        visit(&ts.sys, id, &st.cfg, &mut found);
        tvisit(&ts, id, st, &mut tfound);
    });
    out.account(budget, &e);
    if e.stopped.is_some() {
        out.unproven.extend(members.iter().copied());
    }
    let config = |id: StateId| e.store_config(&ts, id).cfg;
    let trace = |id: StateId, looping: Option<ServiceId>, last: TraceStep| {
        let path = e.store.path(id);
        match looping.and_then(|s| ts.sys.member_index(s)) {
            Some(i) => timed_lasso(&ts, &path, i, last),
            None => timed_trace(&ts, &path, Target::Any, last),
        }
    };
    collect(
        &Witnesses {
            sys: &ts.sys,
            config: &config,
            trace: &trace,
            complete: e.stopped.is_none(),
        },
        &found,
        out,
    );
    for (&thread, &id) in &tfound.overruns {
        let name = &c.threads[thread].name.name;
        let text =
            format!("thread `{name}` wakes up while codels of its previous period are unfinished");
        let trace = timed_trace(
            &ts,
            &e.store.path(id),
            Target::Any,
            TraceStep::new(Event::Violation, text),
        );
        facts.overruns.push(Overrun { thread, trace });
    }
    for (&codel, &id) in &tfound.codel_overruns {
        let k = &c.codels[codel];
        let thread = c.services[k.service]
            .thread
            .map_or("", |t| &c.threads[t.id].name.name);
        let text = format!(
            "`{}::{}` is still running when thread `{thread}` wakes up again",
            c.services[k.service].name.name, k.name.name
        );
        let trace = timed_trace(
            &ts,
            &e.store.path(id),
            Target::Any,
            TraceStep::new(Event::Violation, text),
        );
        facts.codel_overruns.push(CodelOverrun { codel, trace });
    }
    for (&service, &(id, member, clock, max)) in &tfound.exceeded {
        let s = &c.services[service];
        let m = s.max_time.map_or(0, |m| m.ns);
        let text = format!(
            "`{}` has not ended {} after its acknowledgment",
            s.name.name,
            genom_model::duration::format_ns(m)
        );
        let target = Target::Exceeded { member, clock, max };
        let trace = timed_trace(
            &ts,
            &e.store.path(id),
            target,
            TraceStep::new(Event::Violation, text),
        );
        facts.exceeded.push(Exceeded { service, trace });
    }
    facts.in_time.extend(tfound.in_time);
    facts.acknowledged.extend(tfound.acknowledged);
    facts.in_time.extend(
        found
            .started
            .iter()
            .filter(|&&s| c.services[s].start.is_none()),
    );
}

/// Reads the timing facts of one new symbolic state.
fn tvisit(ts: &TimedSystem<'_>, id: StateId, st: &TState, found: &mut TFound) {
    if let Some(Violation::Overrun(k)) = st.violation {
        if let Some(t) = ts.threads.get(usize::from(k)) {
            found.overruns.entry(t.id).or_insert(id);
        }
        if let Some(codel) = ts
            .running_on(st, usize::from(k))
            .filter(|&x| longer_than_period(ts, x))
        {
            found.codel_overruns.entry(codel).or_insert(id);
        }
        return;
    }
    let urgent = ts.urgent(st);
    for i in 0..ts.sys.len() {
        let s = ts.sys.service(i);
        if System::has_instance(&st.cfg, i) {
            found.acknowledged.insert(s);
        }
        if ends_in_time(ts, st, i) {
            found.in_time.insert(s);
        }
        // A looping service's max-time is enforced by its watchdog (the
        // `max-time-watchdog` advice), not a deadline it can miss.
        if urgent || found.exceeded.contains_key(&s) || ts.sys.machine_of(i).active_loop {
            continue;
        }
        let (Some((main, pend)), Some(max)) = (ts.watch[i], ts.max_time[i]) else {
            continue;
        };
        let mut clocks = Vec::new();
        if ts.watchable(&st.cfg, i) {
            clocks.push(main);
        }
        if st.cfg.pending[i].is_some() {
            clocks.push(if st.cfg.main[i] == genom_model::behaviour::IDLE {
                main
            } else {
                pend
            });
        }
        for clock in clocks {
            let z = exceeded_zone(ts, st, i, clock, max);
            if !z.is_empty() && z.intersects(0, clock, lt(-max)) {
                found.exceeded.entry(s).or_insert((id, i, clock, max));
            }
        }
    }
}

/// Whether codel `k`'s WCET is longer than its thread's period.
fn longer_than_period(ts: &TimedSystem<'_>, k: CodelId) -> bool {
    let c = ts.sys.component();
    let codel = &c.codels[k];
    let period = c.services[codel.service]
        .thread
        .and_then(|t| c.threads[t.id].period);
    matches!((codel.wcet, period), (Some(w), Some(p)) if w.ns > p.ns)
}

/// Member `i` runs a codel that may end its instance by itself (an `end`
/// or report outcome), not interrupted: it can end within its max-time.
fn ends_in_time(ts: &TimedSystem<'_>, st: &TState, i: usize) -> bool {
    let Position::Running {
        codel,
        interrupted: false,
    } = ts.sys.position(&st.cfg, i)
    else {
        return false;
    };
    let c = ts.sys.component();
    !st.cfg.timed_out[i]
        && c.codels[codel]
            .outcomes()
            .iter()
            .any(|o| matches!(o, Outcome::End | Outcome::Report(_)))
}
