//! The network of timed automata of a **GenoM3** component, in GenoM3's
//! timed semantics (`docs/genom3-semantics.md` section 15 and the rules of
//! sections 1-10 it relies on), written from that document and the model,
//! independently of the timed GenoM3 engine (`checker/engine/src/genom3/
//! timed/`), so that TChecker checks an independent encoding of it.
//!
//! The encoding (docs/exports/tchecker.md, section "GenoM3 components"):
//!
//! - **Slots**: each activity has one *slot* (one instance), each task
//!   with permanent codels one more (first in its sweep), and an activity
//!   that interrupts itself a second one, `X_2`: a client restarts it by
//!   requesting it again while an instance lives, and the new instance
//!   interrupts the other slot's (ended if accepted, flagged or sent to
//!   `stop` if running, left alone if stopping) and pends until it ended
//!   (3.4, 5.1-5.3). A request takes the activity's first free slot (its
//!   slots are interchangeable, as the engine's instances are) and is
//!   possible while one is free. This is the engine's default,
//!   `--max-instances 1`: one instance of each activity, plus the request
//!   restarting one that interrupts itself (15.8).
//! - **Integer variables** per slot: its status `st_X` (0 none, 1 accepted
//!   and delayed by interrupted instances, 2 accepted, 3 running its
//!   machine, 4 on its stop path), its state `q_X`, `due_X` (runs a codel
//!   in the current sweep), `pz_X` (its last yield was `pause::`) and
//!   `fl_X` (interrupted while its codel runs or is due). Per task: `cont_T`
//!   (an unpaused transition in this sweep), `busy_T` (the process is in a
//!   codel location), `cur_T` (the slot whose codel runs, 1-based) and
//!   `run_T` (that codel's key, 1-based, for the locks). Globally: `phase`
//!   (0 boot, 1 run, 2 drain after `kill`, 3 permanent stop paths, 4
//!   stopped, 5 failed start), `booted` (tasks spawned), `pstop` (task
//!   running its permanent stop path), `cph`/`crun` (control thread's
//!   location and running codel), and `done_S` for the services some
//!   `after`/`before` names.
//! - **Clocks**: per periodic task its period clock `p_T` (since its last
//!   tick), per task its execution clock `x_T`, and `x_ctl` for the
//!   control thread's codels.
//! - **Processes**: one per task ([`tasks`]): `sleep` before the first tick
//!   of a periodic task, `idle`, one location per codel of its slots, and
//!   `overrun`; and the control thread ([`control`]).
//! - **Atomic steps**: a tick, an activation, a codel end or a request is
//!   one edge whose statements ([`stmts`]) do the whole step: interruption,
//!   pending interrupters re-examined, boot order, shutdown, and the
//!   sweeps that follow at once.
//! - **Urgency**: codel begins (and the control thread's) are urgent
//!   edges with integer guards; [`Network::urgency`] says one is enabled.
//! - **GenoM3's resource FIFO** ([`fifo`]): `qlen`, `tpos_T`, `tslot_T`
//!   and `cpos`; a thread that cannot begin its codel takes a ticket (the
//!   urgent `ticket`/`cticket` edges) and begins at the queue's head.
//!
//! Labels: `codel_SERVICE_CODEL` on the locations where an activity's
//! codel runs (one per slot of the activity: [`Network::labels`] has one
//! entry per location), `overrun_TASK` on a periodic task's overrun
//! location.

mod control;
mod fifo;
pub mod read;
mod stmts;
mod tasks;

use std::collections::{BTreeMap, BTreeSet};

use genom_model::component::{CodelId, Component, ServiceId};
use genom_model::span::Span;
use genom_model::timed_automata::{
    Clock, ClockId, ClockRole, EventId, Expr, IntVar, Network, VarId,
};

use read::Read;

/// Why a GenoM3 component has no network.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum Genom3NetworkError {
    /// Not a GenoM3 component (or an interface).
    #[error("not a GenoM3 component")]
    NotGenom3,
    /// Something the network does not model yet.
    #[error("{0}")]
    Unsupported(String),
}

