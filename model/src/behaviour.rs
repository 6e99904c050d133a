//! The local behaviour of each service instance (LANGUAGE.md section 3), as
//! a finite table of *positions* and the steps between them. The explorer,
//! the Petri net, the timed automata and the exports are all built from
//! this one table, so they cannot disagree on what a codel step means.
//!
//! A service's main instance slot is in exactly one position:
//!
//! - `Idle`: no active or stopping instance;
//! - `Ready { codel, on_inter }`: active, its next codel is `codel`, not yet
//!   started. `on_inter` is where an interrupt at this point leads: the
//!   `on-inter` of the codel it last ran, or `None` (end at once with
//!   `INTERRUPTED`), which is also the case before the start codel ran;
//! - `Running { codel, interrupted }`: its thread runs `codel`; an interrupt
//!   during the codel only sets `interrupted`, taken into account when the
//!   codel ends (then the codel's `on-inter` is taken instead of its outcome);
//! - `StopReady { codel }`, `StopRunning { codel }`: interrupted (stopping),
//!   following the `next` of its inter codels; not interrupted again.
//!
//! The pending instance of a service (acknowledged, not started) is not a
//! position: it is a separate slot handled by the explorer.

use std::collections::BTreeMap;

use crate::component::{CodelId, Component, Outcome, ServiceId, ThreadId};
use crate::kinds::ServiceKind;

/// Index of a position in a [`ServiceMachine`]; `0` is `Idle`.
pub type PosId = u16;

/// The idle position.
pub const IDLE: PosId = 0;

/// Where a service's main instance is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Position {
    /// No active or stopping instance.
    Idle,
    /// Active, about to run `codel`; an interrupt now leads to `on_inter`
    /// (or ends the instance when `None`).
    Ready {
        /// The next codel.
        codel: CodelId,
        /// The inter codel an interrupt leads to.
        on_inter: Option<CodelId>,
    },
    /// Active, running `codel`.
    Running {
        /// The codel being run.
        codel: CodelId,
        /// Interrupted while running: the codel's `on-inter` follows.
        interrupted: bool,
    },
    /// Stopping, about to run `codel`.
    StopReady {
        /// The next codel.
        codel: CodelId,
    },
    /// Stopping, running `codel`.
    StopRunning {
        /// The codel being run.
        codel: CodelId,
    },
}

impl Position {
    /// The codel at this position, if any.
    pub fn codel(self) -> Option<CodelId> {
        match self {
            Position::Idle => None,
            Position::Ready { codel, .. }
            | Position::Running { codel, .. }
            | Position::StopReady { codel }
            | Position::StopRunning { codel } => Some(codel),
        }
    }

    /// True while a codel runs (the thread is busy).
    pub fn is_running(self) -> bool {
        matches!(
            self,
            Position::Running { .. } | Position::StopRunning { .. }
        )
    }

    /// True once interrupted (stopping, or running with the interrupt noted).
    pub fn is_interrupted(self) -> bool {
        matches!(
            self,
            Position::Running {
                interrupted: true,
                ..
            } | Position::StopReady { .. }
                | Position::StopRunning { .. }
        )
    }
}

/// How an instance ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Ending {
    /// Success (`end` reached while active).
    Success,
    /// A report (index in the service's reports).
    Report(usize),
    /// Interrupted: `INTERRUPTED`, or `TIMEOUT` when the watchdog did it.
    Interrupted,
}

/// Where a step leads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Effect {
    /// To another position.
    Goto(PosId),
    /// The instance ends; the slot becomes idle.
    End(Ending),
}

/// One way a running codel can finish.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Finish {
    /// The outcome the codel yields (`None` when the pending interrupt
    /// overrides it).
    pub outcome: Option<Outcome>,
    /// Where it leads.
    pub effect: Effect,
}

/// The local machine of one service.
#[derive(Debug, Clone)]
pub struct ServiceMachine {
    /// The service.
    pub service: ServiceId,
    /// Its thread, when it runs on one.
    pub thread: Option<ThreadId>,
    /// `auto` service.
    pub auto: bool,
    /// Has a `max-time` (the watchdog can interrupt it).
    pub watchdog: bool,
    /// Positions; index 0 is `Idle`.
    pub positions: Vec<Position>,
    /// The position a started instance begins at (`Ready` at the start
    /// codel); `None` for services without a start codel, which complete as
    /// soon as they start.
    pub start: Option<PosId>,
    /// For `Ready`/`StopReady` positions: the running position.
    pub begin: Vec<Option<PosId>>,
    /// For running positions: the ways the codel can finish.
    pub finish: Vec<Vec<Finish>>,
    /// The effect of an interrupt at each position (`None`: no effect,
    /// because idle or already interrupted).
    pub interrupt: Vec<Option<Effect>>,
    /// Active positions from which the instance may never end by itself: a
    /// loop with no `max-time` to bound it (for starvation verdicts).
    pub may_never_end: Vec<bool>,
    /// Interrupted positions from which the inter codels can loop forever
    /// (for `unbounded-interrupt`).
    pub stop_loops: Vec<bool>,
    /// The active codels can loop forever from the start codel (an
    /// unbounded loop: only a watchdog can bound such a service).
    pub active_loop: bool,
}

