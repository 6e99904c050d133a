//! The timed semantics of LANGUAGE.md section 3: the untimed semantics of
//! [`System`] (which alone defines requests, codel outcomes, interrupts and
//! starts) plus time:
//!
//! - a periodic thread wakes up at every multiple of its period and runs, in
//!   acknowledgment order, one codel of each service that was active at the
//!   wake-up; a wake-up with codels of the previous period unfinished is a
//!   *thread overrun* (a terminal violation state), but only where that
//!   work needs time beyond the wake-up instant: codel ends and zero-time
//!   steps at the wake-up instant come first (a codel ending exactly at the
//!   wake-up is in time);
//! - an aperiodic thread runs rounds back to back, one codel per active
//!   service per round;
//! - a codel takes between 0 and its WCET (0 without one); a thread starts
//!   its next codel as soon as it may (urgent) — it only waits for locks;
//! - locks: a codel starts only when no running codel of another thread
//!   (the control thread included) conflicts with it; a thread waiting for
//!   a lock gets it before the control thread takes it for a new request;
//! - a control codel takes between 0 and its WCET on the control thread,
//!   which handles one request at a time; requests arrive at any time;
//! - a service with `max-time` is interrupted by its watchdog when its
//!   instance is still active (or pending) `max-time` after acknowledgment.
//!
//! A symbolic state is the discrete state plus a clock zone.

mod response;
mod steps;

use genom_model::behaviour::{Behaviour, IDLE, Position};
use genom_model::component::{CodelId, Component, ServiceId, ThreadId};
use genom_model::trace::TraceStep;

pub use response::Forever;

use super::clocks::{ClockRole, Clocks, unit_ns, units};
use crate::dialect::system::{Action, Config, System, conflict};
use crate::kernel::explore::Model;
use crate::kernel::store::Subsumes;
use crate::zones::dbm::Dbm;

impl Subsumes for Dbm {
    fn subsumed_by(&self, other: &Dbm) -> bool {
        self.included_in(other)
    }

    fn heap_bytes(&self) -> usize {
        self.heap_bytes()
    }
}

/// A transition of the timed model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TAction {
    /// An untimed step of a service (request without control codel, codel
    /// begin and finish, watchdog).
    Step(Action),
    /// A request whose control codel starts running on the control thread.
    RequestBegin(ServiceId),
    /// The control codel of the running request finishes: accept or reject.
    RequestEnd(ServiceId, bool),
    /// A periodic thread wakes up (index among the model's threads).
    WakeUp(u16),
    /// An aperiodic thread starts a new round.
    Round(u16),
}

/// A thread of the model.
#[derive(Debug, Clone)]
pub struct TThread {
    /// The thread.
    pub id: ThreadId,
    /// Its period in units (`None`: aperiodic).
    pub period: Option<i64>,
    /// Member indices of the services it runs, by slot.
    pub members: Vec<usize>,
    /// Clock of the period (periodic threads).
    pub period_clock: Option<usize>,
    /// Clock of the running codel.
    pub exec_clock: usize,
}

/// What a transition did to one member's instances.
#[derive(Debug, Clone, Copy)]
struct Change {
    /// A new instance was acknowledged.
    acked: bool,
    /// A pending instance became the main instance.
    started: bool,
    /// The main instance ended (or was replaced).
    ended: bool,
}

/// A terminal violation found by the model itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Violation {
    /// A thread woke up with codels of the previous period unfinished.
    Overrun(u16),
}

/// A symbolic state.
#[derive(Debug, Clone, PartialEq)]
pub struct TState {
    /// The untimed configuration.
    pub cfg: Config,
    /// Per thread: slots that still run a codel in the current period.
    pub eligible: Vec<u64>,
    /// Per thread: slots with an instance, in acknowledgment order.
    pub order: Vec<Vec<u8>>,
    /// The member whose control codel runs, if any.
    pub ctl: Option<u16>,
    /// A violation reached (terminal).
    pub violation: Option<Violation>,
    /// The clock zone.
    pub zone: Dbm,
}

