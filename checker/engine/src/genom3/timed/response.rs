//! Worst-case response times in GenoM3's timed semantics: for every
//! activity, function and attribute, the largest time from its
//! acknowledgment to its final reply (docs/genom3-semantics.md section 16).
//!
//! - An **activity** on a periodic task: the timed model of its group
//!   ([`super::groups`]) is explored once more with a *response clock* per
//!   activity, reset when its instance is accepted (after `validate`) and
//!   freed when it ended (the control thread then replies, in no time). The
//!   worst case is the supremum of the clock over the reachable symbolic
//!   states where the instance lives. Response clocks are compared from
//!   below with constants up to a horizon `H` (their LU bound), which keeps
//!   that supremum exact up to `H`. An instance that can stay alive forever
//!   is `unbounded` ([`TimedEngine::endless`]) and its clock is freed there.
//! - An activity on an **aperiodic** task: the model activates such a task
//!   at any time, not at once, so no bound is computed; its response is
//!   `unbounded` when its machine can pause, loop or wait in an `async`
//!   codel (a paused instance waits for an event that may never come), else
//!   undecided.
//! - A **function or attribute**: from the moment the control thread takes
//!   its request to its reply, that is its control codels' WCETs plus, for
//!   the codels whose locks some task contends, their waits (a control
//!   response clock in the same exploration).
//!
//! One instance per activity (`--max-instances 1`). A tick that finds its
//! task's work unfinished is coalesced, as GenoM3 does (the task wakes
//! again as soon as the work ends): the response times hold whether or not
//! tasks overrun (`thread-overrun` is reported by the schedulability
//! analysis, which stops at the first overrun tick instead).

use std::collections::BTreeMap;

use genom_model::component::ServiceId;
use genom_model::duration::format_ns;
use genom_model::trace::{Event, Trace, TraceStep};

use super::groups::groups;
use super::locks::Locks;
use super::trace::timed_trace_beyond;
use super::{TG3State, TimedEngine, unit_ns};
use crate::genom3::machine::{Machine, Owner, Target};
use crate::genom3::state::{G3State, Inst, Status, mark};
use crate::genom3::steps::G3Action;
use crate::kernel::explore::{Limits, Stop, explore};
use crate::kernel::store::StateId;
use crate::timed::{ServiceResponse, Worst};
use crate::zones::dbm::{INF, constant};

/// Candidate states tried for a deadline trace (a stored zone can be larger
/// than the exact zone of its own path).
const TRACE_CANDIDATES: usize = 8;

/// What the response-time explorations found.
#[derive(Debug, Clone, Default)]
pub struct ResponseAnalysis {
    /// One result per service (built-ins left out), in service order.
    pub found: Vec<ServiceResponse>,
    /// Symbolic states stored.
    pub states: u64,
    /// Transitions fired.
    pub transitions: u64,
    /// Why an exploration stopped early, if one did.
    pub stopped: Option<Stop>,
}

/// What the visits saw of one clock.
#[derive(Debug, Default, Clone)]
struct Seen {
    /// Some state has the instance (or the request) alive.
    alive: bool,
    /// The largest supremum (units) and a state with it.
    max: Option<(i64, StateId)>,
    /// A state beyond the horizon.
    above: Option<StateId>,
    /// A state from which the instance may never reply.
    endless: Option<StateId>,
    /// States whose supremum exceeds the deadline (units), for traces.
    late: Vec<StateId>,
}

impl Seen {
    fn visit(&mut self, id: StateId, sup: Option<i64>, horizon: i64, deadline: Option<i64>) {
        self.alive = true;
        match sup {
            None => {
                self.above.get_or_insert(id);
            }
            Some(c) if c > horizon => {
                self.above.get_or_insert(id);
            }
            Some(c) => {
                if self.max.is_none_or(|(m, _)| c > m) {
                    self.max = Some((c, id));
                }
            }
        }
        let late = deadline.is_some_and(|d| sup.is_none_or(|c| c > d));
        if late && self.late.len() < TRACE_CANDIDATES {
            self.late.push(id);
        }
    }
}

