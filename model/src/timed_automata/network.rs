//! The public types of a network: clocks, variables, locations, edges,
//! processes, events, labels and the network itself.

use crate::behaviour::PosId;
use crate::component::{CodelId, ServiceId, ThreadId};
use crate::span::Span;

use crate::timed_automata::{ClockId, CmpOp, EventId, Expr, LocationId, ProcessId, Stmt, VarId};

/// A clock constraint `clock op bound`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ClockConstraint {
    /// The clock.
    pub clock: ClockId,
    /// The comparison.
    pub op: CmpOp,
    /// The bound, in time units.
    pub bound: i64,
}

// ---------------------------------------------------------------------------
// The network
// ---------------------------------------------------------------------------

/// What a clock measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ClockRole {
    /// Time since the last wake-up of a periodic thread.
    Period(ThreadId),
    /// Time since the running codel of a thread started.
    Exec(ThreadId),
    /// Time since the running control codel started.
    Control,
    /// Time since the acknowledgment of the service's instance.
    Watchdog(ServiceId),
}

/// A clock.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Clock {
    /// Its identifier.
    pub name: String,
    /// What it measures.
    pub role: ClockRole,
    /// The thread, service or component it belongs to.
    pub span: Span,
    /// What it is, for comments.
    pub description: String,
}

/// An integer variable or array.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IntVar {
    /// Its identifier.
    pub name: String,
    /// 1 for a scalar, else the number of elements.
    pub size: u32,
    /// Smallest value.
    pub min: i64,
    /// Largest value.
    pub max: i64,
    /// Initial value (of every element).
    pub init: i64,
    /// Whether it is an array (even of size 1).
    pub array: bool,
    /// The element it belongs to.
    pub span: Span,
    /// What it holds, for comments.
    pub description: String,
}

/// A location of a process.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// Its identifier (unique in the process).
    pub name: String,
    /// The process starts here.
    pub initial: bool,
    /// Urgent location (time may not pass).
    pub urgent: bool,
    /// Committed location (time may not pass, and the next edge is one of
    /// this process).
    pub committed: bool,
    /// Invariant: constraints `clock <= bound`.
    pub invariant: Vec<ClockConstraint>,
    /// Labels for reachability queries.
    pub labels: Vec<String>,
    /// The element it stands for.
    pub span: Span,
    /// What it stands for.
    pub description: String,
}

/// An edge of a process.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Edge {
    /// Source location.
    pub from: LocationId,
    /// Target location.
    pub to: LocationId,
    /// Its event.
    pub event: EventId,
    /// Integer guard.
    pub guard: Expr,
    /// Clock guard (a conjunction).
    pub clock_guard: Vec<ClockConstraint>,
    /// What it does, in order.
    pub statements: Vec<Stmt>,
    /// Taken as soon as it is enabled (time may not pass while it is); the
    /// guard of an urgent edge has no clock constraint.
    pub urgent: bool,
    /// Labels of the codel running until this edge (on codel ends).
    pub labels: Vec<String>,
    /// The element it stands for.
    pub span: Span,
    /// Which service, codel and rule it stands for.
    pub description: String,
}

/// What a process stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProcessKind {
    /// The control thread: requests and control codels.
    Control,
    /// An execution thread.
    Thread(ThreadId),
    /// The max-time watchdog of a service.
    Watchdog(ServiceId),
}

/// A process (one timed automaton).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Process {
    /// Its identifier.
    pub name: String,
    /// What it stands for.
    pub kind: ProcessKind,
    /// Its locations.
    pub locations: Vec<Location>,
    /// Its edges.
    pub edges: Vec<Edge>,
    /// The element it stands for.
    pub span: Span,
    /// What it is.
    pub description: String,
}

impl Process {
    /// The location with this name.
    pub fn location(&self, name: &str) -> Option<LocationId> {
        self.locations
            .iter()
            .position(|l| l.name == name)
            .map(|i| LocationId(u32::try_from(i).unwrap_or(u32::MAX)))
    }
}