/// The timed model of a set of member services.
#[derive(Debug)]
pub struct TimedSystem<'a> {
    /// The untimed semantics.
    pub sys: System<'a>,
    c: &'a Component,
    /// Nanoseconds per model unit.
    pub unit: u64,
    /// The threads of the members.
    pub threads: Vec<TThread>,
    /// Per member: its thread (index in `threads`) and slot.
    placement: Vec<Option<(usize, usize)>>,
    /// WCET of each codel of the component, in units (0 without one).
    wcet: Vec<i64>,
    /// Per member: max-time in units.
    pub max_time: Vec<Option<i64>>,
    /// Per member: control codel WCET in units, when it has a control codel.
    ctl_wcet: Vec<Option<i64>>,
    /// Per member: watchdog clock of the main instance (and of the pending
    /// one for self-stopping services).
    pub watch: Vec<Option<(usize, usize)>>,
    /// Per member: its watchdog fires exactly at its max-time (else at any
    /// time from `max_time`, the horizon, on).
    pub watch_exact: Vec<bool>,
    /// Per member: response clocks of its main (and pending) instance,
    /// when its response time is measured ([`TimedSystem::track_responses`]).
    pub response: Vec<Option<(usize, usize)>>,
    /// Clock of the control codel.
    ctl_clock: usize,
    /// The clocks.
    pub clocks: Clocks,
    /// The init service's member index, frozen once initialisation is done
    /// (it is only there for the pre-init phase of this cluster).
    frozen: Option<usize>,
    /// Apply LU extrapolation (always, except to measure its effect).
    pub extrapolate: bool,
    width: usize,
}

impl<'a> TimedSystem<'a> {
    /// The timed model of `members`; `frozen_init` freezes the init service
    /// once it has completed (when it is only in the cluster for the
    /// pre-init phase).
    pub fn new(
        c: &'a Component,
        b: &'a Behaviour,
        members: &[ServiceId],
        frozen_init: bool,
    ) -> Self {
        let sys = System::new(c, b, members, false);
        let unit = unit_ns(c, members);
        let wcet: Vec<i64> = c
            .codels
            .values()
            .map(|k| k.wcet.map_or(0, |w| units(w.ns, unit)))
            .collect();
        let mut clocks = Clocks::default();
        let threads = threads(c, &sys, unit, &mut clocks);
        let mut placement = vec![None; sys.len()];
        for (k, t) in threads.iter().enumerate() {
            for (slot, &i) in t.members.iter().enumerate() {
                placement[i] = Some((k, slot));
            }
        }
        let ctl_clock = clocks.add(ClockRole::Exec(None), None, None);
        // Every service with a max-time has a watchdog clock, looping ones
        // included: the watchdog fires exactly max-time after the
        // acknowledgment; only a looping service whose max-time is beyond
        // the horizon has its watchdog fire at any time from the horizon on
        // (docs/semantics.md, "Watchdogs of looping services").
        let instants: Vec<Option<(u64, bool)>> = (0..sys.len())
            .map(|i| {
                let s = sys.service(i);
                c.services[s].max_time?;
                Some(c.watchdog_instant_ns(s, sys.machine_of(i).active_loop, members))
            })
            .collect();
        let watch_exact: Vec<bool> = instants.iter().map(|x| x.is_none_or(|(_, e)| e)).collect();
        let max_time: Vec<Option<i64>> = instants
            .iter()
            .map(|x| x.map(|(ns, _)| units(ns, unit)))
            .collect();
        let watch = watch_clocks(c, &sys, &max_time, &watch_exact, &mut clocks);
        let ctl_wcet = (0..sys.len())
            .map(|i| {
                c.services[sys.service(i)]
                    .control
                    .map(|k| c.codels[k].wcet.map_or(0, |w| units(w.ns, unit)))
            })
            .collect::<Vec<_>>();
        bound_exec_clocks(c, &sys, &threads, &ctl_wcet, &wcet, ctl_clock, &mut clocks);
        let frozen = c
            .init_service()
            .and_then(|s| sys.member_index(s))
            .filter(|_| frozen_init);
        let width = sys.width()
            + threads
                .iter()
                .map(|t| 1 + order_words(t.members.len()))
                .sum::<usize>()
            + 1;
        let members_len = sys.len();
        TimedSystem {
            sys,
            c,
            unit,
            threads,
            placement,
            wcet,
            max_time,
            ctl_wcet,
            watch,
            watch_exact,
            response: vec![None; members_len],
            ctl_clock,
            clocks,
            frozen,
            extrapolate: true,
            width,
        }
    }

