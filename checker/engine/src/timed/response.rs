//! Worst-case response times of the LANGUAGE.md dialect, computed exactly
//! by the zone engine: each timed exploration (a timed cluster, with the
//! init service when it is not a member) is explored once more with a
//! *response clock* per member and instance slot, reset when an instance
//! is acknowledged and freed when it has replied. The worst case of a
//! service is the supremum of its response clock over the reachable
//! symbolic states where an instance has not replied yet: an instance
//! alive at `r` replies at `r` or later (or never), and the reply itself
//! takes no time. Response clocks are compared from below with constants
//! up to a horizon `H` (their LU bound), which keeps that supremum exact
//! up to `H` through extrapolation; beyond it, only "more than `H`" is
//! known, unless an execution provably never replies (`unbounded`: see
//! [`Forever`]). Deadlines are decided on the same exploration, with a
//! timed trace to an instance still alive past its deadline.

use std::collections::BTreeMap;

use genom_model::behaviour::Behaviour;
use genom_model::component::{Component, ServiceId};
use genom_model::trace::{Event, Trace, TraceStep};

use super::analysis::timed_explorations;
use super::model::{Forever, TimedSystem};
use super::trace::{Target, timed_lasso, timed_trace};
use crate::kernel::explore::{Limits, explore};
use crate::kernel::store::StateId;
use crate::zones::dbm::{INF, constant, lt};

/// How many states may be tried for a deadline trace before giving up on
/// one (a stored zone can be larger than the exact zone of its own path).
const TRACE_CANDIDATES: usize = 16;

/// What one exploration found about a service's response time.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Worst {
    /// The supremum, in nanoseconds.
    Exact(u64),
    /// More than this many nanoseconds (the horizon).
    Above(u64),
    /// Some execution never replies.
    Unbounded,
    /// The exploration stopped on a limit.
    Incomplete,
    /// The exploration stopped on a limit, but a static bound holds: at
    /// most this many nanoseconds (GenoM3's functions and attributes,
    /// docs/genom3-semantics.md 16.8).
    AtMost(u64),
    /// No execution acknowledges the service.
    Never,
    /// The model cannot decide it, for this reason (GenoM3: an aperiodic
    /// task's activations are not timed; a task of the group overruns).
    Undecided(&'static str),
}

/// The response time of one service.
#[derive(Debug, Clone)]
pub struct ServiceResponse {
    /// The service.
    pub service: ServiceId,
    /// Its worst case in the timed model.
    pub worst: Worst,
    /// Whether the model is exact for it: `false` when a watchdog of its
    /// exploration is timed approximately (docs/semantics.md, "Watchdogs of
    /// looping services"), so that the model has more executions than the
    /// component.
    pub exact: bool,
    /// With a deadline that some execution misses: a trace where the
    /// instance has not replied when the deadline passes (or never replies).
    pub trace: Option<Trace>,
}

/// Per tracked member, what the visits found.
#[derive(Default, Clone)]
struct Seen {
    acknowledged: bool,
    sup: i64,
    above: bool,
    forever: Option<(StateId, Forever)>,
    late: Vec<(StateId, usize)>,
}

/// The response time of every service of `c` (in service order), with
/// `deadlines` (nanoseconds, by service) decided and traced.
pub fn response_times(
    c: &Component,
    limits: Limits,
    deadlines: &BTreeMap<ServiceId, u64>,
) -> Vec<ServiceResponse> {
    let b = Behaviour::new(c);
    let mut out = Vec::new();
    let mut budget = limits;
    for (members, frozen) in timed_explorations(c) {
        let init = c.init_service().filter(|_| frozen);
        let tracked: Vec<ServiceId> = members
            .iter()
            .copied()
            .filter(|&s| Some(s) != init)
            .collect();
        out.extend(explore_cluster(
            c,
            &b,
            &members,
            frozen,
            &tracked,
            &mut budget,
            deadlines,
        ));
    }
    out.sort_by_key(|r| r.service);
    out
}