/// Computes the response times of `m`'s services; `deadlines` (ns by
/// service) get traces when missed. `None` with too many tasks.
pub fn analyse_responses(
    m: &Machine<'_>,
    limits: Limits,
    deadlines: &BTreeMap<ServiceId, u64>,
) -> Option<ResponseAnalysis> {
    if m.tasks.len() > super::MAX_TASKS {
        return None;
    }
    let locks = Locks::new(m, unit_ns(m));
    let mut out = ResponseAnalysis::default();
    let mut results: BTreeMap<ServiceId, ServiceResponse> = BTreeMap::new();
    for group in groups(m, &locks) {
        let mut te = TimedEngine::with_locks(m.clone(), &group, locks.clone())?;
        let acts: Vec<bool> = (0..m.activities.len())
            .map(|a| group.acts[a] && te.period[m.activities[a].task].is_some())
            .collect();
        let ctls: Vec<bool> = (0..m.controls.len())
            .map(|k| group.ctls[k] && te.job_codels(G3Action::Call(k as u16)) > 0)
            .collect();
        let horizon = horizon(&te, deadlines);
        te.track_responses(&acts, ctls.contains(&true), horizon);
        let found = explore_group(&te, limits, horizon, deadlines, &acts, &ctls, &mut out);
        for r in found {
            merge(&mut results, r);
        }
        if matches!(out.stopped, Some(Stop::Time | Stop::Memory)) {
            break;
        }
    }
    for (a, act) in m.activities.iter().enumerate() {
        if m.tasks[act.task].period_ns.is_none() {
            results.insert(act.service, aperiodic(m, a));
        }
    }
    for ctl in m.controls.iter().filter(|c| !c.builtin) {
        let r = results
            .entry(ctl.service)
            .or_insert_with(|| ServiceResponse {
                service: ctl.service,
                worst: Worst::Exact(control_wcets(m, ctl.service)),
                exact: true,
                trace: None,
            });
        // An exploration stopped by a limit: the static bound (16.8).
        if r.worst == Worst::Incomplete {
            if let Some(ns) = super::response_bound::control_bound(m, &locks, ctl.service) {
                r.worst = Worst::AtMost(ns);
            }
        }
    }
    for act in &m.activities {
        results
            .entry(act.service)
            .or_insert_with(|| undecided(act.service, out.stopped));
    }
    out.found = results.into_values().collect();
    Some(out)
}

/// The horizon (units): twice the number of codel states plus two, times
/// the longest period and the sum of the WCETs; at least twice every
/// deadline.
fn horizon(te: &TimedEngine<'_>, deadlines: &BTreeMap<ServiceId, u64>) -> i64 {
    let m = te.m();
    let unit = te.unit;
    let p = m
        .tasks
        .iter()
        .map(|t| t.period_ns.unwrap_or(0).max(t.delay_ns))
        .max()
        .unwrap_or(0);
    let states = m
        .activities
        .iter()
        .map(|a| &a.fsm)
        .chain(m.tasks.iter().filter_map(|t| t.perm.as_ref()))
        .flat_map(|f| f.states.iter())
        .chain(m.control_codels.values().flatten());
    let (mut n, mut w) = (2u64, 0u64);
    for s in states {
        n += 1;
        w = w.saturating_add(s.wcet_ns.unwrap_or(0));
    }
    let ns = n.saturating_mul(2).saturating_mul(p.saturating_add(w)).max(
        deadlines
            .values()
            .map(|d| d.saturating_mul(2))
            .max()
            .unwrap_or(0),
    );
    i64::try_from(ns / unit)
        .unwrap_or(i64::MAX / 4)
        .min(i64::MAX / 4)
}

