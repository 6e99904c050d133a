//! An independent replay of the timed GenoM3 engine's `thread-overrun`
//! traces against GenoM3's execution rules in time
//! (`docs/genom3-semantics.md` sections 1, 2, 7 and 8).
//!
//! It shares no code with the timed engine it checks
//! (`genom_engine::genom3::timed`) and depends on the model alone: it
//! reads the component itself ([`reading`]: tasks, periods, delays, codel
//! state machines with their yields, `pause::`, `async`, WCETs and data
//! accesses, control codels; the resolved [`Component`] for `interrupts`),
//! and re-applies the rules on a plain state: per instance its status, state and whether
//! it is due in its task's current sweep, paused, running or interrupted;
//! per task its next tick and whether it sweeps again; the control
//! thread's request; and every codel run as a time interval.
//!
//! Checked, step by step (steps numbered from 1; every step has an
//! instant):
//! - `component-start` first at 0, instants never decrease, `violation`
//!   last, right after the violating tick;
//! - ticks (`wake-up`, outcome `tick`): the first at the task's `delay`,
//!   the next exactly one period later, none skipped (no step later than a
//!   missed tick); a tick that is not the last finds its task's work done;
//!   the last finds it really unfinished: a codel running for less than its
//!   WCET (or `async`), or a due codel waiting for a lock whose holder runs
//!   for less than its WCET;
//! - activations (`wake-up`, outcome `activation`): an aperiodic task,
//!   idle, with an instance to start or resume;
//! - sweeps: a tick or activation starts the accepted instances and
//!   resumes the paused ones; a task whose last codel yielded without
//!   `pause::` sweeps again at once when it has nothing left due
//!   (continuation sweeps start and resume nothing in a periodic task);
//! - `codel-start`: a due instance at that state on an idle task;
//!   `codel-end`: the task's running codel, after at most its WCET (at
//!   least, `async`), a yield of that state (`pause::` included) or
//!   `exception`; an interrupted instance goes to `stop` after it;
//! - GenoM3's resource queue (8.3): a thread that cannot begin its codel
//!   (a lock it waits for is held, or tickets are queued) takes a ticket
//!   (`lock-wait`) and begins only at the queue's head; a thread without a
//!   ticket begins only when the queue is empty;
//! - urgency: time never passes while an idle task has a due codel and no
//!   ticket, nor while the thread at the queue's head has its locks free;
//! - control thread (`control`): `accept` (activities, functions, `kill`;
//!   `pending` exactly when the new instance waits for the instances it
//!   interrupts), `interrupt` (`abort_activity`), `request` then its
//!   control codels that hold contended locks and take time (start, end
//!   after at most the WCET, `ok` or `exception`), the request's effect
//!   after the last one; one request at a time, once every task started;
//! - locks (8.1-8.2): no codel begins while a codel of another thread that
//!   it waits for runs (strictly overlapping intervals), where an FSM codel
//!   waits for the conflicting codels of other tasks and of the control
//!   thread except, for an activity's codel, those of a service that
//!   interrupts its own; control codels wait for the conflicting FSM codels;
//!   `async` codels take no lock.
//!
//! The engine explores tasks coupled by locks together: the tasks replayed
//! are those the trace names (the others run elsewhere and never hold a
//! lock these wait for). Instances of one activity at one state are told
//! apart by their marks: a `codel-start` takes a due one.

use std::collections::BTreeSet;

use genom_model::component::{Component, ServiceId};
use genom_model::trace::{Event, Trace};

use reading::{Access, Base, Builtin, CodelDef, Owner, Rules, Target};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Status {
    Delayed,
    Ready,
    Run,
    Stop,
}

