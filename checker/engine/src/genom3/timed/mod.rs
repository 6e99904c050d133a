//! The timed GenoM3 engine: the untimed engine's rules ([`super::steps`])
//! plus GenoM3's task loop in time (`docs/genom3-semantics.md` sections 1,
//! 2, 7 and 8, read as section 15 says):
//!
//! - a periodic task wakes at every tick (`period`, first at `delay`); at a
//!   tick it starts the accepted instances, resumes the paused ones, and
//!   then *sweeps*: every unpaused instance runs one codel per sweep, in
//!   any order (every slot order is explored), and the task sweeps again
//!   at once while some instance made a transition without `pause::`; a
//!   tick that finds the work of the previous one unfinished is a
//!   `thread-overrun` (terminal violation);
//! - an aperiodic task is activated at any time while it has something to
//!   start or resume (requests, other tasks' transitions and interruptions
//!   wake it in GenoM3, and the environment may send requests at any time),
//!   and its continuation sweeps start and resume too;
//! - a codel takes between 0 and its WCET (0 without one); an `async` codel
//!   takes at least its WCET and has no upper bound; a task begins a codel
//!   as soon as it may (urgent), waiting only for GenoM3's locks: the codel
//!   waits while another thread runs a codel of its exclusion list
//!   ([`locks`]);
//! - GenoM3's resource FIFO (8.3): a thread that cannot begin its codel at
//!   once (a lock is held, or older tickets wait) takes a ticket for that
//!   codel ([`TG3Action::Ticket`], urgent; threads due at one instant take
//!   theirs in every order) and begins it only at the head of the queue,
//!   its locks free; the queue's head blocks every later ticket, conflicting
//!   or not (head-of-line blocking);
//! - the control thread (requests, functions, attributes, `kill`,
//!   `abort_activity`) acts at any time and takes no time; an interrupted
//!   instance whose codel runs or is due in the sweep goes to `stop` after
//!   that codel.
//!
//! A symbolic state is the untimed state (instances with their timing
//! marks), per task the continuation and first-tick bits, and a zone over
//! the clocks: per periodic task the time since its tick, per task the time
//! since its running codel began.

pub mod analysis;
pub mod aside;
pub mod bound;
pub mod groups;
pub mod hunt;
pub mod locks;
pub mod overrun;
mod requests;
pub mod response;
pub mod response_bound;
mod steps;
mod time;
pub mod trace;
pub mod windows;

use std::collections::BTreeMap;

use genom_model::component::{Idx, ServiceId};

use super::machine::{Machine, Owner};
use super::state::{G3State, Inst, Status, mark};
use super::steps::{Engine, G3Action};
use crate::kernel::explore::Model;
use crate::kernel::store::bits::{BitReader, BitWriter, bits_for, words_for};
use crate::timed::clocks::gcd;
use crate::zones::dbm::Dbm;
pub(crate) use requests::ctl_copy;
use requests::{canonical_calls, quiet_calls};

/// Whose instance: an activity's or a task's permanent activity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Who {
    /// Activity index.
    Act(u16),
    /// Task index (its permanent activity).
    Perm(u8),
}

impl Who {
    /// The state machine's owner.
    pub fn owner(self) -> Owner {
        match self {
            Who::Act(a) => Owner::Activity(usize::from(a)),
            Who::Perm(t) => Owner::Task(usize::from(t)),
        }
    }
}