/// Explores one group with its response clocks.
fn explore_group(
    te: &TimedEngine<'_>,
    limits: Limits,
    horizon: i64,
    deadlines: &BTreeMap<ServiceId, u64>,
    acts: &[bool],
    ctls: &[bool],
    out: &mut ResponseAnalysis,
) -> Vec<ServiceResponse> {
    let m = te.m();
    let d_units = |s: ServiceId| deadlines.get(&s).map(|&d| (d / te.unit) as i64);
    // The WCETs of each control service's codels that never wait.
    let extras: Vec<i64> = (0..ctls.len())
        .map(|j| if ctls[j] { static_part(m, te, j) } else { 0 })
        .collect();
    let mut act_seen = vec![Seen::default(); acts.len()];
    let mut ctl_seen = vec![Seen::default(); ctls.len()];
    let e = explore(te, limits, |id, st: &TG3State| {
        for (a, seen) in act_seen.iter_mut().enumerate() {
            let Some(x) = te.resp.get(a).copied().flatten() else {
                continue;
            };
            if st.g.inst[a].is_empty() {
                continue;
            }
            if te.endless(&st.g, a) {
                seen.alive = true;
                seen.endless.get_or_insert(id);
            } else {
                let d = d_units(m.activities[a].service);
                seen.visit(id, sup(st, x), horizon, d);
            }
        }
        if let (Some(x), Some(c)) = (te.ctl_resp, st.ctl) {
            if let G3Action::Call(k) = c.job {
                let k = usize::from(k);
                for j in (0..ctls.len()).filter(|&j| ctls[j] && usize::from(te.canon[j]) == k) {
                    let d = d_units(m.controls[j].service).map(|d| d - extras[j]);
                    ctl_seen[j].visit(id, sup(st, x), horizon, d);
                }
            }
        }
    });
    out.states += e.store.len() as u64;
    out.transitions += e.transitions;
    out.stopped = out.stopped.or(e.stopped);
    let conclude = |s: ServiceId, seen: &Seen, x: usize, extra: i64| {
        // A state seen where the instance may never reply, or where its
        // clock is past the horizon, decides the worst case even when the
        // exploration stopped (16.2): more states cannot undo it.
        let worst = if seen.endless.is_some() {
            Worst::Unbounded
        } else if seen.above.is_some() {
            Worst::Above(to_ns(te, horizon + extra))
        } else if e.stopped.is_some() {
            Worst::Incomplete
        } else if let Some((c, _)) = seen.max {
            Worst::Exact(to_ns(te, c + extra))
        } else {
            Worst::Never
        };
        let trace = deadlines
            .get(&s)
            .filter(|_| matches!(worst, Worst::Unbounded | Worst::Above(_) | Worst::Exact(_)))
            .filter(|&&d| !matches!(worst, Worst::Exact(ns) if ns <= d))
            .and_then(|&d| late_trace(te, &e, seen, (x, d, extra), m.service_name(s)));
        ServiceResponse {
            service: s,
            worst,
            exact: true,
            trace,
        }
    };
    let mut found = Vec::new();
    for (a, seen) in act_seen.iter().enumerate() {
        if let Some(x) = te.resp.get(a).copied().flatten() {
            found.push(conclude(m.activities[a].service, seen, x, 0));
        }
    }
    if let Some(x) = te.ctl_resp {
        for (j, seen) in ctl_seen.iter().enumerate().filter(|&(j, _)| ctls[j]) {
            found.push(conclude(m.controls[j].service, seen, x, extras[j]));
        }
    }
    found
}

/// The supremum (units) of clock `x` in `st`'s zone, `None` when unbounded.
fn sup(st: &TG3State, x: usize) -> Option<i64> {
    let ub = st.zone.get(x, 0);
    (ub != INF).then(|| constant(ub))
}

fn to_ns(te: &TimedEngine<'_>, units: i64) -> u64 {
    u64::try_from(units.max(0))
        .unwrap_or(0)
        .saturating_mul(te.unit)
}

/// The WCETs (units) of control service `k`'s codels that the model runs
/// in no time (their locks are not contended: they never wait).
fn static_part(m: &Machine<'_>, te: &TimedEngine<'_>, k: usize) -> i64 {
    let sid = m.controls[k].service;
    let kept = te.jobs.get(&sid).cloned().unwrap_or_default();
    let ns: u64 = m
        .control_codels
        .get(&sid)
        .into_iter()
        .flatten()
        .enumerate()
        .filter(|(i, _)| !kept.contains(i))
        .map(|(_, s)| s.wcet_ns.unwrap_or(0))
        .sum();
    i64::try_from(ns / te.unit).unwrap_or(i64::MAX / 4)
}

