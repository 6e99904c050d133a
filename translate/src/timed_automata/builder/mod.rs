//! The construction of a [`Network`] from a component and its local
//! machines: the builder's state (the static facts about services and
//! threads, the names in use) and the entry point [`build`].
//! Its children add, in order, the clocks and variables ([`clocks`]), the
//! control thread ([`control`]), the execution threads ([`threads`]) and the
//! watchdogs ([`watchdog`]), from shared layers below them: [`state`]
//! (positions as expressions), [`guards`], [`bookkeeping`], [`services`]
//! (interrupts, starts, ends, settle) and [`graph`] (locations and edges).

mod bookkeeping;
mod clocks;
mod control;
mod graph;
mod guards;
mod services;
mod state;
mod threads;
mod units;
mod watchdog;

use std::collections::{BTreeMap, BTreeSet};

use genom_model::behaviour::{Behaviour, PosId, Position, ServiceMachine};
use genom_model::component::{Component, ServiceId, StructureId, ThreadId};
use genom_model::span::Span;
use genom_model::timed_automata::{Clock, ClockId, ClockRole, EventId, IntVar, Network, VarId};

use units::{unit_ns, units};

/// Classes of positions, in the order their values are numbered.
fn position_class(p: Position) -> u8 {
    match p {
        Position::Idle => 0,
        Position::StopReady { .. } => 1,
        Position::Ready { .. } => 2,
        Position::Running {
            interrupted: false, ..
        } => 3,
        Position::Running {
            interrupted: true, ..
        }
        | Position::StopRunning { .. } => 4,
    }
}

/// Static facts about one service.
#[derive(Debug, Clone)]
struct Svc {
    id: ServiceId,
    name: String,
    pos: VarId,
    pend: VarId,
    wait: Option<VarId>,
    tmo: Option<VarId>,
    /// Value of `pos` → machine position.
    order: Vec<PosId>,
    /// Machine position → value of `pos`.
    value: Vec<i64>,
    /// First value of each class 1..4, and one past the last value.
    bounds: [i64; 5],
    stops: Vec<ServiceId>,
    delayers: Vec<ServiceId>,
    forbidders: Vec<ServiceId>,
    self_stop: bool,
    auto: bool,
    control_uses: Vec<(StructureId, bool)>,
    /// Thread index and slot.
    placement: Option<(usize, usize)>,
    /// Clocked watchdog: clock and max-time in units.
    watch: Option<(ClockId, i64)>,
    /// The watchdog fires exactly at the max-time (`on` has the invariant);
    /// else at any time from the horizon (`watch`'s bound) on.
    watch_exact: bool,
    /// 1 while the clocked watchdog is `on` (its location as a variable,
    /// so that the urgency of arming and disarming is an integer predicate).
    armed: Option<VarId>,
    /// Has a max-time.
    watchdog: bool,
    /// Control codel WCET in units, when it has a control codel.
    ctl_wcet: Option<i64>,
}

impl Svc {
    fn ready(&self) -> (i64, i64) {
        (self.bounds[0], self.bounds[2] - 1)
    }
    fn watchable(&self) -> (i64, i64) {
        (self.bounds[1], self.bounds[3] - 1)
    }
}

#[derive(Debug, Clone)]
struct Thr {
    id: ThreadId,
    name: String,
    period: Option<i64>,
    members: Vec<ServiceId>,
    period_clock: Option<ClockId>,
    exec_clock: ClockId,
    elig: VarId,
    ord: VarId,
    turn: VarId,
    busy: VarId,
}

struct Builder<'a> {
    c: &'a Component,
    b: &'a Behaviour,
    net: Network,
    names: BTreeSet<String>,
    label_names: BTreeSet<String>,
    svcs: Vec<Svc>,
    thrs: Vec<Thr>,
    locks: BTreeMap<StructureId, (VarId, VarId)>,
    ctl: Option<VarId>,
    ctl_clock: Option<ClockId>,
    init_done: VarId,
    wcet: Vec<i64>,
    locals: usize,
}