/// The horizon of an exploration, in units: twice the sum of the members'
/// max-times and of one longest period or WCET per codel (control codels
/// included) and per member, times the number of members; at least twice
/// every deadline. A response time up to it is exact.
fn horizon(ts: &TimedSystem<'_>, members: &[ServiceId], deadlines: &[Option<i64>]) -> i64 {
    let c = ts.sys.component();
    let unit = ts.unit;
    let mut longest = 1i64;
    let mut steps = 0i64;
    let mut max_times = 0i64;
    for &s in members {
        let svc = &c.services[s];
        if let Some(p) = svc.thread.and_then(|t| c.threads[t.id].period) {
            longest = longest.max(super::clocks::units(p.ns, unit));
        }
        for &k in svc.codels.iter().chain(&svc.control) {
            if let Some(w) = c.codels[k].wcet {
                longest = longest.max(super::clocks::units(w.ns, unit));
            }
        }
        steps = steps.saturating_add(1 + i64::try_from(svc.codels.len()).unwrap_or(i64::MAX / 4));
        if let Some(m) = svc.max_time {
            max_times =
                max_times.saturating_add(i64::try_from(m.ns / unit).unwrap_or(i64::MAX / 4));
        }
    }
    let n = i64::try_from(members.len()).unwrap_or(1).max(1);
    let h = steps
        .saturating_mul(longest)
        .saturating_mul(n)
        .saturating_add(max_times)
        .saturating_mul(2);
    let d = deadlines.iter().flatten().copied().max().unwrap_or(0);
    // Constants stay far from i64's end: zone sums must not overflow.
    h.max(d.saturating_add(1).saturating_mul(2))
        .clamp(1, i64::MAX / 16)
}

fn explore_cluster(
    c: &Component,
    b: &Behaviour,
    members: &[ServiceId],
    frozen: bool,
    tracked: &[ServiceId],
    budget: &mut Limits,
    deadlines: &BTreeMap<ServiceId, u64>,
) -> Vec<ServiceResponse> {
    let mut ts = TimedSystem::new(c, b, members, frozen);
    let n = ts.sys.len();
    let is_tracked: Vec<bool> = (0..n)
        .map(|i| tracked.contains(&ts.sys.service(i)))
        .collect();
    // A deadline `D` ns is missed when the response clock exceeds `⌊D/u⌋`
    // units (zone bounds are whole units).
    let deadline: Vec<Option<i64>> = (0..n)
        .map(|i| {
            deadlines
                .get(&ts.sys.service(i))
                .map(|&d| i64::try_from(d / ts.unit).unwrap_or(i64::MAX / 16))
        })
        .collect();
    let h = horizon(&ts, members, &deadline);
    ts.track_responses(&is_tracked, h);
    let exact = ts.watch_exact.iter().all(|&e| e);
    let past_deadline = std::time::Instant::now();
    if budget.deadline.is_some_and(|d| past_deadline >= d) {
        return incomplete(&ts, &is_tracked, exact);
    }
    let mut seen = vec![Seen::default(); n];
    let e = explore(&ts, *budget, |id, st| {
        for i in (0..n).filter(|&i| is_tracked[i]) {
            // A service without start codel that may be requested here
            // completes at once (unless delayed: then it is seen pending).
            if ts.sys.machine_of(i).start.is_none() && ts.sys.request_enabled(&st.cfg, i) {
                seen[i].acknowledged = true;
            }
            let live = ts.live_responses(&st.cfg, i);
            if live.is_empty() {
                continue;
            }
            let s = &mut seen[i];
            s.acknowledged = true;
            let forever = ts.never_replies(st, i);
            if s.forever.is_none() {
                s.forever = forever.map(|f| (id, f));
            }
            // An instance that may never reply has its response clock
            // freed: nothing to read.
            if forever.is_some() {
                continue;
            }
            for r in live {
                let ub = st.zone.get(r, 0);
                if ub == INF || constant(ub) > h {
                    s.above = true;
                } else {
                    s.sup = s.sup.max(constant(ub));
                }
                if let Some(d) = deadline[i] {
                    if s.late.len() < TRACE_CANDIDATES && st.zone.intersects(0, r, lt(-d)) {
                        s.late.push((id, r));
                    }
                }
            }
        }
    });
    budget.max_states = budget.max_states.saturating_sub(e.store.len()).max(1);
    if e.stopped.is_some() {
        return incomplete(&ts, &is_tracked, exact);
    }
    let mut out = Vec::new();
    for i in (0..n).filter(|&i| is_tracked[i]) {
        let s = &seen[i];
        let service = ts.sys.service(i);
        let worst = if !s.acknowledged {
            Worst::Never
        } else if s.forever.is_some() {
            Worst::Unbounded
        } else if s.above {
            Worst::Above(u64::try_from(h).unwrap_or(0).saturating_mul(ts.unit))
        } else {
            Worst::Exact(u64::try_from(s.sup).unwrap_or(0).saturating_mul(ts.unit))
        };
        let trace = deadline[i].and_then(|d| {
            let missed = match worst {
                Worst::Unbounded | Worst::Above(_) => true,
                Worst::Exact(ns) => deadlines.get(&service).is_some_and(|&dl| ns > dl),
                Worst::Incomplete | Worst::AtMost(_) | Worst::Never | Worst::Undecided(_) => false,
            };
            let shown = deadlines.get(&service).copied().unwrap_or(0);
            missed
                .then(|| late_trace(&ts, &e, (i, s), d, shown))
                .flatten()
        });
        out.push(ServiceResponse {
            service,
            worst,
            exact,
            trace,
        });
    }
    out
}