/// An instance (an activity's, or a task's permanent one).
#[derive(Debug, Clone, PartialEq, Eq)]
struct Inst {
    owner: Owner,
    status: Status,
    state: u8,
    /// Runs a codel in its task's current sweep, not begun yet.
    due: bool,
    /// Its last yield was `pause::`.
    paused: bool,
    /// Its codel runs (since that instant).
    busy: Option<u64>,
    /// Interrupted while running or due: to `stop` after that codel.
    flagged: bool,
    /// Its task holds a ticket for its due codel (8.3).
    ticket: bool,
}

impl Inst {
    fn new(owner: Owner, status: Status, state: u8) -> Inst {
        Inst {
            owner,
            status,
            state,
            due: false,
            paused: false,
            busy: None,
            flagged: false,
            ticket: false,
        }
    }

    fn started(&self) -> bool {
        matches!(self.status, Status::Run | Status::Stop)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    Boot(usize),
    Run,
    Drain,
    PermStop(usize),
    Stopped,
    Failed,
}

/// A codel: an FSM state's, or a service's `i`-th control codel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Codel {
    Fsm(Owner, u8),
    Ctl(ServiceId, usize),
}

/// One codel run: its thread (`None`: control), instants, step.
#[derive(Debug, Clone)]
struct Interval {
    thread: Option<usize>,
    codel: Codel,
    start: u64,
    end: Option<u64>,
    step: usize,
    /// The step that ended it.
    end_step: Option<usize>,
}

/// The request the control thread handles through its timed codels.
#[derive(Debug, Clone)]
struct Request {
    service: ServiceId,
    /// Index into its timed control codels of the next one.
    next: usize,
    /// The running one began then.
    since: Option<u64>,
}

/// The replay's state.
struct Sim<'m, 'c> {
    m: &'m Rules<'c>,
    /// Per task: replayed (named by the trace).
    scope: Vec<bool>,
    phase: Phase,
    insts: Vec<Inst>,
    done: BTreeSet<ServiceId>,
    /// Per task: its next tick.
    next_tick: Vec<Option<u64>>,
    /// Per task: sweeps again once nothing is due.
    cont: Vec<bool>,
    ctl: Option<Request>,
    runs: Vec<Interval>,
    now: u64,
    /// Per activity: when its last instance was accepted.
    accepted: Vec<Option<u64>>,
    /// Ticks that find work unfinished are coalesced (GenoM3 1.2: the task
    /// wakes again as soon as the work ends) rather than overruns.
    coalesce: bool,
    /// Per task: a coalesced tick is pending.
    late: Vec<bool>,
    /// GenoM3's resource queue (8.3): the threads holding a ticket, oldest
    /// first (`None`: the control thread).
    queue: Vec<Option<usize>>,
}

/// Replays an overrun trace of the timed GenoM3 engine on `c` (read with
/// `--max-instances` `max_instances`); Err says which step (1-based) breaks
/// which rule.
pub fn replay_genom3_timed(
    c: &Component,
    max_instances: usize,
    trace: &Trace,
) -> Result<(), String> {
    let m = Rules::new(c, max_instances).ok_or("not a GenoM3 component")?;
    let n = trace.steps.len();
    let tick = n.checked_sub(2).and_then(|k| trace.steps.get(k));
    if n >= 3
        && !tick.is_some_and(|t| t.event == Event::WakeUp && t.outcome.as_deref() == Some("tick"))
    {
        return Err(format!("step {}: the violation follows a tick", n - 1));
    }
    replay(&m, trace, true).map(|_| ())
}

/// Replays a `deadline-miss` trace of the timed GenoM3 engine on `c`: the
/// rules as [`replay_genom3_timed`], except that a tick finding its task's
/// work unfinished is coalesced (the task wakes again as soon as its work
/// ends, GenoM3 1.2), up to the final `violation`, where an
/// instance of activity `service` must still be alive (it has not
/// replied). Ok: how long before the end it was accepted (its age, in ns),
/// to compare with the deadline.
pub fn replay_genom3_alive(
    c: &Component,
    max_instances: usize,
    trace: &Trace,
    service: &str,
) -> Result<u64, String> {
    let m = Rules::new(c, max_instances).ok_or("not a GenoM3 component")?;
    let a = (0..m.activities.len())
        .find(|&a| m.activity_name(a) == service)
        .ok_or_else(|| format!("no activity `{service}`"))?;
    let (now, alive, accepted) = replay(&m, trace, false)?;
    match (alive[a], accepted[a]) {
        (true, Some(at)) => Ok(now - at),
        _ => Err(format!(
            "at the end ({now} ns), `{service}` has no instance alive"
        )),
    }
}