/// A function's or attribute's worst case when no exploration measured it
/// (its codels never wait): the sum of its control codels' WCETs.
fn control_wcets(m: &Machine<'_>, sid: ServiceId) -> u64 {
    m.control_codels
        .get(&sid)
        .into_iter()
        .flatten()
        .map(|s| s.wcet_ns.unwrap_or(0))
        .sum()
}

/// An activity explored nowhere (its group was not reached).
fn undecided(service: ServiceId, stopped: Option<Stop>) -> ServiceResponse {
    ServiceResponse {
        service,
        worst: if stopped.is_some() {
            Worst::Incomplete
        } else {
            Worst::Never
        },
        exact: true,
        trace: None,
    }
}

/// An activity of an aperiodic task (see the module doc).
fn aperiodic(m: &Machine<'_>, a: usize) -> ServiceResponse {
    let fsm = &m.activities[a].fsm;
    let waits = fsm.states.iter().any(|s| {
        s.is_async
            || s.yields
                .iter()
                .any(|y| matches!(y, Target::State { pause: true, .. }))
    });
    let worst = if waits || (0..fsm.states.len()).any(|s| loops_from(m, Owner::Activity(a), s)) {
        Worst::Unbounded
    } else {
        Worst::Undecided("its task is aperiodic: the model does not time its activations")
    };
    ServiceResponse {
        service: m.activities[a].service,
        worst,
        exact: true,
        trace: None,
    }
}

/// Keeps the worse of two results for one service (controls are measured
/// in every group that contends their codels).
fn merge(results: &mut BTreeMap<ServiceId, ServiceResponse>, r: ServiceResponse) {
    let rank = |w: &Worst| match w {
        Worst::Never => (0, 0),
        Worst::Exact(n) => (1, *n),
        Worst::Above(n) => (2, *n),
        Worst::Unbounded => (3, 0),
        Worst::Undecided(_) => (4, 0),
        Worst::AtMost(n) => (5, *n),
        Worst::Incomplete => (6, 0),
    };
    match results.get(&r.service) {
        Some(old) if rank(&old.worst) >= rank(&r.worst) => {}
        _ => {
            results.insert(r.service, r);
        }
    }
}

/// Whether from state `s` of `owner`'s machine a cycle of its yields, or an
/// `async` codel, can be reached: the instance may then never end.
fn loops_from(m: &Machine<'_>, owner: Owner, s: usize) -> bool {
    let fsm = m.fsm(owner);
    let n = fsm.states.len();
    // Depth-first search with colours: grey on the stack, black done.
    let mut colour = vec![0u8; n];
    let mut stack = vec![(s, 0usize)];
    colour[s] = 1;
    while let Some(&mut (v, ref mut next)) = stack.last_mut() {
        if fsm.states[v].is_async {
            return true;
        }
        let succ = fsm.states[v].yields.iter().filter_map(|y| match y {
            Target::State { state, .. } => Some(usize::from(*state)),
            Target::Ether => None,
        });
        if let Some(w) = succ.clone().nth(*next) {
            *next += 1;
            match colour[w] {
                1 => return true,
                0 => {
                    colour[w] = 1;
                    stack.push((w, 0));
                }
                _ => {}
            }
        } else {
            colour[v] = 2;
            stack.pop();
        }
    }
    false
}

