//! An independent checker of timed traces, written from LANGUAGE.md
//! section 3 and the timing decisions of `docs/timing.md`, reading only the
//! component model (periods, WCETs, max-times, `next`, `on-inter`, the data
//! each codel uses) and the trace. It shares no code with the timed engine
//! (`genom_engine::timed`) nor with the untimed replay
//! ([`crate::replay`]), which checks the untimed rules of the same
//! trace (who may be requested, interrupted, started...): this one checks
//! the *timing* of each step.
//!
//! Rules checked step by step:
//!
//! - every step has `time_ns`; instants never decrease; the trace starts
//!   with the component at 0;
//! - a periodic thread wakes up at every multiple of its period, in order,
//!   and no wake-up is skipped: time never passes a thread's next wake-up
//!   instant without it;
//! - a codel starts on its service's thread, when that thread runs no other
//!   codel; on a periodic thread, only if its service was ready at the
//!   thread's last wake-up, at most once per service and period, and in
//!   acknowledgment order; never while a conflicting codel (same lockable
//!   structure, one of them writing) runs on another thread, the control
//!   thread included;
//! - a codel ends between its start and its start plus its WCET (no WCET:
//!   at its start instant); a control codel likewise, between the `request`
//!   step that runs it and its `accept` or `reject`;
//! - codel starts are urgent: time does not pass while a thread is free
//!   and the service at its turn could take its locks; and a new control
//!   codel does not take a lock that a thread at its turn wants;
//! - the watchdog of every service with `max-time` (looping or not) fires
//!   exactly max-time after the acknowledgment of the instance it
//!   interrupts, and time does not pass that deadline while the instance
//!   is still running uninterrupted (except at the violation of a max-time
//!   claim); an auto service's acknowledgment is its start, when
//!   initialisation completes; only a looping service whose max-time is
//!   beyond the exactly timed range (`Component::watchdog_instant_ns`)
//!   has its watchdog fire at any time from its horizon on;
//! - a wake-up that finds work of the previous period unfinished is an
//!   overrun, allowed only as the last step before an overrun violation.
//!
//! At the end, the claim: an overrun of a thread must be genuine (at the
//! wake-up some codel of the thread is running with time left before its
//! WCET, or a service is still to run one with a positive WCET or waits for
//! a lock that can be held past the wake-up); a max-time violation must be
//! strictly after the acknowledgment plus the max-time, with the instance
//! still running uninterrupted.

use std::collections::{BTreeMap, BTreeSet};

use genom_model::component::{CodelId, Component, Outcome, ServiceId, ThreadId};
use genom_model::kinds::CodelKind;
use genom_model::{Event, Trace, TraceStep};