/// A transition of the timed GenoM3 model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TG3Action {
    /// The control thread accepts a request, runs a function or
    /// attribute, or `abort_activity` (as the untimed engine).
    Control(G3Action),
    /// Periodic task `t` reaches its tick.
    Tick(u8),
    /// Aperiodic task `t` is activated.
    Wake(u8),
    /// The control thread takes a request whose service has control
    /// codels (`validate`, a function's codels): they run in turn, the
    /// first begins or takes its ticket at once (docs/genom3-semantics.md
    /// 15.5, "Requests taken with their first codel").
    CtlBegin(G3Action),
    /// The control thread begins its next control codel (its locks are
    /// free, and its ticket is the queue's head or the queue is empty).
    CtlPhase,
    /// The control thread takes a ticket for its next control codel: it
    /// cannot begin it now.
    CtlTicket,
    /// The running control codel ends: success (the next one, or the
    /// request's effect) or an exception (rejected, nothing changes).
    CtlEnd(bool),
    /// An instance (packed) begins the codel of its state.
    Begin(Who, u16),
    /// The task of an instance (packed) takes a ticket for the instance's
    /// due codel in GenoM3's resource FIFO: it cannot begin it now.
    Ticket(Who, u16),
    /// The running instance (packed) ends its codel with outcome `o`.
    End(Who, u16, u8),
}

/// A symbolic state.
#[derive(Debug, Clone, PartialEq)]
pub struct TG3State {
    /// The untimed state, instances with their timing marks.
    pub g: G3State,
    /// Per task (bit): some instance made a transition without `pause::`
    /// in the current sweep (the task sweeps again at once).
    pub cont: u64,
    /// Per task (bit): its first tick happened.
    pub ticked: u64,
    /// The task whose tick found its work unfinished (terminal).
    pub violation: Option<u8>,
    /// The request the control thread handles, if it runs control codels.
    pub ctl: Option<Ctl>,
    /// GenoM3's resource FIFO (8.3): the threads holding a ticket, oldest
    /// first (task indices, [`CTL`] for the control thread). A task's
    /// ticket is for its instance marked [`mark::TICKET`].
    pub queue: Vec<u8>,
    /// Per task (bit): a tick found its work unfinished and, with
    /// [`TimedEngine::coalesce`], was coalesced: the task wakes again as
    /// soon as that work ends (GenoM3 1.2).
    pub late: u64,
    /// The clock zone.
    pub zone: Dbm,
}

/// A request on the control thread, with control codels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Ctl {
    /// What it does once its codels succeeded.
    pub job: G3Action,
    /// Which of its control codels is next or running.
    pub phase: u8,
    /// Whether that codel runs (else it waits for its locks).
    pub running: bool,
}

impl Ctl {
    fn pack(self) -> u64 {
        let (kind, x) = match self.job {
            G3Action::Accept(a) => (1, a),
            G3Action::Call(k) => (2, k),
            _ => (3, 0),
        };
        kind << 25 | u64::from(x) << 9 | u64::from(self.phase) << 1 | u64::from(self.running)
    }

    fn unpack(v: u64) -> Option<Ctl> {
        let x = ((v >> 9) & 0xffff) as u16;
        let job = match v >> 25 {
            1 => G3Action::Accept(x),
            2 => G3Action::Call(x),
            _ => return None,
        };
        Some(Ctl {
            job,
            phase: ((v >> 1) & 0xff) as u8,
            running: v & 1 == 1,
        })
    }
}