/// Event names and what they do.
const EVENTS: [(&str, &str); 11] = [
    ("tick", "a periodic task's tick"),
    (
        "overrun",
        "a tick finds the previous wake-up's work unfinished",
    ),
    ("wake", "an aperiodic task is activated"),
    ("begin", "a task begins a codel"),
    (
        "ticket",
        "a thread takes a ticket in GenoM3's resource FIFO for a codel it cannot begin",
    ),
    (
        "cticket",
        "the control thread takes a ticket for a control codel it cannot begin",
    ),
    ("finish", "a task's codel ends with one of its outcomes"),
    ("drop", "a codel killed by the shutdown is forgotten"),
    ("request", "the control thread handles a request"),
    ("cbegin", "the control thread begins a control codel"),
    ("cend", "a control codel ends"),
];

fn event(name: &str) -> EventId {
    let i = EVENTS.iter().position(|(n, _)| *n == name).unwrap_or(0);
    EventId(u32::try_from(i).unwrap_or(0))
}

use super::names::sanitize;

/// Location `i` of a process.
fn lid(i: usize) -> genom_model::timed_automata::LocationId {
    genom_model::timed_automata::LocationId(u32::try_from(i).unwrap_or(u32::MAX))
}

/// An edge from location `from` to `to` on event `ev` under `guard`, with
/// no clock guard, statement or label yet.
fn plain_edge(
    (from, to): (usize, usize),
    ev: &str,
    guard: Expr,
    span: Span,
    desc: String,
) -> genom_model::timed_automata::Edge {
    genom_model::timed_automata::Edge {
        from: lid(from),
        to: lid(to),
        event: event(ev),
        guard,
        clock_guard: Vec::new(),
        statements: Vec::new(),
        urgent: false,
        labels: Vec::new(),
        span,
        description: desc,
    }
}

/// The variables of one slot.
#[derive(Debug, Clone, Copy)]
struct SlotVars {
    st: VarId,
    q: VarId,
    due: VarId,
    pz: VarId,
    fl: VarId,
}

/// The variables and clocks of one task.
#[derive(Debug, Clone, Copy)]
struct TaskVars {
    cont: VarId,
    busy: VarId,
    cur: VarId,
    run: VarId,
    period: Option<(ClockId, i64, i64)>,
    exec: ClockId,
}

struct Builder<'a> {
    c: &'a Component,
    r: Read,
    net: Network,
    names: BTreeSet<String>,
    labels: BTreeSet<String>,
    /// Per activity codel: its label (shared by the activity's slots).
    codel_labels: BTreeMap<CodelId, String>,
    unit: u64,
    slots: Vec<SlotVars>,
    tasks: Vec<TaskVars>,
    phase: VarId,
    booted: VarId,
    pstop: VarId,
    cph: VarId,
    crun: VarId,
    ctl_clock: ClockId,
    done: BTreeMap<ServiceId, VarId>,
    /// Per key: its duration bounds in units (lower, upper; `None`:
    /// unbounded).
    bounds: Vec<(i64, Option<i64>)>,
    /// Per service: its control codels that take time (indices).
    timed_ctl: BTreeMap<ServiceId, Vec<usize>>,
    locals: usize,
    /// GenoM3's resource FIFO ([`fifo`]).
    fifo: fifo::Fifo,
}

/// Phase values.
const BOOT: i64 = 0;
const RUN: i64 = 1;
const DRAIN: i64 = 2;
const PERM_STOP: i64 = 3;
const STOPPED: i64 = 4;
const FAILED: i64 = 5;

/// The network of a GenoM3 component in GenoM3's timed semantics
/// ([`BuildNetwork::build_genom3`](super::BuildNetwork::build_genom3)).
pub(super) fn build(c: &Component) -> Result<Network, Genom3NetworkError> {
    let g = c
        .genom3
        .as_deref()
        .filter(|g| !g.is_interface)
        .ok_or(Genom3NetworkError::NotGenom3)?;
    let r = read::read(c, g);
    refuse(&r)?;
    let mut b = Builder::new(c, r);
    b.declare();
    b.initial_values();
    for t in 0..b.r.tasks.len() {
        b.task_process(t);
    }
    b.control_process();
    b.net.urgency = b.urgency();
    b.net.horizon = b.horizon();
    Ok(b.net)
}

/// What the network does not model: a task with more slots than
/// GenoM3's pool of 32 (a request could find it full).
fn refuse(r: &Read) -> Result<(), Genom3NetworkError> {
    for t in &r.tasks {
        if t.slots.len() > 32 {
            return Err(Genom3NetworkError::Unsupported(format!(
                "task `{}` needs more instance slots than GenoM3's 32",
                t.name
            )));
        }
    }
    Ok(())
}