/// At the end of a replay: the final instant, and per activity whether an
/// instance lives and when the last one was accepted.
type Ended = (u64, Vec<bool>, Vec<Option<u64>>);

/// Replays `trace` (`overrun`: its violation is the tick before it).
fn replay(m: &Rules<'_>, trace: &Trace, overrun: bool) -> Result<Ended, String> {
    let steps = &trace.steps;
    let n = steps.len();
    if steps.first().map(|s| s.event) != Some(Event::ComponentStart) {
        return Err("step 1: a trace starts with `component-start`".into());
    }
    if n < 3 || steps[n - 1].event != Event::Violation {
        return Err(format!("step {n}: the trace ends with `violation`"));
    }
    let named = m
        .tasks
        .iter()
        .map(|t| steps.iter().any(|s| s.thread.as_deref() == Some(&t.name)))
        .collect();
    let scope = Sim::new(m, named).closure();
    let mut sim = Sim::new(m, scope);
    sim.coalesce = !overrun;
    let aside = aside_tasks(m, trace)?;
    for (k, step) in steps.iter().enumerate().skip(1) {
        let at = |e: String| format!("step {} ({}): {e}", k + 1, step.event.as_str());
        let time = step
            .time_ns
            .ok_or_else(|| at("the step has no instant".into()))?;
        if time < sim.now {
            return Err(at(format!("time goes back from {} ns", sim.now)));
        }
        if time > sim.now {
            sim.urgent().map_err(at)?;
        }
        sim.missed(time).map_err(at)?;
        sim.overdue(time).map_err(at)?;
        sim.now = time;
        if step.event == Event::Violation {
            if k + 1 != n || step.thread.is_some() {
                return Err(at("a violation is the last step and names no thread".into()));
            }
            continue;
        }
        sim.step(step, k, overrun && k + 2 == n).map_err(at)?;
        if step.event == Event::LockWait {
            sim.nothing_aside_ahead(&aside, step.thread.as_deref())
                .map_err(at)?;
        }
        sim.finish();
    }
    sim.locks()?;
    let alive = (0..m.activities.len())
        .map(|a| sim.insts.iter().any(|i| i.owner == Owner::Activity(a)))
        .collect();
    Ok((sim.now, alive, sim.accepted))
}

impl<'m, 'c> Sim<'m, 'c> {
    fn new(m: &'m Rules<'c>, scope: Vec<bool>) -> Self {
        let mut insts = Vec::new();
        for (t, task) in m.tasks.iter().enumerate() {
            if let Some(s) = task
                .perm
                .as_ref()
                .and_then(|f| f.start)
                .filter(|_| scope[t])
            {
                insts.push(Inst::new(Owner::Task(t), Status::Run, s));
            }
        }
        let next_tick = m
            .tasks
            .iter()
            .map(|t| t.period_ns.map(|_| t.delay_ns))
            .collect();
        let mut sim = Sim {
            m,
            cont: vec![false; m.tasks.len()],
            scope,
            phase: Phase::Boot(0),
            insts,
            done: BTreeSet::new(),
            next_tick,
            ctl: None,
            runs: Vec::new(),
            now: 0,
            accepted: vec![None; m.activities.len()],
            coalesce: false,
            late: vec![false; m.tasks.len()],
            queue: Vec::new(),
        };
        sim.settle(false);
        sim
    }

    fn task_of(&self, o: Owner) -> usize {
        self.m.task_of(o)
    }