    /// Number of clocks.
    pub fn clock_count(&self) -> usize {
        self.clocks.len()
    }

    /// The codel thread `k` runs, if any.
    pub fn running_on(&self, st: &TState, k: usize) -> Option<CodelId> {
        self.threads[k]
            .members
            .iter()
            .find_map(|&i| self.running_codel(&st.cfg, i))
    }

    fn thread_busy(&self, st: &TState, k: usize) -> bool {
        self.threads[k]
            .members
            .iter()
            .any(|&i| self.sys.position(&st.cfg, i).is_running())
    }

    fn active_ready(&self, cfg: &Config, i: usize) -> bool {
        matches!(
            self.sys.position(cfg, i),
            Position::Ready { .. } | Position::StopReady { .. }
        )
    }

    /// The member whose turn it is on thread `k`: the first eligible slot
    /// in acknowledgment order.
    fn turn(&self, st: &TState, k: usize) -> Option<usize> {
        st.order[k]
            .iter()
            .map(|&slot| usize::from(slot))
            .find(|&slot| st.eligible[k] & (1 << slot) != 0)
            .map(|slot| self.threads[k].members[slot])
    }

    /// Member `i` may begin its next codel now.
    fn may_begin(&self, st: &TState, i: usize) -> bool {
        let Some((k, _)) = self.placement[i] else {
            return false;
        };
        let Some(codel) = self.sys.position(&st.cfg, i).codel() else {
            return false;
        };
        !self.thread_busy(st, k)
            && self.active_ready(&st.cfg, i)
            && self.turn(st, k) == Some(i)
            && self.sys.can_begin(&st.cfg, i, codel)
            && !self.control_conflicts(st, self.sys.codel_uses(codel))
    }

    fn control_conflicts(
        &self,
        st: &TState,
        uses: &[(genom_model::component::StructureId, bool)],
    ) -> bool {
        st.ctl
            .is_some_and(|r| conflict(uses, self.sys.control_uses(usize::from(r))))
    }

    /// Some thread is at its turn, idle, and wants a lock the control codel
    /// of member `i` would take: it gets the lock first (locks are granted
    /// in request order, and a thread is ready before a request arriving
    /// at the same instant).
    fn thread_waits_for(&self, st: &TState, i: usize) -> bool {
        (0..self.threads.len()).any(|k| {
            let Some(j) = self.turn(st, k).filter(|_| !self.thread_busy(st, k)) else {
                return false;
            };
            let Some(codel) = self.sys.position(&st.cfg, j).codel() else {
                return false;
            };
            conflict(self.sys.codel_uses(codel), self.sys.control_uses(i))
        })
    }

    /// Whether time must not pass in this state: a thread may begin a codel
    /// or an aperiodic thread may start a round.
    pub fn urgent(&self, st: &TState) -> bool {
        (0..self.sys.len()).any(|i| self.may_begin(st, i))
            || (0..self.threads.len()).any(|k| self.round_enabled(st, k))
    }

    fn round_enabled(&self, st: &TState, k: usize) -> bool {
        self.threads[k].period.is_none()
            && st.eligible[k] == 0
            && !self.thread_busy(st, k)
            && self.threads[k]
                .members
                .iter()
                .any(|&i| self.active_ready(&st.cfg, i))
    }

    fn request_open(&self, st: &TState, i: usize) -> bool {
        st.ctl.is_none()
            && !(self.frozen == Some(i) && st.cfg.init_done)
            && self.sys.request_enabled(&st.cfg, i)
    }

    /// The invariants of a discrete state, as constraints `x ≤ c`, leaving
    /// out the watchdog invariant of member `except`.
    pub fn invariants(&self, st: &TState, except: Option<usize>) -> Vec<(usize, i64)> {
        let mut out = Vec::new();
        for t in &self.threads {
            if let (Some(p), Some(x)) = (t.period, t.period_clock) {
                out.push((x, p));
            }
            if let Some(codel) = t
                .members
                .iter()
                .find_map(|&i| self.running_codel(&st.cfg, i))
            {
                out.push((t.exec_clock, self.wcet[codel.0 as usize]));
            }
        }
        if let Some(r) = st.ctl {
            out.push((self.ctl_clock, self.ctl_wcet[usize::from(r)].unwrap_or(0)));
        }
        for i in (0..self.sys.len()).filter(|&i| Some(i) != except) {
            out.extend(self.watch_invariants(&st.cfg, i));
        }
        out
    }