/// The timed GenoM3 model of a machine.
#[derive(Debug)]
pub struct TimedEngine<'a> {
    /// The untimed rules.
    pub e: Engine<'a>,
    /// Nanoseconds per model unit.
    pub unit: u64,
    /// Per task: period in units.
    pub period: Vec<Option<i64>>,
    /// Per task: first tick in units.
    pub delay: Vec<i64>,
    /// Per task: its period clock.
    pub period_clock: Vec<Option<usize>>,
    /// Per task: its execution clock.
    pub exec_clock: Vec<usize>,
    /// The control thread's execution clock.
    pub ctl_clock: usize,
    /// Per task: its activities.
    pub acts_of: Vec<Vec<usize>>,
    /// The codels' WCETs and exclusion lists.
    pub locks: locks::Locks,
    /// Largest constant each clock is compared with from below (`x > c`;
    /// index: clock − 1).
    bounds: Vec<Option<i64>>,
    /// Largest constant each clock is compared with from above (`x < c`):
    /// as [`TimedEngine::bounds`], but none for response clocks.
    upper: Vec<Option<i64>>,
    /// Per activity: its response clock, when its response time is
    /// measured ([`response`]).
    pub resp: Vec<Option<usize>>,
    /// The control thread's response clock (time since it took its
    /// request), when measured.
    pub ctl_resp: Option<usize>,
    /// Per activity and state, with response clocks: whether a cycle of
    /// yields or an `async` codel can be reached from it (read on every
    /// state, so computed once).
    pub(crate) loops: Vec<Vec<bool>>,
    /// A tick that finds its task's work unfinished is coalesced, as in
    /// GenoM3 (the task wakes again as soon as the work ends), instead of
    /// ending the exploration as a `thread-overrun` (for response times).
    pub coalesce: bool,
    /// Per service: the control codels (indices) whose locks some task's
    /// codel contends, even those that take no time (while one waits, its
    /// ticket delays those behind it); the others run in no time here (a
    /// request may come at any time, they never wait, and they make no one
    /// wait, so neither their duration nor their ticket changes what a task
    /// sees).
    pub(crate) jobs: BTreeMap<ServiceId, Vec<usize>>,
    /// Per control service: the one standing for it in requests, when its
    /// request does nothing but run its contended codels and another's
    /// codels look the same (then either's run is the other's).
    pub(crate) canon: Vec<u16>,
    /// Per control service whose request does nothing but run one
    /// contended control codel that takes no time and throws nothing: that
    /// codel's key. When it could begin at once, the request changes nothing
    /// a task sees, and it is not explored (see
    /// [`TimedEngine::changes_nothing`]).
    pub(crate) quiet: Vec<Option<usize>>,
    /// The `done` bits that matter: services some `after`/`before` names
    /// (the others are cleared, so that they do not split states).
    tracked: Vec<u64>,
    /// Per task: in the explored group (see [`groups`]).
    pub in_group: Vec<bool>,
}

/// Most tasks a timed model handles (one bit each in a word).
pub const MAX_TASKS: usize = 32;

/// The control thread in [`TG3State::queue`].
pub const CTL: u8 = 62;

/// Bits of a packed [`Ctl`] (`None`: 0).
const CTL_BITS: u32 = 27;

impl<'a> TimedEngine<'a> {
    /// The timed model of the whole of `m`; `None` with more than
    /// [`MAX_TASKS`] tasks.
    pub fn new(m: Machine<'a>) -> Option<Self> {
        let all = groups::Group {
            tasks: vec![true; m.tasks.len()],
            acts: vec![true; m.activities.len()],
            ctls: vec![true; m.controls.len()],
        };
        Self::for_group(m, &all)
    }

    /// The timed model of one group of `m`.
    pub fn for_group(m: Machine<'a>, group: &groups::Group) -> Option<Self> {
        let locks = locks::Locks::new(&m, unit_ns(&m));
        Self::with_locks(m, group, locks)
    }