impl ServiceMachine {
    /// Builds the machine of a service by exploring its positions from the
    /// start codel.
    pub fn new(c: &Component, service: ServiceId) -> ServiceMachine {
        let s = &c.services[service];
        let mut b = Builder {
            c,
            index: BTreeMap::new(),
            positions: Vec::new(),
        };
        b.intern(Position::Idle);
        let start = s.start.map(|codel| {
            b.intern(Position::Ready {
                codel,
                on_inter: None,
            })
        });
        let (mut begin, mut finish, mut interrupt) = (Vec::new(), Vec::new(), Vec::new());
        let mut i = 0;
        while i < b.positions.len() {
            let p = b.positions[i];
            begin.push(b.begin(p));
            finish.push(b.finish(p));
            interrupt.push(b.interrupt(p));
            i += 1;
        }
        let mut m = ServiceMachine {
            service,
            thread: s.thread.map(|t| t.id),
            auto: s.kind == ServiceKind::Auto,
            watchdog: s.max_time.is_some(),
            positions: b.positions,
            start,
            begin,
            finish,
            interrupt,
            may_never_end: Vec::new(),
            stop_loops: Vec::new(),
            active_loop: false,
        };
        m.stop_loops = m.loops(|p| p.is_interrupted());
        m.may_never_end = m.never_ending();
        let active = m.loops(|p| p != Position::Idle && !p.is_interrupted());
        m.active_loop = m.start.is_some_and(|p| active[usize::from(p)]);
        m
    }

    /// Successor positions by codel steps only (no interrupts).
    pub fn steps(&self, p: PosId) -> Vec<PosId> {
        let mut out: Vec<PosId> = self.begin[usize::from(p)].into_iter().collect();
        out.extend(
            self.finish[usize::from(p)]
                .iter()
                .filter_map(|f| match f.effect {
                    Effect::Goto(q) => Some(q),
                    Effect::End(_) => None,
                }),
        );
        out
    }

    /// For each position: whether, staying within positions accepted by
    /// `keep`, codel steps can go on forever (a cycle is reachable). Linear:
    /// the cycles are the strongly connected sets of kept positions (or a
    /// position that steps to itself), then every kept position that
    /// reaches one, searched backwards from them.
    fn loops(&self, keep: impl Fn(Position) -> bool) -> Vec<bool> {
        use petgraph::Direction::Incoming;
        use petgraph::graph::{DiGraph, NodeIndex};
        let n = self.positions.len();
        let kept: Vec<bool> = self.positions.iter().map(|&p| keep(p)).collect();
        let mut g: DiGraph<(), ()> = DiGraph::with_capacity(n, n);
        let nodes: Vec<NodeIndex> = (0..n).map(|_| g.add_node(())).collect();
        for p in (0..n).filter(|&p| kept[p]) {
            for q in self.kept_steps(p, &kept) {
                g.add_edge(nodes[p], nodes[q], ());
            }
        }
        let mut reaches_cycle = vec![false; n];
        let mut stack = Vec::new();
        for scc in petgraph::algo::tarjan_scc(&g) {
            if scc.len() > 1 || g.contains_edge(scc[0], scc[0]) {
                for v in scc {
                    reaches_cycle[v.index()] = true;
                    stack.push(v);
                }
            }
        }
        while let Some(q) = stack.pop() {
            for p in g.neighbors_directed(q, Incoming) {
                if !std::mem::replace(&mut reaches_cycle[p.index()], true) {
                    stack.push(p);
                }
            }
        }
        reaches_cycle
    }

    fn kept_steps(&self, p: usize, kept: &[bool]) -> Vec<usize> {
        let Ok(id) = PosId::try_from(p) else {
            return Vec::new();
        };
        self.steps(id)
            .into_iter()
            .map(usize::from)
            .filter(|&q| kept[q])
            .collect()
    }