/// What the end of a timed trace must show.
#[derive(Debug, Clone, Copy)]
pub enum TimedClaim<'a> {
    /// Nothing timed (a behavioural verdict's trace on a timed model).
    Rules,
    /// The named thread overruns at the last wake-up.
    Overrun(&'a str),
    /// The named service is still running, uninterrupted, strictly after
    /// its acknowledgment plus its max-time.
    LateService(&'a str),
    /// The named service has an instance (main or pending, active or
    /// stopping) that has not replied, strictly after its acknowledgment
    /// plus the given deadline in nanoseconds (`--deadline`).
    PastDeadline(&'a str, u64),
}

/// The facts read off a valid trace, for the tests' own assertions.
#[derive(Debug, Clone, Default)]
pub struct TimedEnd {
    /// Instant of the violation step.
    pub last_ns: u64,
    /// Wake-up instants of each thread, by name.
    pub wake_ups: BTreeMap<String, Vec<u64>>,
    /// Acknowledgment instant of the claimed late service's instance.
    pub late_ack_ns: Option<u64>,
    /// Codels run: (service, codel, start, end) with end `None` when still
    /// running at the end.
    pub codels: Vec<(String, String, u64, Option<u64>)>,
}

/// Where one service's main instance is, as far as timing is concerned.
#[derive(Debug, Clone, PartialEq)]
enum Main {
    Idle,
    /// Between codels, next at `codel`.
    Ready {
        codel: CodelId,
        stopping: bool,
    },
    /// Running `codel` since `since`.
    Running {
        codel: CodelId,
        since: u64,
        interrupted: bool,
        stopping: bool,
    },
}

#[derive(Debug, Clone)]
struct Svc {
    main: Main,
    /// Acknowledgment instant of the main instance.
    main_ack: Option<u64>,
    /// Acknowledgment instant of the pending instance, if any.
    pending_ack: Option<u64>,
    /// The codel the main instance ran last.
    last_ran: Option<CodelId>,
}

#[derive(Debug, Clone, Default)]
struct Thr {
    period: Option<u64>,
    /// Next wake-up instant (periodic threads).
    next_wake: u64,
    /// Step index of the last wake-up.
    /// Services to run in the current period and those that ran.
    eligible: BTreeSet<ServiceId>,
    ran: BTreeSet<ServiceId>,
    /// Services in acknowledgment order.
    order: Vec<ServiceId>,
    /// Work found unfinished at the last wake-up.
    overrun_at: Option<(usize, u64)>,
}

struct Checker<'c> {
    c: &'c Component,
    now: u64,
    svc: Vec<Svc>,
    threads: BTreeMap<ThreadId, Thr>,
    /// Running control codel: (service, start).
    control: Option<(ServiceId, u64)>,
    /// Instances that ended and owe a reply (service).
    owed: Vec<ServiceId>,
    end: TimedEnd,
    late_exempt: Option<ServiceId>,
}

/// Checks `trace` against the timing rules of `c`, then `claim`.
pub fn check_timed(
    c: &Component,
    trace: &Trace,
    claim: TimedClaim<'_>,
) -> Result<TimedEnd, String> {
    let late_exempt = match claim {
        TimedClaim::LateService(name) => Some(
            c.service_named(name)
                .ok_or_else(|| format!("no service `{name}`"))?,
        ),
        _ => None,
    };
    let mut ch = Checker {
        c,
        now: 0,
        svc: c
            .services
            .ids()
            .map(|_| Svc {
                main: Main::Idle,
                main_ack: None,
                pending_ack: None,
                last_ran: None,
            })
            .collect(),
        threads: BTreeMap::new(),
        control: None,
        owed: Vec::new(),
        end: TimedEnd::default(),
        late_exempt,
    };
    for (tid, t) in c.threads.iter() {
        if t.period.is_none() {
            ch.threads.insert(tid, Thr::default());
        }
    }
    let steps = &trace.steps;
    let first = steps.first().ok_or("empty trace")?;
    if first.event != Event::ComponentStart || first.time_ns != Some(0) {
        return Err("step 1: the trace starts with the component, at 0".to_owned());
    }
    let last = steps.len() - 1;
    if steps[last].event != Event::Violation {
        return Err("the last step is the violation".to_owned());
    }
    for (k, step) in steps.iter().enumerate().skip(1) {
        let t = step
            .time_ns
            .ok_or_else(|| format!("step {}: no `time_ns`", k + 1))?;
        ch.step(k, step, t, k == last)
            .map_err(|e| format!("step {} ({}): {e}", k + 1, describe(step)))?;
    }
    ch.end.last_ns = ch.now;
    ch.claim(claim, steps)?;
    Ok(ch.end)
}

fn describe(s: &TraceStep) -> String {
    let mut out = s.event.as_str().to_owned();
    if let Some(t) = &s.thread {
        out.push_str(&format!(" [{t}]"));
    }
    match (&s.service, &s.codel) {
        (Some(svc), Some(k)) => out.push_str(&format!(" {svc}::{k}")),
        (Some(svc), None) => out.push_str(&format!(" {svc}")),
        _ => {}
    }
    if let Some(o) = &s.outcome {
        out.push_str(&format!(" -> {o}"));
    }
    if let Some(t) = s.time_ns {
        out.push_str(&format!(" @{t}ns"));
    }
    out
}

/// Whether the codels of service `s` can loop without bound: a cycle of
/// `next` edges between start and exec codels reachable from the start
/// codel.
pub fn loops_without_bound(c: &Component, s: ServiceId) -> bool {
    let Some(start) = c.services[s].start else {
        return false;
    };
    let succ = |k: CodelId| -> Vec<CodelId> {
        c.codels[k]
            .outcomes()
            .into_iter()
            .filter_map(|o| match o {
                Outcome::Codel(n) if c.codels[n].kind != CodelKind::Inter => Some(n),
                _ => None,
            })
            .collect()
    };
    // Depth-first search for a back edge.
    fn dfs(
        k: CodelId,
        succ: &dyn Fn(CodelId) -> Vec<CodelId>,
        on_path: &mut Vec<CodelId>,
        done: &mut BTreeSet<CodelId>,
    ) -> bool {
        if on_path.contains(&k) {
            return true;
        }
        if !done.insert(k) {
            return false;
        }
        on_path.push(k);
        let found = succ(k).into_iter().any(|n| dfs(n, succ, on_path, done));
        on_path.pop();
        found
    }
    dfs(start, &succ, &mut Vec::new(), &mut BTreeSet::new())
}

/// When the watchdog of `s` fires after the acknowledgment, and whether
/// exactly then (docs/semantics.md, "Watchdogs of looping services": a
/// looping service whose max-time is far beyond the periods and WCETs of
/// the services it is explored with fires at any time from a horizon on).
fn watchdog_instant(c: &Component, s: ServiceId) -> (u64, bool) {
    let mut members = c
        .timed_clusters()
        .into_iter()
        .find(|m| m.contains(&s))
        .unwrap_or_default();
    if let Some(i) = c.init_service().filter(|i| !members.contains(i)) {
        members.push(i);
    }
    c.watchdog_instant_ns(s, loops_without_bound(c, s), &members)
}

/// Whether `s` is an auto service.
fn is_auto(c: &Component, s: ServiceId) -> bool {
    c.services[s].kind == genom_model::kinds::ServiceKind::Auto
}

fn wcet(c: &Component, k: CodelId) -> u64 {
    c.codels[k].wcet.map_or(0, |w| w.ns)
}

impl Checker<'_> {
    fn service(&self, step: &TraceStep) -> Result<ServiceId, String> {
        let name = step.service.as_deref().ok_or("no service")?;
        self.c
            .service_named(name)
            .ok_or_else(|| format!("no service `{name}`"))
    }

    fn codel(&self, s: ServiceId, step: &TraceStep) -> Result<Option<CodelId>, String> {
        step.codel
            .as_deref()
            .map(|n| {
                self.c
                    .codel_named(s, n)
                    .ok_or_else(|| format!("no codel `{n}`"))
            })
            .transpose()
    }

    fn thread_of(&self, s: ServiceId) -> Option<ThreadId> {
        self.c.services[s].thread.map(|t| t.id)
    }

    fn running_on(&self, t: ThreadId) -> Option<(ServiceId, CodelId, u64)> {
        self.c
            .services
            .ids()
            .find_map(|s| match self.svc[s.0 as usize].main {
                Main::Running { codel, since, .. } if self.thread_of(s) == Some(t) => {
                    Some((s, codel, since))
                }
                _ => None,
            })
    }

    /// Codels running on threads other than `t`.
    fn running_elsewhere(&self, t: ThreadId) -> Vec<(ServiceId, CodelId, u64)> {
        self.c
            .services
            .ids()
            .filter_map(|s| match self.svc[s.0 as usize].main {
                Main::Running { codel, since, .. } if self.thread_of(s) != Some(t) => {
                    Some((s, codel, since))
                }
                _ => None,
            })
            .collect()
    }

    /// A running codel (of another thread, or the control codel) that
    /// conflicts with `k` on thread `t`.
    fn lock_holder(&self, t: ThreadId, k: CodelId) -> Option<String> {
        if let Some((_, codel, _)) = self
            .running_elsewhere(t)
            .into_iter()
            .find(|&(_, codel, _)| self.c.conflicts(k, codel))
        {
            return Some(self.c.codel_label(codel));
        }
        let (r, _) = self.control?;
        let ctl = self.c.services[r].control?;
        self.c.conflicts(k, ctl).then(|| self.c.codel_label(ctl))
    }

    fn ready_codel(&self, s: ServiceId) -> Option<CodelId> {
        match self.svc[s.0 as usize].main {
            Main::Ready { codel, .. } => Some(codel),
            _ => None,
        }
    }

    /// The service at its turn on thread `t`, if the thread is free.
    fn turn(&self, t: ThreadId) -> Option<ServiceId> {
        let th = self.threads.get(&t)?;
        if self.running_on(t).is_some() {
            return None;
        }
        th.order
            .iter()
            .copied()
            .find(|s| th.eligible.contains(s) && !th.ran.contains(s))
    }

    /// Time passes from `self.now` to `t`: check that nothing had to happen
    /// before.
    fn advance(&mut self, t: u64, is_violation: bool) -> Result<(), String> {
        if t < self.now {
            return Err(format!("time goes backwards from {} ns", self.now));
        }
        if t == self.now {
            return Ok(());
        }
        for (&tid, th) in &self.threads {
            let name = &self.c.threads[tid].name.name;
            if th.period.is_some() && th.next_wake < t {
                return Err(format!(
                    "thread `{name}` should have woken up at {} ns",
                    th.next_wake
                ));
            }
            // Urgency.
            if let Some(s) = self.turn(tid) {
                if let Some(k) = self.ready_codel(s) {
                    if self.lock_holder(tid, k).is_none() {
                        return Err(format!(
                            "time passes from {} ns while thread `{name}` is free and `{}` is at its turn with its locks free",
                            self.now,
                            self.c.codel_label(k)
                        ));
                    }
                }
            }
            if th.period.is_none() {
                let ready: Vec<CodelId> = self
                    .c
                    .services
                    .ids()
                    .filter(|&s| self.thread_of(s) == Some(tid))
                    .filter_map(|s| self.ready_codel(s))
                    .collect();
                if self.running_on(tid).is_none()
                    && !ready.is_empty()
                    && ready.iter().all(|&k| self.lock_holder(tid, k).is_none())
                {
                    return Err(format!(
                        "time passes while the aperiodic thread `{name}` is free with codels ready"
                    ));
                }
            }
        }
        for s in self.c.services.ids() {
            let v = &self.svc[s.0 as usize];
            if let Main::Running { codel, since, .. } = v.main {
                if t - since > wcet(self.c, codel) {
                    return Err(format!(
                        "`{}` started at {since} ns must have ended by {} ns (WCET)",
                        self.c.codel_label(codel),
                        since + wcet(self.c, codel)
                    ));
                }
            }
            let svc = &self.c.services[s];
            let Some(m) = svc.max_time.map(|m| m.ns) else {
                continue;
            };
            if (is_violation && self.late_exempt == Some(s)) || !watchdog_instant(self.c, s).1 {
                continue;
            }
            let watchable = match v.main {
                Main::Ready { stopping, .. } => !stopping,
                Main::Running {
                    interrupted,
                    stopping,
                    ..
                } => !interrupted && !stopping,
                Main::Idle => false,
            };
            for ack in [v.main_ack.filter(|_| watchable), v.pending_ack]
                .into_iter()
                .flatten()
            {
                if t > ack + m {
                    return Err(format!(
                        "time passes {} ns, the deadline of `{}` acknowledged at {ack} ns, without its watchdog",
                        ack + m,
                        svc.name.name
                    ));
                }
            }
        }
        if let Some((r, since)) = self.control {
            let w = self.c.services[r].control.map_or(0, |k| wcet(self.c, k));
            if t - since > w {
                return Err(format!(
                    "the control codel of `{}` started at {since} ns must have ended by {} ns",
                    self.c.services[r].name.name,
                    since + w
                ));
            }
        }
        self.now = t;
        Ok(())
    }
}

mod claim;
mod steps;