    fn fsm_state(&self, o: Owner, s: u8) -> &'m CodelDef {
        &self.m.fsm(o).states[usize::from(s)]
    }

    fn spawned(&self, t: usize) -> bool {
        !matches!(self.phase, Phase::Boot(b) if t > b)
    }

    fn task_named(&self, name: Option<&str>) -> Result<usize, String> {
        let name = name.ok_or("the step names no thread")?;
        let t = self.m.tasks.iter().position(|t| t.name == name);
        t.ok_or_else(|| format!("there is no task `{name}`"))
    }

    fn service_named(&self, name: Option<&str>) -> Result<ServiceId, String> {
        let name = name.ok_or("the step names no service")?;
        let found = self.m.c.services.iter().find(|(_, s)| s.name.name == name);
        found
            .map(|(sid, _)| sid)
            .ok_or_else(|| format!("there is no service `{name}`"))
    }

    fn activity_of(&self, sid: ServiceId) -> Option<usize> {
        self.m.activity_of(sid)
    }

    /// The activities service `sid` interrupts (all for `kill`).
    fn targets(&self, sid: ServiceId) -> Vec<usize> {
        let kill = self.m.builtin(sid) == Some(Builtin::Kill);
        let stops = &self.m.c.services[sid].stops;
        (0..self.m.activities.len())
            .filter(|&a| kill || stops.iter().any(|r| r.id == self.m.activities[a].service))
            .collect()
    }

    /// The running instance of task `t`.
    fn running(&self, t: usize) -> Option<usize> {
        let on = |i: &Inst| self.task_of(i.owner) == t && i.busy.is_some();
        self.insts.iter().position(on)
    }

    /// Task `t` has work left in its wake-up.
    fn unfinished(&self, t: usize) -> bool {
        self.cont[t]
            || self
                .insts
                .iter()
                .any(|i| self.task_of(i.owner) == t && (i.due || i.busy.is_some()))
    }

    /// `excludes(k, j)`: codel `k` waits while codel `j` runs on another
    /// thread (8.1-8.2, `async` codels take no lock).
    fn waits(&self, k: Codel, j: Codel) -> bool {
        let def = |c: Codel| match c {
            Codel::Fsm(o, s) => Some(self.fsm_state(o, s)),
            Codel::Ctl(sid, i) => self.m.control_codels.get(&sid)?.get(i),
        };
        let (Some(a), Some(b)) = (def(k), def(j)) else {
            return false;
        };
        if a.is_async || b.is_async || !clash(&a.access, &b.access) {
            return false;
        }
        match (k, j) {
            (Codel::Ctl(..), Codel::Ctl(..)) => false,
            (Codel::Fsm(Owner::Activity(x), _), Codel::Fsm(Owner::Activity(y), _)) => {
                let mine = self.m.activities[x].service;
                let other = self.m.activities[y].service;
                !self.m.c.services[other].stops.iter().any(|r| r.id == mine)
            }
            _ => true,
        }
    }

    /// The codels running now on threads other than `thread`, with their
    /// start.
    fn holders(&self, thread: Option<usize>) -> Vec<(Codel, u64)> {
        let mut out: Vec<(Codel, u64)> = self
            .insts
            .iter()
            .filter(|i| Some(self.task_of(i.owner)) != thread)
            .filter_map(|i| Some((Codel::Fsm(i.owner, i.state), i.busy?)))
            .collect();
        if let (Some(r), Some(_)) = (&self.ctl, thread) {
            if let (Some(since), Some(&i)) = (r.since, self.timed_codels(r.service).get(r.next)) {
                out.push((Codel::Ctl(r.service, i), since));
            }
        }
        out
    }

    /// Whether codel `k` of thread `th` (`None`: control) must wait: a
    /// codel it waits for runs on another thread.
    fn held(&self, th: Option<usize>, k: Codel) -> bool {
        self.holders(th).iter().any(|&(j, _)| self.waits(k, j))
    }

    /// The control codels of `sid` shown in traces: those that contend a
    /// lock with some task's codel (the others never wait nor make wait,
    /// so neither their duration nor their ticket changes what a task
    /// sees).
    fn timed_codels(&self, sid: ServiceId) -> Vec<usize> {
        let Some(v) = self.m.control_codels.get(&sid) else {
            return Vec::new();
        };
        let fsm_codels: Vec<Codel> = (0..self.m.tasks.len())
            .flat_map(|t| self.codels_of(t))
            .collect();
        (0..v.len())
            .filter(|&i| {
                let k = Codel::Ctl(sid, i);
                fsm_codels
                    .iter()
                    .any(|&j| self.waits(k, j) || self.waits(j, k))
            })
            .collect()
    }

    /// The FSM codels of task `t`.
    fn codels_of(&self, t: usize) -> Vec<Codel> {
        let acts = (0..self.m.activities.len()).filter(|&a| self.m.activities[a].task == t);
        acts.map(Owner::Activity)
            .chain([Owner::Task(t)])
            .flat_map(|o| (0..self.m.fsm(o).states.len()).map(move |s| (o, s)))
            .filter_map(|(o, s)| Some(Codel::Fsm(o, u8::try_from(s).ok()?)))
            .collect()
    }

    /// The scope with every task whose codels wait for, or make wait, a
    /// codel of a task in it (the engine explores those together).
    fn closure(&self) -> Vec<bool> {
        let mut scope = self.scope.clone();
        let codels: Vec<Vec<Codel>> = (0..scope.len()).map(|t| self.codels_of(t)).collect();
        let coupled = |t: usize, u: usize| {
            codels[t].iter().any(|&k| {
                codels[u]
                    .iter()
                    .any(|&j| self.waits(k, j) || self.waits(j, k))
            })
        };
        let mut grown = true;
        while grown {
            grown = false;
            for u in 0..scope.len() {
                if !scope[u] && (0..scope.len()).any(|t| t != u && scope[t] && coupled(t, u)) {
                    scope[u] = true;
                    grown = true;
                }
            }
        }
        scope
    }

    /// No step is later than a tick not taken.
    fn missed(&self, time: u64) -> Result<(), String> {
        for (t, next) in self.next_tick.iter().enumerate() {
            if let (Some(at), true) = (*next, self.scope[t]) {
                if time > at {
                    let name = &self.m.tasks[t].name;
                    return Err(format!("task `{name}` missed its tick at {at} ns"));
                }
            }
        }
        Ok(())
    }

    /// Time may pass: every idle task with a due codel, and the control
    /// thread with a codel to run, holds a ticket, and the queue's head
    /// waits for a lock.
    fn urgent(&self) -> Result<(), String> {
        for t in (0..self.m.tasks.len()).filter(|&t| self.spawned(t)) {
            if self.running(t).is_some() || self.queue.contains(&Some(t)) {
                continue;
            }
            if let Some(i) = self
                .insts
                .iter()
                .find(|i| self.task_of(i.owner) == t && i.due)
            {
                return Err(format!(
                    "time passes while task `{}` neither begins state `{}` nor takes a ticket for it at {} ns",
                    self.m.tasks[t].name,
                    self.fsm_state(i.owner, i.state).name,
                    self.now
                ));
            }
        }
        if self.ctl_codel().is_some() && !self.queue.contains(&None) {
            return Err(format!(
                "time passes while the control thread neither begins its codel nor takes a ticket for it at {} ns",
                self.now
            ));
        }
        let Some(&head) = self.queue.first() else {
            return Ok(());
        };
        let Some(k) = self.ticket_codel(head) else {
            return Ok(());
        };
        if self.held(head, k) {
            return Ok(());
        }
        let who = head.map_or("the control thread".to_owned(), |t| {
            format!("task `{}`", self.m.tasks[t].name)
        });
        Err(format!(
            "time passes while {who}, at the head of the resource queue, may begin its codel (its locks are free at {} ns)",
            self.now
        ))
    }

    /// The control codel the control thread is to begin next, if any.
    fn ctl_codel(&self) -> Option<Codel> {
        let r = self.ctl.as_ref().filter(|r| r.since.is_none())?;
        let i = *self.timed_codels(r.service).get(r.next)?;
        Some(Codel::Ctl(r.service, i))
    }

    /// The codel a queued thread holds its ticket for.
    fn ticket_codel(&self, th: Option<usize>) -> Option<Codel> {
        match th {
            None => self.ctl_codel(),
            Some(t) => self
                .insts
                .iter()
                .find(|i| self.task_of(i.owner) == t && i.ticket)
                .map(|i| Codel::Fsm(i.owner, i.state)),
        }
    }

    /// The codels queued up to and including `th`'s ticket.
    fn queued_up_to(&self, th: Option<usize>) -> Vec<Codel> {
        let mut out = Vec::new();
        for &u in &self.queue {
            out.extend(self.ticket_codel(u));
            if u == th {
                break;
            }
        }
        out
    }

    /// A thread (a task, `None` for the control thread) begins a codel:
    /// at the queue's head (then its ticket is served), or holding no
    /// ticket while the queue is empty.
    fn served(&mut self, th: Option<usize>) -> Result<(), String> {
        match self.queue.first() {
            None => Ok(()),
            Some(&h) if h == th => {
                self.queue.remove(0);
                Ok(())
            }
            Some(_) if self.queue.contains(&th) => {
                Err("its ticket is not at the head of the resource queue".into())
            }
            Some(_) => Err("tickets are queued: it must take one and wait its turn".into()),
        }
    }

    /// Drops the tickets whose codel is gone.
    pub(super) fn drop_stale_tickets(&mut self) {
        let queue = std::mem::take(&mut self.queue);
        self.queue = queue
            .into_iter()
            .filter(|&u| self.ticket_codel(u).is_some())
            .collect();
    }

    /// Every codel that began while a codel of another thread it waits for
    /// ran: one begun at an earlier step and not ended at an earlier step
    /// (so a codel that takes no time is checked too, and a holder whose
    /// end is missing still holds its locks).
    fn locks(&self) -> Result<(), String> {
        for (x, k) in self.runs.iter().enumerate() {
            for j in &self.runs[..x] {
                let ended = j.end_step.is_some_and(|e| e < k.step);
                if j.thread == k.thread || ended || !self.waits(k.codel, j.codel) {
                    continue;
                }
                let until = j
                    .end
                    .map_or_else(|| "the end of the trace".to_owned(), |e| format!("{e} ns"));
                return Err(format!(
                    "step {}: the codel begins at {} ns while the codel begun at step {} (which it waits for) runs until {until}",
                    k.step + 1,
                    k.start,
                    j.step + 1,
                ));
            }
        }
        Ok(())
    }

    /// No codel runs longer than its WCET: time may not pass beyond it
    /// while the codel has not ended (an `async` codel has no bound).
    fn overdue(&self, time: u64) -> Result<(), String> {
        for i in &self.insts {
            let Some(since) = i.busy else { continue };
            let def = self.fsm_state(i.owner, i.state);
            let w = def.wcet_ns.unwrap_or(0);
            if !def.is_async && time - since > w {
                return Err(format!(
                    "time passes to {time} ns while codel `{}` (begun at {since} ns) runs past its WCET {w} ns",
                    def.name
                ));
            }
        }
        let Some(r) = &self.ctl else { return Ok(()) };
        let (Some(since), Some(&i)) = (r.since, self.timed_codels(r.service).get(r.next)) else {
            return Ok(());
        };
        let def = self.m.control_codels.get(&r.service).and_then(|v| v.get(i));
        let w = def.and_then(|d| d.wcet_ns).unwrap_or(0);
        if time - since > w {
            return Err(format!(
                "time passes to {time} ns while the control thread's codel (begun at {since} ns) runs past its WCET {w} ns"
            ));
        }
        Ok(())
    }
}