    /// `may_never_end` for every position (see the field): an active
    /// instance of a service without `max-time` that can loop forever (an
    /// `auto` service that loops is one; one that ends, or has a watchdog,
    /// is not). Interrupted instances that loop are the separate
    /// `unbounded-interrupt` verdict.
    fn never_ending(&self) -> Vec<bool> {
        let active_loops = self.loops(|p| p != Position::Idle && !p.is_interrupted());
        self.positions
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                let active = p != Position::Idle && !p.is_interrupted();
                active && !self.watchdog && active_loops[i]
            })
            .collect()
    }

    /// The position with this value, if it exists.
    pub fn find(&self, p: Position) -> Option<PosId> {
        self.positions
            .iter()
            .position(|&x| x == p)
            .and_then(|i| PosId::try_from(i).ok())
    }
}

struct Builder<'c> {
    c: &'c Component,
    index: BTreeMap<Position, PosId>,
    positions: Vec<Position>,
}

impl Builder<'_> {
    fn intern(&mut self, p: Position) -> PosId {
        if let Some(&id) = self.index.get(&p) {
            return id;
        }
        let id = PosId::try_from(self.positions.len()).unwrap_or(PosId::MAX);
        self.positions.push(p);
        self.index.insert(p, id);
        id
    }

    fn on_inter(&self, codel: CodelId) -> Option<CodelId> {
        self.c.codels[codel].on_inter.map(|r| r.id)
    }

    fn begin(&mut self, p: Position) -> Option<PosId> {
        match p {
            Position::Ready { codel, .. } => Some(self.intern(Position::Running {
                codel,
                interrupted: false,
            })),
            Position::StopReady { codel } => Some(self.intern(Position::StopRunning { codel })),
            _ => None,
        }
    }

    fn finish(&mut self, p: Position) -> Vec<Finish> {
        match p {
            Position::Running {
                codel,
                interrupted: false,
            } => {
                let after = self.on_inter(codel);
                self.c.codels[codel]
                    .outcomes()
                    .into_iter()
                    .map(|o| {
                        let effect = match o {
                            Outcome::Codel(next) => Effect::Goto(self.intern(Position::Ready {
                                codel: next,
                                on_inter: after,
                            })),
                            Outcome::End => Effect::End(Ending::Success),
                            Outcome::Report(r) => Effect::End(Ending::Report(r)),
                        };
                        Finish {
                            outcome: Some(o),
                            effect,
                        }
                    })
                    .collect()
            }
            Position::Running {
                codel,
                interrupted: true,
            } => {
                let effect = match self.on_inter(codel) {
                    Some(i) => Effect::Goto(self.intern(Position::StopReady { codel: i })),
                    None => Effect::End(Ending::Interrupted),
                };
                vec![Finish {
                    outcome: None,
                    effect,
                }]
            }
            Position::StopRunning { codel } => self.c.codels[codel]
                .outcomes()
                .into_iter()
                .map(|o| {
                    let effect = match o {
                        Outcome::Codel(next) => {
                            Effect::Goto(self.intern(Position::StopReady { codel: next }))
                        }
                        Outcome::End => Effect::End(Ending::Interrupted),
                        Outcome::Report(r) => Effect::End(Ending::Report(r)),
                    };
                    Finish {
                        outcome: Some(o),
                        effect,
                    }
                })
                .collect(),
            _ => Vec::new(),
        }
    }

    fn interrupt(&mut self, p: Position) -> Option<Effect> {
        match p {
            Position::Ready {
                on_inter: Some(i), ..
            } => Some(Effect::Goto(self.intern(Position::StopReady { codel: i }))),
            Position::Ready { on_inter: None, .. } => Some(Effect::End(Ending::Interrupted)),
            Position::Running {
                codel,
                interrupted: false,
            } => Some(Effect::Goto(self.intern(Position::Running {
                codel,
                interrupted: true,
            }))),
            _ => None,
        }
    }
}

/// The local machines of every service of a component.
#[derive(Debug, Clone)]
pub struct Behaviour {
    /// One machine per service, by service id.
    pub machines: Vec<ServiceMachine>,
}

impl Behaviour {
    /// Builds every machine.
    pub fn new(c: &Component) -> Behaviour {
        Behaviour {
            machines: c
                .services
                .ids()
                .map(|s| ServiceMachine::new(c, s))
                .collect(),
        }
    }

    /// The machine of a service.
    pub fn machine(&self, s: ServiceId) -> &ServiceMachine {
        &self.machines[s.0 as usize]
    }
}