    /// [`TimedEngine::for_group`] with the codels of `m` already read
    /// (in units of [`unit_ns`]), for several groups of one machine.
    pub fn with_locks(m: Machine<'a>, group: &groups::Group, locks: locks::Locks) -> Option<Self> {
        let n = m.tasks.len();
        if n > MAX_TASKS {
            return None;
        }
        let unit = unit_ns(&m);
        let to_units = |ns: u64| i64::try_from(ns / unit).unwrap_or(i64::MAX / 4);
        let period: Vec<Option<i64>> = m.tasks.iter().map(|t| t.period_ns.map(to_units)).collect();
        let delay: Vec<i64> = m.tasks.iter().map(|t| to_units(t.delay_ns)).collect();
        let mut bounds = Vec::new();
        let mut period_clock = Vec::new();
        for t in 0..n {
            period_clock.push(period[t].map(|p| {
                bounds.push(Some(p.max(delay[t])));
                bounds.len()
            }));
        }
        // The execution clocks' bounds depend on the codel running: set per
        // state ([`TimedEngine::local_bounds`]).
        let mut exec_clock = Vec::new();
        for _ in 0..n {
            bounds.push(Some(0));
            exec_clock.push(bounds.len());
        }
        bounds.push(Some(0));
        let ctl_clock = bounds.len();
        let acts_of = (0..n)
            .map(|t| {
                (0..m.activities.len())
                    .filter(|&a| m.activities[a].task == t)
                    .collect()
            })
            .collect();
        let tracked = m.completions_read();
        let jobs = m
            .control_codels
            .iter()
            .map(|(&sid, v)| {
                let kept = (0..v.len())
                    .filter(|&i| {
                        // Contended: it may wait, so it holds a ticket that
                        // delays those behind it even when it takes no time.
                        locks.ctl_key(sid, i).is_some_and(|k| locks.contended(k))
                    })
                    .collect();
                (sid, kept)
            })
            .collect();
        let canon = canonical_calls(&m, &locks, &jobs, &tracked, &group.ctls, false);
        let quiet = quiet_calls(&m, &locks, &jobs, &tracked);
        let e = Engine::part_tasks(
            m,
            group.acts.clone(),
            group.ctls.clone(),
            group.tasks.clone(),
        )
        .with_marks();
        Some(TimedEngine {
            in_group: group.tasks.clone(),
            canon,
            quiet,
            jobs,
            tracked,
            e,
            unit,
            period,
            delay,
            period_clock,
            exec_clock,
            ctl_clock,
            acts_of,
            locks,
            upper: bounds.clone(),
            bounds,
            resp: Vec::new(),
            ctl_resp: None,
            loops: Vec::new(),
            coalesce: false,
        })
    }

    /// Lets a request stand for those whose runs are among its own (the
    /// same codels, each with a WCET at least as long), not only for those
    /// whose runs are the same: for schedulability, where which of them
    /// ran does not matter, but not for response times, which are each
    /// service's own.
    pub fn dominate_calls(&mut self) {
        let e = &self.e;
        self.canon = canonical_calls(&e.m, &self.locks, &self.jobs, &self.tracked, &e.ctls, true);
    }

    /// Bit widths of the packed state after the untimed words: a per-task
    /// flag set (`cont`, `ticked`, `late`), the violation, and a queue
    /// entry (a task, the control thread, or none).
    fn field_bits(&self) -> (u32, u32, u32) {
        let n = self.e.m.tasks.len() as u64;
        (n as u32, bits_for(n + 1), bits_for(n + 2))
    }

    /// Bits of the packed state after the untimed words.
    fn extra_bits(&self) -> usize {
        let (n, v, q) = self.field_bits();
        let (n, v, q) = (n as usize, v as usize, q as usize);
        // The queue has an entry per task and one for the control thread.
        3 * n + v + CTL_BITS as usize + (n + 1) * q
    }

    /// Number of clocks.
    pub fn clock_count(&self) -> usize {
        self.bounds.len()
    }