/// The tasks `trace` sets aside as playing no part in its finding
/// (`TraceStep::aside`): known tasks, and not the one whose tick ends it.
/// A thread's steps are all set aside or none.
fn aside_tasks(m: &Rules<'_>, trace: &Trace) -> Result<Vec<usize>, String> {
    let last = trace.steps.iter().rev().find_map(|s| s.thread.as_deref());
    let names = trace.aside_threads();
    if let Some(s) = trace
        .steps
        .iter()
        .find(|s| !s.aside && s.thread.as_deref().is_some_and(|t| names.contains(&t)))
    {
        return Err(format!(
            "some steps of `{}` only are set aside",
            s.thread.as_deref().unwrap_or_default()
        ));
    }
    names
        .into_iter()
        .map(|name| {
            if Some(name) == last {
                return Err(format!("the overrunning task `{name}` is set aside"));
            }
            m.tasks
                .iter()
                .position(|t| t.name == name)
                .ok_or_else(|| format!("no task `{name}` to set aside"))
        })
        .collect()
}

impl Sim<'_, '_> {
    /// A thread that plays a part (not in `aside`) took a ticket: no task
    /// set aside runs a codel or holds a ticket ahead of it, since from
    /// then on only those could delay it (docs/genom3-semantics.md 15.12).
    fn nothing_aside_ahead(&self, aside: &[usize], thread: Option<&str>) -> Result<(), String> {
        let who = match thread {
            Some("control") | None => None,
            Some(name) => self.m.tasks.iter().position(|t| t.name == name),
        };
        if who.is_some_and(|t| aside.contains(&t)) {
            return Ok(());
        }
        let ahead: Vec<Option<usize>> = self
            .queue
            .iter()
            .copied()
            .take_while(|&u| u != who)
            .collect();
        for &a in aside {
            if self.running(a).is_some() || ahead.contains(&Some(a)) {
                return Err(format!(
                    "task `{}`, set aside as playing no part, runs a codel or holds a ticket ahead when a thread that plays a part takes its ticket",
                    self.m.tasks[a].name
                ));
            }
        }
        Ok(())
    }
}