    fn watch_invariants(&self, cfg: &Config, i: usize) -> Vec<(usize, i64)> {
        let (Some((main, pend)), Some(m), true) =
            (self.watch[i], self.max_time[i], self.watch_exact[i])
        else {
            return Vec::new();
        };
        let mut out = Vec::new();
        if self.watchable(cfg, i) {
            out.push((main, m));
        }
        if cfg.pending[i].is_some() {
            out.push((if cfg.main[i] == IDLE { main } else { pend }, m));
        }
        out
    }

    /// The main instance of member `i` is alive and can still be
    /// interrupted by its watchdog.
    pub fn watchable(&self, cfg: &Config, i: usize) -> bool {
        cfg.main[i] != IDLE && self.sys.machine_of(i).interrupt[usize::from(cfg.main[i])].is_some()
    }

    fn running_codel(&self, cfg: &Config, i: usize) -> Option<CodelId> {
        let p = self.sys.position(cfg, i);
        p.codel().filter(|_| p.is_running())
    }

    /// The initial symbolic state: everything at 0, autos acknowledged when
    /// there is no init service, then time passes.
    pub fn initial_state(&self, events: &mut Option<&mut Vec<TraceStep>>) -> TState {
        self.start(0, self.extrapolate, events)
    }

    /// The initial state without extrapolation.
    pub fn initial_exact(&self) -> TState {
        self.start(0, false, &mut None)
    }

    /// The initial state with `extra` more clocks (all 0 at the start, then
    /// running), extrapolated or not.
    pub fn start(
        &self,
        extra: usize,
        extrapolate: bool,
        events: &mut Option<&mut Vec<TraceStep>>,
    ) -> TState {
        let cfg = self.sys.initial(false, events);
        let k = self.threads.len();
        let zone = Dbm::zero(self.clock_count() + extra);
        let mut st = TState {
            cfg,
            eligible: vec![0; k],
            order: vec![Vec::new(); k],
            ctl: None,
            violation: None,
            zone,
        };
        let n = self.sys.len();
        let before = Config {
            init_done: st.cfg.init_done,
            main: vec![IDLE; n],
            pending: vec![None; n],
            timed_out: vec![false; n],
        };
        self.bookkeep(&before, &mut st, None, true);
        for t in 0..k {
            if self.threads[t].period.is_some() {
                self.emit_wake(events, t);
                self.wake(&mut st, t);
            }
        }
        self.settle_with(st, extrapolate)
    }
}

/// Words holding the acknowledgment order of `slots` slots (7 bits each,
/// 9 per word).
fn order_words(slots: usize) -> usize {
    slots.div_ceil(9).max(1)
}

/// The threads of the members, with their clocks.
fn threads(c: &Component, sys: &System<'_>, unit: u64, clocks: &mut Clocks) -> Vec<TThread> {
    let mut out: Vec<TThread> = Vec::new();
    for i in 0..sys.len() {
        let Some(t) = c.services[sys.service(i)].thread.map(|t| t.id) else {
            continue;
        };
        match out.iter_mut().find(|x| x.id == t) {
            Some(x) => x.members.push(i),
            None => out.push(TThread {
                id: t,
                period: None,
                members: vec![i],
                period_clock: None,
                exec_clock: 0,
            }),
        }
    }
    out.sort_by_key(|t| t.id);
    for t in &mut out {
        t.period = c.threads[t.id].period.map(|p| units(p.ns, unit));
        t.period_clock = t
            .period
            .map(|p| clocks.add(ClockRole::Period(t.id), Some(p), Some(p)));
        t.exec_clock = clocks.add(ClockRole::Exec(Some(t.id)), None, None);
    }
    out
}