    /// The machine.
    pub fn m(&self) -> &Machine<'a> {
        &self.e.m
    }

    /// The initial state with `extra` more clocks (for traces), time
    /// passing from 0.
    pub fn start(&self, extra: usize) -> TG3State {
        let st = TG3State {
            g: self.e.initial(),
            cont: 0,
            ticked: 0,
            violation: None,
            ctl: None,
            queue: Vec::new(),
            late: 0,
            zone: Dbm::zero(self.clock_count() + extra),
        };
        self.let_time_pass(self.finish(st))
    }

    /// The periodic tasks of the explored group: those that have ticks,
    /// hence can overrun.
    pub fn periodic_tasks(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.e.m.tasks.len()).filter(|&t| self.in_group[t] && self.period[t].is_some())
    }

    /// Whether task `t` runs at all yet (spawned in the boot order).
    pub fn spawned(&self, g: &G3State, t: usize) -> bool {
        g.phase != super::state::Phase::Boot || t <= usize::from(g.booted)
    }

    /// The instances of task `t` (its permanent one first), with who owns
    /// each (an iterator, not a list: it is read several times per state).
    pub fn instances<'s>(
        &'s self,
        g: &'s G3State,
        t: usize,
    ) -> impl Iterator<Item = (Who, Inst)> + 's {
        let perm = g.perm[t].map(|i| (Who::Perm(t as u8), i));
        let acts = self.acts_of[t].iter().flat_map(move |&a| {
            let v = &g.inst[a];
            // Equal instances are one (they are sorted).
            (0..v.len())
                .filter(move |&n| n == 0 || v[n - 1] != v[n])
                .map(move |n| (Who::Act(a as u16), v[n]))
        });
        perm.into_iter().chain(acts)
    }

    /// The instance of task `t` running a codel, if any.
    pub fn running(&self, g: &G3State, t: usize) -> Option<(Who, Inst)> {
        self.instances(g, t).find(|(_, i)| i.has(mark::BUSY))
    }

    /// Task `t` has work left in its current wake-up.
    pub fn unfinished(&self, st: &TG3State, t: usize) -> bool {
        st.cont >> t & 1 == 1
            || self
                .instances(&st.g, t)
                .any(|(_, i)| i.has(mark::BUSY | mark::DUE))
    }

    /// Whether codel `k` of thread `t` (a task, `None` for the control
    /// thread) has its locks free: no other thread runs a codel it waits
    /// for.
    pub fn locks_free(&self, st: &TG3State, t: Option<usize>, k: usize) -> bool {
        self.holders(st, t)
            .all(|(j, _, _)| !self.locks.excludes(k, j))
    }

    /// How thread `th` (in [`TG3State::queue`]'s numbering) may go on with
    /// a codel whose locks are `free` (8.3): `Some(true)` it begins it now
    /// (its ticket is the head, or it holds none and the queue is empty),
    /// `Some(false)` it takes a ticket (it holds none and cannot begin),
    /// `None` it waits (its ticket is behind, or its locks are held).
    fn turn(st: &TG3State, th: u8, free: bool) -> Option<bool> {
        let queued = st.queue.contains(&th);
        let head = st.queue.first() == Some(&th);
        if free && (head || st.queue.is_empty()) {
            Some(true)
        } else if !queued {
            Some(false)
        } else {
            None
        }
    }

    /// The codels some thread may begin now, and the tickets some thread
    /// takes now (time may not pass then).
    pub fn begins(&self, st: &TG3State, out: &mut Vec<TG3Action>) {
        self.each_begin(st, &mut |a| out.push(a));
    }

    /// [`TimedEngine::begins`], each given to `emit`.
    fn each_begin(&self, st: &TG3State, emit: &mut dyn FnMut(TG3Action)) {
        for t in 0..self.e.m.tasks.len() {
            if !self.spawned(&st.g, t) || self.running(&st.g, t).is_some() {
                continue;
            }
            let queued = st.queue.contains(&(t as u8));
            for (who, i) in self.instances(&st.g, t) {
                if !i.has(mark::DUE) || (queued && !i.has(mark::TICKET)) {
                    continue;
                }
                let k = self.locks.key(who.owner(), i.state);
                if self.locks.is_async(k) {
                    // No lock, no ticket (7.2); a queued task was skipped
                    // above (an `async` codel never holds the ticket).
                    emit(TG3Action::Begin(who, i.pack()));
                    continue;
                }
                match Self::turn(st, t as u8, self.locks_free(st, Some(t), k)) {
                    Some(true) => emit(TG3Action::Begin(who, i.pack())),
                    Some(false) => emit(TG3Action::Ticket(who, i.pack())),
                    None => {}
                }
            }
        }
        match self.ctl_turn(st) {
            Some(true) => emit(TG3Action::CtlPhase),
            Some(false) => emit(TG3Action::CtlTicket),
            None => {}
        }
    }

    /// How the control thread goes on with its next control codel, when it
    /// has one and does not run it ([`TimedEngine::turn`]).
    pub(crate) fn ctl_turn(&self, st: &TG3State) -> Option<bool> {
        let (c, k) = (st.ctl?, self.ctl_codel(st)?);
        if c.running {
            return None;
        }
        Self::turn(st, CTL, self.locks_free(st, None, k))
    }

    /// The instance task `t` holds its ticket for, if any.
    pub fn ticket_of(&self, g: &G3State, t: usize) -> Option<(Who, Inst)> {
        self.instances(g, t).find(|(_, i)| i.has(mark::TICKET))
    }

    /// The codels (keys) of the threads queued up to and including `th`,
    /// oldest first: those it waits behind, and its own.
    pub fn queued_codels(&self, st: &TG3State, th: u8) -> Vec<usize> {
        let mut out = Vec::new();
        for &u in &st.queue {
            if u == CTL {
                out.extend(self.ctl_codel(st));
            } else {
                let ticket = self.ticket_of(&st.g, usize::from(u));
                out.extend(ticket.map(|(w, i)| self.locks.key(w.owner(), i.state)));
            }
            if u == th {
                break;
            }
        }
        out
    }

    /// The running codels (key, clock, WCET) that a codel of task `except`
    /// may wait for: those of the other tasks and of the control thread;
    /// with `None` (for a control codel), those of every task.
    pub fn holders<'s>(
        &'s self,
        st: &'s TG3State,
        except: Option<usize>,
    ) -> impl Iterator<Item = (usize, usize, Option<i64>)> + 's {
        let tasks = (0..self.e.m.tasks.len())
            .filter(move |&u| Some(u) != except)
            .filter_map(move |u| {
                let (w, j) = self.running(&st.g, u)?;
                let k = self.locks.key(w.owner(), j.state);
                Some((k, self.exec_clock[u], self.locks.wcet_of(k)))
            });
        let ctl = st
            .ctl
            .filter(|c| c.running && except.is_some())
            .and_then(|_| self.ctl_codel(st))
            .map(|k| (k, self.ctl_clock, self.locks.wcet_of(k)));
        tasks.chain(ctl)
    }

    /// The key of the control codel next or running, if any.
    pub fn ctl_codel(&self, st: &TG3State) -> Option<usize> {
        let c = st.ctl?;
        self.locks
            .ctl_key(self.job_service(c.job)?, self.job_codel(c)?)
    }

    /// The service of a control-thread job.
    pub fn job_service(&self, job: G3Action) -> Option<ServiceId> {
        match job {
            G3Action::Accept(a) => Some(self.e.m.activities[usize::from(a)].service),
            G3Action::Call(k) => Some(self.e.m.controls[usize::from(k)].service),
            _ => None,
        }
    }

    /// Number of control codels of a job that hold contended locks.
    pub fn job_codels(&self, job: G3Action) -> usize {
        self.job_service(job)
            .and_then(|s| self.jobs.get(&s))
            .map_or(0, Vec::len)
    }

    /// The index among its service's control codels of the job's phase.
    pub fn job_codel(&self, ctl: Ctl) -> Option<usize> {
        let sid = self.job_service(ctl.job)?;
        self.jobs.get(&sid)?.get(usize::from(ctl.phase)).copied()
    }
}