/// GenoM3's `param_mutex` (8.1): same port or remote whatever the
/// directions; ids member paths equal on their common prefix, one writing.
fn clash(a: &[Access], b: &[Access]) -> bool {
    a.iter().any(|x| {
        b.iter().any(|y| match (&x.base, &y.base) {
            (Base::Port(p), Base::Port(q)) | (Base::Remote(p), Base::Remote(q)) => p == q,
            (Base::Ids, Base::Ids) => {
                let n = x.path.len().min(y.path.len());
                (x.write || y.write) && x.path[..n] == y.path[..n]
            }
            _ => false,
        })
    })
}

/// What a codel's outcome names.
enum Yield {
    To(u8, bool),
    Ether,
    Exception,
}

/// Outcome `text` of `def`'s codel in `fsm`.
fn parse_yield(m: &Rules<'_>, o: Owner, def: &CodelDef, text: &str) -> Result<Yield, String> {
    if text == "exception" {
        return Ok(Yield::Exception);
    }
    let fsm = m.fsm(o);
    for y in &def.yields {
        let (name, y) = match *y {
            Target::Ether => ("ether".to_owned(), Yield::Ether),
            Target::State { state, pause } => {
                let n = &fsm.states[usize::from(state)].name;
                let name = if pause {
                    format!("pause::{n}")
                } else {
                    n.clone()
                };
                (name, Yield::To(state, pause))
            }
        };
        if name == text {
            return Ok(y);
        }
    }
    Err(format!(
        "the codel of state `{}` does not yield `{text}`",
        def.name
    ))
}

mod reading;
mod steps;

#[cfg(test)]
mod tests;