/// The watchdog clocks: one per service with `max-time`, two for a
/// self-stopping one (its pending instance has its own).
fn watch_clocks(
    c: &Component,
    sys: &System<'_>,
    max_time: &[Option<i64>],
    exact: &[bool],
    clocks: &mut Clocks,
) -> Vec<Option<(usize, usize)>> {
    (0..sys.len())
        .map(|i| {
            let m = max_time[i]?;
            let s = sys.service(i);
            // Without invariant (a watchdog firing at any time from the
            // horizon on) the clock has no upper bound to compare.
            let upper = exact[i].then_some(m + 1);
            let main = clocks.add(ClockRole::Watch(s), Some(m), upper);
            let self_stop = c.services[s].stops.iter().any(|r| r.id == s);
            let pend = if self_stop {
                clocks.add(ClockRole::WatchPending(s), Some(m), upper)
            } else {
                main
            };
            Some((main, pend))
        })
        .collect()
}

/// Upper bounds of the execution clocks: the largest WCET they run.
fn bound_exec_clocks(
    c: &Component,
    sys: &System<'_>,
    threads: &[TThread],
    ctl_wcet: &[Option<i64>],
    wcet: &[i64],
    ctl_clock: usize,
    clocks: &mut Clocks,
) {
    for t in threads {
        let worst = t
            .members
            .iter()
            .flat_map(|&i| c.services[sys.service(i)].codels.iter())
            .map(|k| wcet[k.0 as usize])
            .max()
            .unwrap_or(0);
        clocks.raise_upper(t.exec_clock, worst);
    }
    clocks.raise_upper(
        ctl_clock,
        ctl_wcet.iter().flatten().copied().max().unwrap_or(0),
    );
}

impl Model for TimedSystem<'_> {
    type State = TState;
    type Action = TAction;
    type Zone = Dbm;

    /// A transition costs at least the square of the clocks (zone
    /// operations): beyond 32 clocks, the limits are looked at after every
    /// transition.
    fn limit_period(&self) -> u64 {
        if self.clocks.len() > 32 { 1 } else { 64 }
    }

    fn width(&self) -> usize {
        self.width
    }

    fn init_states(&self) -> Vec<TState> {
        vec![self.initial_state(&mut None)]
    }

    fn actions(&self, st: &TState, out: &mut Vec<TAction>) {
        self.enabled(st, out);
    }

    fn next_state(&self, st: &TState, a: TAction) -> Option<TState> {
        self.post(st, a)
    }

    fn encode(&self, st: &TState, out: &mut Vec<u64>) {
        self.sys.encode(&st.cfg, out);
        for (k, t) in self.threads.iter().enumerate() {
            out.push(st.eligible[k]);
            let words = order_words(t.members.len());
            let mut packed = vec![0u64; words];
            for (n, &slot) in st.order[k].iter().enumerate() {
                packed[n / 9] |= (u64::from(slot) + 1) << (7 * (n % 9));
            }
            out.extend(packed);
        }
        let ctl = st.ctl.map_or(0, |r| u64::from(r) + 1);
        let violation = match st.violation {
            None => 0,
            Some(Violation::Overrun(k)) => u64::from(k) + 1,
        };
        out.push(ctl | (violation << 32));
    }

    fn decode(&self, words: &[u64], zone: &Dbm) -> TState {
        let mut at = self.sys.width();
        let cfg = self.sys.decode(&words[..at], &());
        let n = self.threads.len();
        let mut eligible = Vec::with_capacity(n);
        let mut order = Vec::with_capacity(n);
        for t in &self.threads {
            eligible.push(words[at]);
            let count = order_words(t.members.len());
            let list = (0..count * 9)
                .map(|n| (words[at + 1 + n / 9] >> (7 * (n % 9))) & 127)
                .take_while(|&v| v != 0)
                .map(|v| u8::try_from(v - 1).unwrap_or(u8::MAX))
                .collect();
            order.push(list);
            at += 1 + count;
        }
        let last = words[at];
        let ctl = u16::try_from(last & 0xFFFF_FFFF)
            .ok()
            .and_then(|v| v.checked_sub(1));
        let violation = u16::try_from(last >> 32)
            .ok()
            .and_then(|v| v.checked_sub(1))
            .map(Violation::Overrun);
        TState {
            cfg,
            eligible,
            order,
            ctl,
            violation,
            zone: zone.clone(),
        }
    }

    fn zone(&self, st: &TState) -> Dbm {
        st.zone.clone()
    }

    fn expand(&self, st: &TState) -> bool {
        st.violation.is_none()
    }
}