impl<'a> Builder<'a> {
    fn new(c: &'a Component, r: Read) -> Self {
        let unit = r.unit_ns();
        let name = sanitize(&c.name.name);
        let mut names: BTreeSet<String> = ["urgency", "hurry", "calm", name.as_str()]
            .iter()
            .map(|s| (*s).to_owned())
            .collect();
        names.extend(EVENTS.iter().map(|(n, _)| (*n).to_owned()));
        let net = super::names::empty(name, unit, &EVENTS);
        Builder {
            c,
            r,
            net,
            names,
            labels: BTreeSet::new(),
            codel_labels: BTreeMap::new(),
            unit,
            slots: Vec::new(),
            tasks: Vec::new(),
            phase: VarId(0),
            booted: VarId(0),
            pstop: VarId(0),
            cph: VarId(0),
            crun: VarId(0),
            ctl_clock: ClockId(0),
            done: BTreeMap::new(),
            bounds: Vec::new(),
            timed_ctl: BTreeMap::new(),
            locals: 0,
            fifo: fifo::Fifo::default(),
        }
    }

    fn units(&self, ns: u64) -> i64 {
        i64::try_from(ns / self.unit).unwrap_or(i64::MAX / 4)
    }

    fn fresh(&mut self, want: &str) -> String {
        super::names::fresh(&mut self.names, want)
    }

    fn fresh_label(&mut self, want: &str) -> String {
        super::names::fresh(&mut self.labels, want)
    }

    /// A local variable name, unique in the network.
    fn local(&mut self) -> String {
        self.locals += 1;
        format!("tmp{}", self.locals)
    }

    fn int(&mut self, name: &str, max: i64, span: Span, description: String) -> VarId {
        let name = self.fresh(name);
        let id = VarId(u32::try_from(self.net.vars.len()).unwrap_or(u32::MAX));
        self.net.vars.push(IntVar {
            name,
            size: 1,
            min: 0,
            max,
            init: 0,
            array: false,
            span,
            description,
        });
        id
    }

    fn clock(&mut self, name: &str, role: ClockRole, span: Span, description: String) -> ClockId {
        let name = self.fresh(name);
        let id = ClockId(u32::try_from(self.net.clocks.len()).unwrap_or(u32::MAX));
        self.net.clocks.push(Clock {
            name,
            role,
            span,
            description,
        });
        id
    }

    /// Declares the clocks and variables, and reads the durations.
    fn declare(&mut self) {
        let span = self.c.name.span;
        self.declare_tasks();
        self.ctl_clock = self.clock(
            "x_ctl",
            ClockRole::Control,
            span,
            "time since the running control codel began".to_owned(),
        );
        self.declare_slots();
        self.declare_fifo();
        let n = i64::try_from(self.r.tasks.len()).unwrap_or(i64::MAX);
        self.phase = self.int(
            "phase",
            FAILED,
            span,
            "0 boot, 1 run, 2 drain after kill, 3 permanent stop paths, 4 stopped, 5 failed start"
                .to_owned(),
        );
        self.booted = self.int("booted", n, span, "tasks spawned at boot".to_owned());
        self.pstop = self.int(
            "pstop",
            n,
            span,
            "the task running its permanent stop path (shutdown)".to_owned(),
        );
        let keys = i64::try_from(self.r.keys.len()).unwrap_or(i64::MAX);
        self.crun = self.int(
            "crun",
            keys,
            span,
            "key + 1 of the running control codel (0: none)".to_owned(),
        );
        self.bounds = self.key_bounds();
        self.timed_ctl = self.r.contended_control_codels();
        let phases = self
            .timed_ctl
            .values()
            .map(|v| 2 * v.len())
            .sum::<usize>()
            .max(1);
        self.cph = self.int(
            "cph",
            i64::try_from(phases).unwrap_or(i64::MAX),
            span,
            "the control thread's location (0: idle)".to_owned(),
        );
        self.declare_done();
    }