/// Builds the network of a component from its local machines
/// ([`BuildNetwork::build`](super::BuildNetwork::build)).
pub(super) fn build(c: &Component, b: &Behaviour) -> Network {
    let mut bld = Builder::new(c, b);
    bld.declare();
    bld.control_process();
    for k in 0..bld.thrs.len() {
        bld.thread_process(k);
    }
    for s in c.services.ids() {
        bld.watchdog_process(s);
    }
    bld.net.urgency = bld.network_urgency();
    bld.net
}

/// Event names and what they do.
const EVENTS: [(&str, &str); 15] = [
    ("setup", "the component starts"),
    (
        "request",
        "a client request is handled by the control thread",
    ),
    ("accept", "the control codel accepts the request"),
    ("reject", "the control codel rejects the request"),
    ("begin", "a thread begins a codel"),
    ("finish", "a codel ends with one of its outcomes"),
    ("wake", "a periodic thread wakes up"),
    (
        "overrun",
        "a periodic thread wakes up with work of its previous period left",
    ),
    ("round", "an aperiodic thread starts a round"),
    ("arm", "a watchdog follows its service's instance"),
    ("disarm", "a watchdog stops following its service"),
    ("watchdog", "the max-time watchdog interrupts its service"),
    (
        "probe",
        "the watchdog checks whether time can pass its max-time",
    ),
    ("exceed", "the service is still running after its max-time"),
    (
        "resume",
        "the watchdog's probe ends: time cannot pass the max-time",
    ),
];

fn event_id(name: &str) -> EventId {
    let i = EVENTS.iter().position(|(n, _)| *n == name).unwrap_or(0);
    EventId(u32::try_from(i).unwrap_or(0))
}

use super::names::sanitize;

impl<'a> Builder<'a> {
    fn new(c: &'a Component, b: &'a Behaviour) -> Self {
        let all: Vec<ServiceId> = c.services.ids().collect();
        let unit = unit_ns(c, &all);
        let wcet = c
            .codels
            .values()
            .map(|k| k.wcet.map_or(0, |w| units(w.ns, unit)))
            .collect();
        let mut names = BTreeSet::new();
        // Names the printers add.
        for n in ["urgency", "hurry", "delay_cycle"] {
            names.insert(n.to_owned());
        }
        let name = sanitize(&c.name.name);
        names.insert(name.clone());
        let net = super::names::empty(name, unit, &EVENTS);
        for (n, _) in EVENTS {
            names.insert(n.to_owned());
        }
        Builder {
            c,
            b,
            net,
            names,
            label_names: BTreeSet::new(),
            svcs: Vec::new(),
            thrs: Vec::new(),
            locks: BTreeMap::new(),
            ctl: None,
            ctl_clock: None,
            init_done: VarId(0),
            wcet,
            locals: 0,
        }
    }

    fn fresh(&mut self, want: &str) -> String {
        super::names::fresh(&mut self.names, want)
    }

    fn fresh_label(&mut self, want: &str) -> String {
        super::names::fresh(&mut self.label_names, want)
    }

    fn local(&mut self) -> String {
        self.locals += 1;
        format!("tmp{}", self.locals)
    }

    #[allow(clippy::too_many_arguments)]
    fn int(
        &mut self,
        name: &str,
        size: Option<u32>,
        min: i64,
        max: i64,
        init: i64,
        span: Span,
        description: String,
    ) -> VarId {
        let name = self.fresh(name);
        let id = VarId(u32::try_from(self.net.vars.len()).unwrap_or(u32::MAX));
        self.net.vars.push(IntVar {
            name,
            size: size.unwrap_or(1),
            min,
            max,
            init,
            array: size.is_some(),
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

    fn svc(&self, s: ServiceId) -> &Svc {
        &self.svcs[s.0 as usize]
    }

    fn machine(&self, s: ServiceId) -> &'a ServiceMachine {
        self.b.machine(s)
    }

    fn sname(&self, s: ServiceId) -> &'a str {
        &self.c.services[s].name.name
    }
}