fn incomplete(ts: &TimedSystem<'_>, tracked: &[bool], exact: bool) -> Vec<ServiceResponse> {
    (0..ts.sys.len())
        .filter(|&i| tracked[i])
        .map(|i| ServiceResponse {
            service: ts.sys.service(i),
            worst: Worst::Incomplete,
            exact,
            trace: None,
        })
        .collect()
}

/// A trace where member `i`'s instance has not replied `d` units after its
/// acknowledgment: to a state past the deadline, or, when it never
/// replies, into the loop that keeps it alive (or past the deadline in a
/// state where nothing more has to happen).
fn late_trace(
    ts: &TimedSystem<'_>,
    e: &crate::kernel::explore::Exploration<super::model::TAction, crate::zones::dbm::Dbm>,
    (i, seen): (usize, &Seen),
    d: i64,
    deadline_ns: u64,
) -> Option<Trace> {
    let c = ts.sys.component();
    let name = &c.services[ts.sys.service(i)].name.name;
    let after = genom_model::duration::format_ns(deadline_ns);
    let timed_ok = |t: &Trace| t.steps.last().is_some_and(|s| s.time_ns.is_some());
    for &(id, clock) in &seen.late {
        let text = format!("`{name}` has not replied {after} after its acknowledgment");
        let step = TraceStep::new(Event::Violation, text);
        let trace = timed_trace(
            ts,
            &e.store.path(id),
            Target::Late { clock, after: d },
            step,
        );
        if timed_ok(&trace) {
            return Some(trace);
        }
    }
    let (id, why) = seen.forever?;
    let path = e.store.path(id);
    match why {
        Forever::Loops(t) => {
            let looping = &c.services[ts.sys.service(t)].name.name;
            let text = if t == i {
                format!("`{name}` never replies: its codels may loop forever")
            } else {
                format!(
                    "`{name}` never replies: it waits for `{looping}`, whose codels may loop forever"
                )
            };
            Some(timed_lasso(
                ts,
                &path,
                t,
                TraceStep::new(Event::Violation, text),
            ))
        }
        Forever::Blocked => {
            let text = format!(
                "`{name}` never replies: it is pending and nothing more happens without a new request"
            );
            let step = TraceStep::new(Event::Violation, text);
            Some(timed_trace(ts, &path, Target::Any, step))
        }
    }
}