impl TimedEngine<'_> {
    /// Adds a response clock for each activity marked in `acts` and, with
    /// `ctl`, one for the control thread; compared from below only, with
    /// constants up to `horizon`.
    pub fn track_responses(&mut self, acts: &[bool], ctl: bool, horizon: i64) {
        self.coalesce = true;
        let m = &self.e.m;
        self.loops = (0..m.activities.len())
            .map(|a| {
                let n = m.activities[a].fsm.states.len();
                (0..n)
                    .map(|s| loops_from(m, Owner::Activity(a), s))
                    .collect()
            })
            .collect();
        self.resp = vec![None; self.e.m.activities.len()];
        for (a, _) in acts.iter().enumerate().filter(|(_, on)| **on) {
            self.bounds.push(Some(horizon));
            self.upper.push(None);
            self.resp[a] = Some(self.bounds.len());
        }
        if ctl {
            self.bounds.push(Some(horizon));
            self.upper.push(None);
            self.ctl_resp = Some(self.bounds.len());
        }
    }

    /// Resets the response clocks of what the transition from `before` to
    /// `n` started: an activity's instance accepted, a request taken by the
    /// control thread ([`TimedEngine::let_time_pass`] frees them).
    pub(crate) fn follow_responses(&self, before: &TG3State, n: &mut TG3State) {
        for (a, x) in self.resp.iter().enumerate() {
            if let Some(x) = *x {
                if before.g.inst[a].is_empty() && !n.g.inst[a].is_empty() {
                    n.zone.reset(x);
                }
            }
        }
        if let (Some(x), None, Some(_)) = (self.ctl_resp, before.ctl, n.ctl) {
            n.zone.reset(x);
        }
    }

    /// Frees the response clocks not read in `st`: no instance, or one that
    /// may never reply (its response is unbounded already, and a clock
    /// counting on would unroll its loop up to the horizon).
    pub(crate) fn free_responses(&self, st: &mut TG3State) {
        for (a, x) in self.resp.iter().enumerate() {
            if let Some(x) = *x {
                if st.g.inst[a].is_empty() || self.endless(&st.g, a) {
                    st.zone.free(x);
                }
            }
        }
        if let (Some(x), None) = (self.ctl_resp, st.ctl) {
            st.zone.free(x);
        }
    }

    /// Whether activity `a`'s instance in `g` may stay alive forever: its
    /// machine can loop or wait in an `async` codel from where it is (from
    /// `stop` once it is flagged), or it waits for interrupted instances
    /// that can.
    pub fn endless(&self, g: &G3State, a: usize) -> bool {
        let Some(&i) = g.inst[a].first() else {
            return false;
        };
        match i.status {
            Status::Ready => false,
            Status::Delayed => self.e.m.activities[a]
                .interrupts
                .iter()
                .any(|&t| t != a && g.inst[t].iter().any(|&j| self.inst_endless(t, j))),
            Status::Run | Status::Stop => self.inst_endless(a, i),
        }
    }

    fn inst_endless(&self, a: usize, i: Inst) -> bool {
        let m = &self.e.m;
        let owner = Owner::Activity(a);
        let s = usize::from(i.state);
        if i.status == Status::Run && i.has(mark::FLAGGED) {
            let stop = m.activities[a].fsm.stop;
            m.fsm(owner).states[s].is_async || stop.is_some_and(|t| self.loops(a, usize::from(t)))
        } else {
            i.status >= Status::Run && self.loops(a, s)
        }
    }

    /// [`loops_from`] for activity `a`'s state `s`, from the table when
    /// response clocks are tracked.
    fn loops(&self, a: usize, s: usize) -> bool {
        self.loops
            .get(a)
            .and_then(|v| v.get(s))
            .copied()
            .unwrap_or_else(|| loops_from(&self.e.m, Owner::Activity(a), s))
    }
}

/// A trace to an instance still without reply `d` ns after its
/// acknowledgment (or into what keeps it alive forever).
fn late_trace(
    te: &TimedEngine<'_>,
    e: &crate::kernel::explore::Exploration<super::TG3Action, crate::zones::dbm::Dbm>,
    seen: &Seen,
    (x, d, extra): (usize, u64, i64),
    name: &str,
) -> Option<Trace> {
    if let Some(id) = seen.endless {
        let last = TraceStep::new(
            Event::Violation,
            format!(
                "from here `{name}`'s instance can run forever without replying (its codels can loop, wait in an `async` codel, or wait for an interrupted instance that can)"
            ),
        );
        return Some(timed_trace_beyond(te, &e.path(te, id), last, None));
    }
    let units = (d / te.unit) as i64 - extra;
    let strict = d % te.unit == 0;
    for &id in &seen.late {
        let text = format!(
            "`{name}` still has not replied {} after its acknowledgment (its deadline)",
            format_ns(d)
        );
        let last = TraceStep::new(Event::Violation, text);
        let t = timed_trace_beyond(te, &e.path(te, id), last, Some((x, units, strict)));
        if t.steps.last().is_some_and(|s| s.time_ns.is_some()) {
            return Some(t);
        }
    }
    None
}