    fn declare_tasks(&mut self) {
        let slots_max = self.r.slots.len();
        let keys = i64::try_from(self.r.keys.len()).unwrap_or(i64::MAX);
        for t in 0..self.r.tasks.len() {
            let task = self.r.tasks[t].clone();
            let period = task.period_ns.map(|p| {
                let clock = self.clock(
                    &format!("p_{}", task.name),
                    ClockRole::Period(task.id),
                    task.span,
                    format!("time since task {}'s last tick", task.name),
                );
                (clock, self.units(p), self.units(task.delay_ns))
            });
            let exec = self.clock(
                &format!("x_{}", task.name),
                ClockRole::Exec(task.id),
                task.span,
                format!("time since task {}'s running codel began", task.name),
            );
            let v = TaskVars {
                cont: self.int(
                    &format!("cont_{}", task.name),
                    1,
                    task.span,
                    format!(
                        "task {} made an unpaused transition in this sweep",
                        task.name
                    ),
                ),
                busy: self.int(
                    &format!("busy_{}", task.name),
                    1,
                    task.span,
                    format!("task {} is in a codel location", task.name),
                ),
                cur: self.int(
                    &format!("cur_{}", task.name),
                    i64::try_from(slots_max).unwrap_or(i64::MAX),
                    task.span,
                    format!("slot + 1 whose codel task {} runs (0: none)", task.name),
                ),
                run: self.int(
                    &format!("run_{}", task.name),
                    keys,
                    task.span,
                    format!("key + 1 of the codel task {} runs (0: none)", task.name),
                ),
                period,
                exec,
            };
            self.tasks.push(v);
        }
    }

    fn declare_slots(&mut self) {
        for i in 0..self.r.slots.len() {
            let slot = self.r.slots[i].clone();
            let span = slot.service.map_or(self.r.tasks[slot.task].span, |s| {
                self.c.services[s].name.span
            });
            let n = &slot.name;
            let states = i64::try_from(slot.fsm.states.len().max(1) - 1).unwrap_or(0);
            let v = SlotVars {
                st: self.int(
                    &format!("st_{n}"),
                    4,
                    span,
                    format!("{n}: 0 none, 1 delayed, 2 accepted, 3 running, 4 stopping"),
                ),
                q: self.int(&format!("q_{n}"), states, span, format!("{n}: its state")),
                due: self.int(
                    &format!("due_{n}"),
                    1,
                    span,
                    format!("{n}: runs a codel in this sweep"),
                ),
                pz: self.int(
                    &format!("pz_{n}"),
                    1,
                    span,
                    format!("{n}: paused (its last yield was pause::)"),
                ),
                fl: self.int(
                    &format!("fl_{n}"),
                    1,
                    span,
                    format!("{n}: interrupted while its codel runs or is due"),
                ),
            };
            self.slots.push(v);
        }
    }

    /// `done_S` for every service an `after` or `before` names.
    fn declare_done(&mut self) {
        let named: BTreeSet<ServiceId> = self
            .r
            .after
            .values()
            .chain(self.r.before.values())
            .flatten()
            .copied()
            .collect();
        for s in named {
            let name = self.c.services[s].name.name.clone();
            let span = self.c.services[s].name.span;
            let v = self.int(
                &format!("done_{name}"),
                1,
                span,
                format!("{name} completed successfully once"),
            );
            self.done.insert(s, v);
        }
    }

    /// Per key, its duration bounds in units.
    fn key_bounds(&self) -> Vec<(i64, Option<i64>)> {
        let mut out = vec![(0, Some(0)); self.r.keys.len()];
        for s in self.r.slots.iter().flat_map(|s| s.fsm.states.iter()) {
            let w = self.units(s.wcet_ns);
            out[s.key] = if s.is_async { (w, None) } else { (0, Some(w)) };
        }
        for k in self.r.ctl_codels.values().flatten() {
            out[k.key] = (0, Some(self.units(k.wcet_ns)));
        }
        out
    }

    /// The initial state: each permanent activity with a `start` codel in
    /// it (not yet due: it starts at its task's first sweep), and the boot
    /// order's first task.
    fn initial_values(&mut self) {
        for t in 0..self.r.tasks.len() {
            let Some(p) = self.r.tasks[t].perm else {
                continue;
            };
            if let Some(start) = self.r.slots[p].fsm.start {
                let s = self.slots[p];
                self.net.vars[s.st.0 as usize].init = 3;
                self.net.vars[s.q.0 as usize].init = stmts::idx(start);
            }
        }
        let (booted, phase) = self.initial_boot();
        self.net.vars[self.booted.0 as usize].init = booted;
        self.net.vars[self.phase.0 as usize].init = phase;
    }

    /// One more than the largest constant.
    fn horizon(&self) -> i64 {
        let mut m = 0;
        for t in &self.tasks {
            if let Some((_, p, d)) = t.period {
                m = m.max(p).max(d);
            }
        }
        for (lo, hi) in &self.bounds {
            m = m.max(*lo).max(hi.unwrap_or(0));
        }
        m + 1
    }
}