/// An event.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Event {
    /// Its identifier.
    pub name: String,
    /// What edges carrying it do.
    pub description: String,
}

/// A synchronisation: processes that take an edge with their event
/// together (`weak`: only if the process has such an edge enabled).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Sync {
    /// The participants.
    pub parts: Vec<SyncPart>,
}

/// One participant of a [`Sync`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SyncPart {
    /// The process.
    pub process: ProcessId,
    /// Its event.
    pub event: EventId,
    /// Weak participation.
    pub weak: bool,
}

/// What a label marks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LabelKind {
    /// The codel runs.
    Codel(CodelId),
    /// The thread overran its period.
    Overrun(ThreadId),
    /// The service exceeded its max-time (no unbounded loop).
    Timeout(ServiceId),
}

/// A label and the location that carries it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Label {
    /// The label.
    pub name: String,
    /// What it marks.
    pub kind: LabelKind,
    /// The process.
    pub process: ProcessId,
    /// The location.
    pub location: LocationId,
}

/// The variables of one service.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ServiceVars {
    /// The service.
    pub service: ServiceId,
    /// Its name.
    pub name: String,
    /// Position of its main instance (see `positions`).
    pub pos: VarId,
    /// 1 when it has a pending instance.
    pub pend: VarId,
    /// The wait bits of its pending instance, one per `stops` target.
    pub wait: Option<VarId>,
    /// Interrupted by its watchdog (`TIMEOUT` reply).
    pub timed_out: Option<VarId>,
    /// The machine position held by each value of `pos`.
    pub positions: Vec<PosId>,
    /// Has a `max-time` (its watchdog may interrupt it).
    pub watchdog: bool,
    /// The services whose instance delays this one (`delays`).
    pub delayers: Vec<ServiceId>,
}

/// The network of timed automata of a component.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Network {
    /// The component's name (the system's identifier).
    pub name: String,
    /// Nanoseconds per time unit.
    pub unit_ns: u64,
    /// A delay after which nothing new can happen without a discrete step:
    /// one more than the largest constant. Printers that bound delays
    /// (TChecker's urgency clock) use it.
    pub horizon: i64,
    /// The clocks.
    pub clocks: Vec<Clock>,
    /// The integer variables.
    pub vars: Vec<IntVar>,
    /// The events.
    pub events: Vec<Event>,
    /// The processes.
    pub processes: Vec<Process>,
    /// The synchronisations (none: steps are atomic edges).
    pub syncs: Vec<Sync>,
    /// Every label, in process and location order: one entry per location
    /// that carries it (a GenoM3 activity's codel label marks its location
    /// in each of the activity's slots, so a name may come more than once).
    pub labels: Vec<Label>,
    /// The variables of each service, by service id.
    pub services: Vec<ServiceVars>,
    /// Set by a watchdog probe: every other non-urgent edge is disabled.
    pub frozen: VarId,
    /// Some urgent edge is enabled (a thread may begin a codel or start a
    /// round, as the engine's urgency; or a watchdog may arm or disarm): an
    /// integer predicate, for printers without urgent edges.
    pub urgency: Expr,
}

impl Network {
    /// The clock.
    pub fn clock(&self, id: ClockId) -> &Clock {
        &self.clocks[id.0 as usize]
    }

    /// The variable.
    pub fn var(&self, id: VarId) -> &IntVar {
        &self.vars[id.0 as usize]
    }

    /// The event.
    pub fn event(&self, id: EventId) -> &Event {
        &self.events[id.0 as usize]
    }

    /// The process.
    pub fn process(&self, id: ProcessId) -> &Process {
        &self.processes[id.0 as usize]
    }

    /// The labels of one kind of fact, for queries.
    pub fn label(&self, kind: LabelKind) -> Option<&Label> {
        self.labels.iter().find(|l| l.kind == kind)
    }

    /// Numbers of locations and edges.
    pub fn size(&self) -> (usize, usize) {
        self.processes.iter().fold((0, 0), |(l, e), p| {
            (l + p.locations.len(), e + p.edges.len())
        })
    }
}