/// The time unit: the GCD of the periods, delays and WCETs (control codels
/// included; 1 ns without any).
pub fn unit_ns(m: &Machine<'_>) -> u64 {
    let mut g = 0;
    for t in &m.tasks {
        g = gcd(gcd(g, t.period_ns.unwrap_or(0)), t.delay_ns);
        for s in t.perm.iter().flat_map(|f| f.states.iter()) {
            g = gcd(g, s.wcet_ns.unwrap_or(0));
        }
    }
    let states = m
        .activities
        .iter()
        .flat_map(|a| a.fsm.states.iter())
        .chain(m.control_codels.values().flatten());
    for s in states {
        g = gcd(g, s.wcet_ns.unwrap_or(0));
    }
    g.max(1)
}

impl Model for TimedEngine<'_> {
    type State = TG3State;
    type Action = TG3Action;
    type Zone = Dbm;

    /// Paths are found again from the parents (no reduction; a step is a
    /// function of the state and its zone).
    const KEEPS_ACTIONS: bool = false;

    fn limit_period(&self) -> u64 {
        if self.clock_count() > 32 { 1 } else { 64 }
    }

    fn width(&self) -> usize {
        words_for(self.bits())
    }

    /// The untimed state's bits, then the timed fields'.
    fn bits(&self) -> usize {
        self.e.bits() + self.extra_bits()
    }

    fn init_states(&self) -> Vec<TG3State> {
        vec![self.start(0)]
    }

    fn actions(&self, st: &TG3State, out: &mut Vec<TG3Action>) {
        self.enabled(st, out);
    }

    fn next_state(&self, st: &TG3State, a: TG3Action) -> Option<TG3State> {
        let mut n = self.fire(st, a)?;
        for (d, t) in n.g.done.iter_mut().zip(&self.tracked) {
            *d &= t;
        }
        self.follow_responses(st, &mut n);
        let n = self.let_time_pass(n);
        (!n.zone.is_empty()).then_some(n)
    }

    fn encode(&self, st: &TG3State, out: &mut Vec<u64>) {
        let (n, v, q) = self.field_bits();
        let mut w = BitWriter::new(out);
        self.e.write(&st.g, &mut w);
        w.put(st.cont, n);
        w.put(st.ticked, n);
        w.put(st.late, n);
        w.put(st.violation.map_or(0, |t| u64::from(t) + 1), v);
        w.put(st.ctl.map_or(0, Ctl::pack), CTL_BITS);
        let tasks = self.e.m.tasks.len() as u64;
        for &th in &st.queue {
            // The control thread after the tasks; 0 ends the queue.
            let th = if th == CTL { tasks } else { u64::from(th) };
            w.put(th + 1, q);
        }
        for _ in st.queue.len()..self.e.m.tasks.len() + 1 {
            w.put(0, q);
        }
        w.finish();
    }

    fn decode(&self, w: &[u64], zone: &Dbm) -> TG3State {
        let (n, v, q) = self.field_bits();
        let mut r = BitReader::new(w);
        let g = self.e.read(&mut r);
        let cont = r.take(n);
        let ticked = r.take(n);
        let late = r.take(n);
        let violation = r.take(v).checked_sub(1).and_then(|t| u8::try_from(t).ok());
        let ctl = Ctl::unpack(r.take(CTL_BITS));
        let tasks = self.e.m.tasks.len() as u64;
        let queue = (0..=tasks)
            .map(|_| r.take(q))
            .take_while(|&x| x != 0)
            .map(|x| if x - 1 == tasks { CTL } else { (x - 1) as u8 })
            .collect();
        TG3State {
            g,
            cont,
            ticked,
            violation,
            ctl,
            queue,
            late,
            zone: zone.clone(),
        }
    }

    fn zone(&self, st: &TG3State) -> Dbm {
        st.zone.clone()
    }

    fn expand(&self, st: &TG3State) -> bool {
        st.violation.is_none()
    }
}

/// Service index of an activity (for `done` bits).
pub(crate) fn service_index(m: &Machine<'_>, a: usize) -> usize {
    m.activities[a].service.index()
}

/// Whether an instance is started and not running a codel.
pub(crate) fn idle_running(i: Inst) -> bool {
    matches!(i.status, Status::Run | Status::Stop) && !i.has(mark::BUSY)
}

#[cfg(test)]
mod bound_tests;
#[cfg(test)]
mod causes_tests;
#[cfg(test)]
mod tests;
