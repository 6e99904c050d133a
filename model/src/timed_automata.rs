//! The component as a network of timed automata: an intermediate
//! representation that the UPPAAL and TChecker exports print, built from
//! the [`Component`] and its [`Behaviour`] so that it encodes exactly the
//! timed semantics of the zone engine (`checker/src/timed/model.rs`, on top
//! of the untimed semantics of `checker/src/engine/system.rs`).
//!
//! The construction (docs/semantics.md section 7 sums it up; the exports'
//! pages docs/exports/uppaal.md and docs/exports/tchecker.md give the
//! printed forms, queries and labels):
//!
//! - **Time unit**: the GCD of every duration of the component (periods,
//!   codel WCETs, control codel WCETs, max-times of services with a start
//!   codel), as in the engine; every constant is an integer number of units.
//! - **Clocks**: one period clock per periodic thread, one execution clock
//!   per thread, one clock for the control codel, one watchdog clock per
//!   service with a `max-time` and no unbounded loop.
//! - **Integer variables** hold the discrete state: per service its
//!   position (a permutation of the machine's positions, so that the ready,
//!   running and watchable positions are intervals), its pending flag, the
//!   wait bits of its pending instance and its `timed_out` flag; per thread
//!   its eligible set, acknowledgment order, current turn and busy flag;
//!   per lockable structure the number of running codels reading and
//!   writing it; the service whose control codel runs; `init_done`; and
//!   `frozen` (see watchdogs).
//! - **Processes**: the control thread (a committed start location whose
//!   edge performs the component start, `idle`, and one location per
//!   control codel), one process per execution thread (`idle`, one location
//!   per codel it may run, `overrun`), and one watchdog process per service
//!   with a `max-time`.
//! - **Atomic steps**: a request, a codel end or a watchdog is one edge whose
//!   statement performs the whole step of the engine: interrupts, the
//!   urgent starts of step 7 (a `while` loop), initialisation and auto
//!   services, and the bookkeeping of clocks, eligible sets and orders.
//! - **Urgency**: edges marked [`Edge::urgent`] (codel begins, rounds of
//!   aperiodic threads, watchdog arming) are taken as soon as they are
//!   enabled; their guards use integer variables only. Each printer
//!   expresses this in its language.
//! - **Violations**: a thread overrun leads to a committed location without
//!   edges (nothing can happen after it, as in the engine); a running codel
//!   that has used its whole WCET at a wake-up instant ends before the
//!   wake-up (its overrun edge needs `exec < WCET`); a max-time
//!   exceeded is found by a watchdog *probe*: at its max-time, in a
//!   non-urgent state, the watchdog may freeze every other process and let
//!   time pass without its own invariant; if its clock then exceeds the
//!   max-time, it reaches its `late` location, otherwise it resumes.
//!
//! Labels: `codel_SERVICE_CODEL` on the location where that codel runs,
//! `overrun_THREAD` and `timeout_SERVICE` on the violation locations.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

use crate::behaviour::{Behaviour, Effect, Ending, IDLE, PosId, Position, ServiceMachine};
use crate::component::{
    CodelId, Component, ServiceId, StructureId, ThreadId, uses_conflict as conflict,
};
use crate::define_id;
use crate::kinds::ServiceKind;
use crate::span::Span;

define_id!(
    /// A clock of a [`Network`].
    ClockId
);
define_id!(
    /// An integer variable (or array) of a [`Network`].
    VarId
);
define_id!(
    /// A process of a [`Network`].
    ProcessId
);
define_id!(
    /// A location of one process.
    LocationId
);
define_id!(
    /// An event (edge label for synchronisations).
    EventId
);

// ---------------------------------------------------------------------------
// Expressions and statements
// ---------------------------------------------------------------------------

/// A comparison operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum CmpOp {
    /// `==`
    Eq,
    /// `!=`
    Ne,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
}

impl CmpOp {
    /// The C spelling (both printers use it).
    pub fn symbol(self) -> &'static str {
        match self {
            CmpOp::Eq => "==",
            CmpOp::Ne => "!=",
            CmpOp::Lt => "<",
            CmpOp::Le => "<=",
            CmpOp::Gt => ">",
            CmpOp::Ge => ">=",
        }
    }

    /// The negated operator.
    pub fn negate(self) -> CmpOp {
        match self {
            CmpOp::Eq => CmpOp::Ne,
            CmpOp::Ne => CmpOp::Eq,
            CmpOp::Lt => CmpOp::Ge,
            CmpOp::Le => CmpOp::Gt,
            CmpOp::Gt => CmpOp::Le,
            CmpOp::Ge => CmpOp::Lt,
        }
    }

    fn eval(self, a: i64, b: i64) -> bool {
        match self {
            CmpOp::Eq => a == b,
            CmpOp::Ne => a != b,
            CmpOp::Lt => a < b,
            CmpOp::Le => a <= b,
            CmpOp::Gt => a > b,
            CmpOp::Ge => a >= b,
        }
    }
}

/// An integer expression over the network's integer variables (booleans are
/// integers: 0 is false, anything else true). Built through the smart
/// constructors, which fold constants.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Expr {
    /// A constant.
    Const(i64),
    /// A scalar variable.
    Var(VarId),
    /// An element of an array variable.
    Elem(VarId, Box<Expr>),
    /// A local variable of the statement being executed.
    Local(String),
    /// A sum.
    Add(Vec<Expr>),
    /// A difference.
    Sub(Box<Expr>, Box<Expr>),
    /// A comparison (0 or 1).
    Cmp(CmpOp, Box<Expr>, Box<Expr>),
    /// Negation (0 or 1).
    Not(Box<Expr>),
    /// Conjunction (0 or 1).
    And(Vec<Expr>),
    /// Disjunction (0 or 1).
    Or(Vec<Expr>),
    /// `if c then a else b`.
    Ite(Box<Expr>, Box<Expr>, Box<Expr>),
}

impl Expr {
    /// True.
    pub const TRUE: Expr = Expr::Const(1);
    /// False.
    pub const FALSE: Expr = Expr::Const(0);

    /// A constant.
    pub fn int(v: i64) -> Expr {
        Expr::Const(v)
    }

    /// A scalar variable.
    pub fn var(v: VarId) -> Expr {
        Expr::Var(v)
    }

    /// An array element with a constant index.
    pub fn elem(v: VarId, i: i64) -> Expr {
        Expr::Elem(v, Box::new(Expr::Const(i)))
    }

    /// An array element with a computed index.
    pub fn elem_at(v: VarId, i: Expr) -> Expr {
        Expr::Elem(v, Box::new(i))
    }

    /// The constant value, if constant.
    pub fn as_const(&self) -> Option<i64> {
        match self {
            Expr::Const(c) => Some(*c),
            _ => None,
        }
    }

    /// Whether the expression is the constant true.
    pub fn is_true(&self) -> bool {
        self.as_const().is_some_and(|c| c != 0)
    }

    /// Whether the expression is the constant false.
    pub fn is_false(&self) -> bool {
        self.as_const() == Some(0)
    }

    /// Whether the expression's value is always 0 or 1.
    pub fn is_boolean(&self) -> bool {
        matches!(
            self,
            Expr::Cmp(..) | Expr::Not(_) | Expr::And(_) | Expr::Or(_) | Expr::Const(0 | 1)
        )
    }

    /// A comparison, folded when both sides are constants.
    pub fn cmp(op: CmpOp, a: Expr, b: Expr) -> Expr {
        match (a.as_const(), b.as_const()) {
            (Some(x), Some(y)) => Expr::bool(op.eval(x, y)),
            _ => Expr::Cmp(op, Box::new(a), Box::new(b)),
        }
    }

    /// `a == b`.
    pub fn eq(a: Expr, b: Expr) -> Expr {
        Expr::cmp(CmpOp::Eq, a, b)
    }

    /// `a != b`.
    pub fn ne(a: Expr, b: Expr) -> Expr {
        Expr::cmp(CmpOp::Ne, a, b)
    }

    /// A boolean constant.
    pub fn bool(b: bool) -> Expr {
        Expr::Const(i64::from(b))
    }

    /// Negation, folded.
    pub fn negation(e: Expr) -> Expr {
        match e {
            Expr::Const(c) => Expr::bool(c == 0),
            Expr::Not(inner) if inner.is_boolean() => *inner,
            Expr::Cmp(op, a, b) => Expr::Cmp(op.negate(), a, b),
            other => Expr::Not(Box::new(other)),
        }
    }

    /// Conjunction, flattened and folded.
    pub fn and(items: impl IntoIterator<Item = Expr>) -> Expr {
        let mut out = Vec::new();
        for e in items {
            match e {
                Expr::And(inner) => out.extend(inner),
                e if e.is_true() => {}
                e if e.is_false() => return Expr::FALSE,
                e => out.push(e),
            }
        }
        dedup_keep_order(&mut out);
        match out.len() {
            0 => Expr::TRUE,
            1 => out.pop().unwrap_or(Expr::TRUE),
            _ => Expr::And(out),
        }
    }

    /// Disjunction, flattened and folded.
    pub fn or(items: impl IntoIterator<Item = Expr>) -> Expr {
        let mut out = Vec::new();
        for e in items {
            match e {
                Expr::Or(inner) => out.extend(inner),
                e if e.is_false() => {}
                e if e.is_true() => return Expr::TRUE,
                e => out.push(e),
            }
        }
        dedup_keep_order(&mut out);
        match out.len() {
            0 => Expr::FALSE,
            1 => out.pop().unwrap_or(Expr::FALSE),
            _ => Expr::Or(out),
        }
    }

    /// A sum, folded.
    pub fn add(items: impl IntoIterator<Item = Expr>) -> Expr {
        let mut constant = 0;
        let mut out = Vec::new();
        for e in items {
            match e {
                Expr::Const(c) => constant += c,
                Expr::Add(inner) => out.extend(inner),
                e => out.push(e),
            }
        }
        if constant != 0 || out.is_empty() {
            out.push(Expr::Const(constant));
        }
        if out.len() == 1 {
            out.pop().unwrap_or(Expr::Const(0))
        } else {
            Expr::Add(out)
        }
    }

    /// A difference.
    pub fn minus(a: Expr, b: Expr) -> Expr {
        match (a.as_const(), b.as_const()) {
            (Some(x), Some(y)) => Expr::Const(x - y),
            (_, Some(0)) => a,
            _ => Expr::Sub(Box::new(a), Box::new(b)),
        }
    }

    /// `if c then a else b`, folded.
    pub fn ite(c: Expr, a: Expr, b: Expr) -> Expr {
        if c.is_true() {
            a
        } else if c.is_false() || a == b {
            b
        } else if a == Expr::Const(1) && b == Expr::Const(0) && c.is_boolean() {
            c
        } else {
            Expr::Ite(Box::new(c), Box::new(a), Box::new(b))
        }
    }

    /// `lo <= e <= hi` (false when the interval is empty).
    pub fn within(e: &Expr, lo: i64, hi: i64) -> Expr {
        if lo > hi {
            Expr::FALSE
        } else if lo == hi {
            Expr::eq(e.clone(), Expr::Const(lo))
        } else {
            Expr::and([
                Expr::cmp(CmpOp::Ge, e.clone(), Expr::Const(lo)),
                Expr::cmp(CmpOp::Le, e.clone(), Expr::Const(hi)),
            ])
        }
    }
}

fn dedup_keep_order(v: &mut Vec<Expr>) {
    let mut seen: Vec<Expr> = Vec::new();
    v.retain(|e| {
        if seen.contains(e) {
            false
        } else {
            seen.push(e.clone());
            true
        }
    });
}

/// What a statement assigns.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum LValue {
    /// A scalar variable.
    Var(VarId),
    /// An array element.
    Elem(VarId, Expr),
    /// A local variable.
    Local(String),
}

/// A statement of an edge. Local variables are declared once per edge
/// statement, with names unique in it and distinct from every global name.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Stmt {
    /// Declares a local integer variable with its initial value.
    Local(String, Expr),
    /// An integer assignment.
    Assign(LValue, Expr),
    /// `if c then ... else ... end`.
    If(Expr, Vec<Stmt>, Vec<Stmt>),
    /// `while c do ... end`.
    While(Expr, Vec<Stmt>),
    /// Resets a clock to 0.
    Reset(ClockId),
}

impl Stmt {
    /// `v = e`.
    pub fn set(v: VarId, e: Expr) -> Stmt {
        Stmt::Assign(LValue::Var(v), e)
    }

    /// `v[i] = e`.
    pub fn set_elem(v: VarId, i: i64, e: Expr) -> Stmt {
        Stmt::Assign(LValue::Elem(v, Expr::Const(i)), e)
    }

    /// `if c then a else b end`, folded; pushed onto `out`.
    pub fn push_if(out: &mut Vec<Stmt>, c: Expr, a: Vec<Stmt>, b: Vec<Stmt>) {
        if c.is_true() {
            out.extend(a);
        } else if c.is_false() {
            out.extend(b);
        } else if !(a.is_empty() && b.is_empty()) {
            out.push(Stmt::If(c, a, b));
        }
    }
}

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
    /// Every label, in process and location order.
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

// ---------------------------------------------------------------------------
// Identifiers and keyword renaming
// ---------------------------------------------------------------------------

/// Reserved words of TChecker and UPPAAL (declarations, statements,
/// queries and built-in functions). An identifier of the network equal to
/// one of them is renamed with `_` suffixes, the same way in both exports.
pub const KEYWORDS: &[&str] = &[
    "A",
    "E",
    "M",
    "abs",
    "and",
    "assign",
    "bool",
    "break",
    "broadcast",
    "case",
    "chan",
    "clock",
    "commit",
    "committed",
    "const",
    "continue",
    "control",
    "deadlock",
    "default",
    "do",
    "double",
    "edge",
    "else",
    "end",
    "event",
    "exists",
    "false",
    "for",
    "forall",
    "guard",
    "if",
    "imply",
    "init",
    "int",
    "local",
    "location",
    "max",
    "meta",
    "min",
    "new",
    "nop",
    "not",
    "or",
    "pow",
    "priority",
    "process",
    "return",
    "scalar",
    "select",
    "sqrt",
    "state",
    "string",
    "struct",
    "sum",
    "switch",
    "sync",
    "system",
    "then",
    "trans",
    "true",
    "typedef",
    "urgent",
    "void",
    "while",
];

/// A consistent renaming of identifiers that clash with [`KEYWORDS`].
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Renaming {
    map: BTreeMap<String, String>,
    used: BTreeSet<String>,
    /// The renamed identifiers, in order: (original, new).
    pub renamed: Vec<(String, String)>,
}

impl Renaming {
    /// The renaming of every identifier of the network (globals and
    /// locations; location names never clash with globals' renamings as
    /// they are scoped by their process). `extra` are names the printer
    /// adds.
    pub fn new(net: &Network, extra: &[&str]) -> Renaming {
        let mut names: Vec<&str> = vec![net.name.as_str()];
        names.extend(net.events.iter().map(|e| e.name.as_str()));
        names.extend(net.clocks.iter().map(|c| c.name.as_str()));
        names.extend(net.vars.iter().map(|v| v.name.as_str()));
        names.extend(net.processes.iter().map(|p| p.name.as_str()));
        for p in &net.processes {
            names.extend(p.locations.iter().map(|l| l.name.as_str()));
        }
        names.extend(extra.iter().copied());
        let mut r = Renaming::default();
        for n in &names {
            if !KEYWORDS.contains(n) {
                r.used.insert((*n).to_owned());
            }
        }
        for n in names {
            r.get(n);
        }
        r
    }

    /// The printed identifier.
    pub fn get(&mut self, name: &str) -> String {
        if let Some(n) = self.map.get(name) {
            return n.clone();
        }
        if !KEYWORDS.contains(&name) {
            return name.to_owned();
        }
        let mut new = format!("{name}_");
        while self.used.contains(&new) || KEYWORDS.contains(&new.as_str()) {
            new.push('_');
        }
        self.used.insert(new.clone());
        self.map.insert(name.to_owned(), new.clone());
        self.renamed.push((name.to_owned(), new.clone()));
        new
    }

    /// The printed identifier (no new renaming: unknown names pass).
    pub fn name(&self, name: &str) -> String {
        self.map
            .get(name)
            .cloned()
            .unwrap_or_else(|| name.to_owned())
    }

    /// A fresh identifier for something the printer adds, unique among all.
    pub fn fresh(&mut self, want: &str) -> String {
        let mut new = want.to_owned();
        while self.used.contains(&new) || KEYWORDS.contains(&new.as_str()) {
            new.push('_');
        }
        self.used.insert(new.clone());
        new
    }
}

// ---------------------------------------------------------------------------
// The time unit (as the engine computes it)
// ---------------------------------------------------------------------------

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// The engine's time unit for a set of services (`timed::clocks::unit_ns`).
fn unit_ns(c: &Component, services: &[ServiceId]) -> u64 {
    let mut g = 0;
    for &s in services {
        let svc = &c.services[s];
        if let Some(t) = svc.thread.and_then(|t| c.threads[t.id].period) {
            g = gcd(g, t.ns);
        }
        if let Some(m) = svc.max_time.filter(|_| svc.start.is_some()) {
            g = gcd(g, m.ns);
        }
        for &k in &svc.codels {
            if let Some(w) = c.codels[k].wcet {
                g = gcd(g, w.ns);
            }
        }
    }
    g.max(1)
}

fn units(ns: u64, unit: u64) -> i64 {
    i64::try_from(ns / unit.max(1)).unwrap_or(i64::MAX / 4)
}

/// For each service (by index), the services its timed cluster
/// (`Component::timed_clusters`) is explored with: the cluster, plus the
/// init service.
fn cluster_of(c: &Component) -> Vec<Vec<ServiceId>> {
    let root = c.timed_cluster_roots();
    let clusters = c.timed_clusters();
    let init = c.init_service();
    root.iter()
        .map(|&r| {
            let mut members = clusters
                .iter()
                .find(|m| m.first().is_some_and(|s| s.0 as usize == r))
                .cloned()
                .unwrap_or_default();
            if let Some(s) = init.filter(|s| !members.contains(s)) {
                members.push(s);
                members.sort();
            }
            members
        })
        .collect()
}

// ---------------------------------------------------------------------------
// The builder
// ---------------------------------------------------------------------------

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

impl Network {
    /// Builds the network of a component from its local machines.
    pub fn build(c: &Component, b: &Behaviour) -> Network {
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

fn sanitize(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect()
}

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
        let net = Network {
            name,
            unit_ns: unit,
            horizon: 1,
            clocks: Vec::new(),
            vars: Vec::new(),
            events: EVENTS
                .iter()
                .map(|(n, d)| Event {
                    name: (*n).to_owned(),
                    description: (*d).to_owned(),
                })
                .collect(),
            processes: Vec::new(),
            syncs: Vec::new(),
            labels: Vec::new(),
            services: Vec::new(),
            frozen: VarId(0),
            urgency: Expr::FALSE,
        };
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
        let base = sanitize(want);
        let mut name = base.clone();
        let mut k = 2;
        while self.names.contains(&name)
            || name.starts_with("tmp") && name[3..].parse::<u32>().is_ok()
        {
            name = format!("{base}_{k}");
            k += 1;
        }
        self.names.insert(name.clone());
        name
    }

    fn fresh_label(&mut self, want: &str) -> String {
        let base = sanitize(want);
        let mut name = base.clone();
        let mut k = 2;
        while self.label_names.contains(&name) {
            name = format!("{base}_{k}");
            k += 1;
        }
        self.label_names.insert(name.clone());
        name
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

    /// Declares the clocks and variables.
    fn declare(&mut self) {
        let c = self.c;
        let all: Vec<ServiceId> = c.services.ids().collect();
        let unit = self.net.unit_ns;
        let cspan = c.name.span;
        let has_init = c.init_service().is_some();
        self.init_done = self.int(
            "init_done",
            None,
            0,
            1,
            i64::from(!has_init),
            cspan,
            "1 once the init service has completed successfully".to_owned(),
        );
        self.net.frozen = self.int(
            "frozen",
            None,
            0,
            1,
            0,
            cspan,
            "1 while a watchdog probes whether time can pass its max-time (every other step waits)"
                .to_owned(),
        );
        // Threads (those running some service), in thread order.
        let mut thread_members: BTreeMap<ThreadId, Vec<ServiceId>> = BTreeMap::new();
        for &s in &all {
            if let Some(t) = c.services[s].thread.map(|t| t.id) {
                thread_members.entry(t).or_default().push(s);
            }
        }
        let clusters = cluster_of(c);
        let mut max_const = 0i64;
        // Thread clocks first (the engine's order), then control, then
        // watchdogs.
        let mut thrs = Vec::new();
        for (&t, members) in &thread_members {
            let th = &c.threads[t];
            let period = th.period.map(|p| units(p.ns, unit));
            let period_clock = period.map(|p| {
                max_const = max_const.max(p);
                self.clock(
                    &format!("{}_period", th.name.name),
                    ClockRole::Period(t),
                    th.name.span,
                    format!(
                        "time since the last wake-up of thread {} (period {p})",
                        th.name.name
                    ),
                )
            });
            let exec_clock = self.clock(
                &format!("{}_exec", th.name.name),
                ClockRole::Exec(t),
                th.name.span,
                format!("time since thread {} began its running codel", th.name.name),
            );
            thrs.push((t, period, members.clone(), period_clock, exec_clock));
        }
        if c.services.values().any(|s| s.control.is_some()) {
            self.ctl_clock = Some(self.clock(
                "control_exec",
                ClockRole::Control,
                cspan,
                "time since the control thread began the running control codel".to_owned(),
            ));
        }
        // Services.
        let n = c.services.len();
        let index = |s: ServiceId| s.0 as usize;
        for &s in &all {
            let svc = &c.services[s];
            let m = self.machine(s);
            let mut order: Vec<PosId> = (1..m.positions.len())
                .filter_map(|i| PosId::try_from(i).ok())
                .collect();
            order.sort_by_key(|&p| (position_class(m.positions[usize::from(p)]), p));
            order.insert(0, IDLE);
            let mut value = vec![0i64; m.positions.len()];
            for (v, &p) in order.iter().enumerate() {
                value[usize::from(p)] = v as i64;
            }
            let mut bounds = [0i64; 5];
            for (k, slot) in bounds.iter_mut().enumerate() {
                let class = u8::try_from(k + 1).unwrap_or(0);
                *slot = order
                    .iter()
                    .position(|&p| position_class(m.positions[usize::from(p)]) >= class)
                    .unwrap_or(order.len()) as i64;
            }
            let mut desc = format!("position of {}'s main instance:", svc.name.name);
            for (v, &p) in order.iter().enumerate() {
                let _ = write!(
                    desc,
                    " {v} {};",
                    self.position_text(m.positions[usize::from(p)])
                );
            }
            desc.pop();
            let pos = self.int(
                &format!("{}_pos", svc.name.name),
                None,
                0,
                order.len() as i64 - 1,
                0,
                svc.name.span,
                desc,
            );
            let pend = self.int(
                &format!("{}_pend", svc.name.name),
                None,
                0,
                1,
                0,
                svc.name.span,
                format!("1 when {} has a pending instance", svc.name.name),
            );
            let mut stops: Vec<ServiceId> = Vec::new();
            for r in &svc.stops {
                if !stops.contains(&r.id) {
                    stops.push(r.id);
                }
            }
            let wait = (!stops.is_empty()).then(|| {
                let names: Vec<&str> = stops.iter().map(|&t| self.sname(t)).collect();
                self.int(
                    &format!("{}_wait", svc.name.name),
                    Some(u32::try_from(stops.len()).unwrap_or(u32::MAX)),
                    0,
                    1,
                    0,
                    svc.name.span,
                    format!(
                        "wait bits of {}'s pending instance, one per stops target ({})",
                        svc.name.name,
                        names.join(", ")
                    ),
                )
            });
            let tmo = svc.max_time.map(|mt| {
                self.int(
                    &format!("{}_timed_out", svc.name.name),
                    None,
                    0,
                    1,
                    0,
                    mt.span,
                    format!(
                        "1 when {}'s main instance was interrupted by its watchdog",
                        svc.name.name
                    ),
                )
            });
            let others =
                |rule: fn(&crate::component::Service) -> &Vec<crate::component::Ref<ServiceId>>| {
                    c.services
                        .iter()
                        .filter(|&(t, ts)| t != s && rule(ts).iter().any(|r| r.id == s))
                        .map(|(t, _)| t)
                        .collect::<Vec<ServiceId>>()
                };
            let ctl_wcet = svc
                .control
                .map(|k| c.codels[k].wcet.map_or(0, |w| units(w.ns, unit)));
            if let Some(w) = ctl_wcet {
                max_const = max_const.max(w);
            }
            self.svcs.push(Svc {
                id: s,
                name: svc.name.name.clone(),
                pos,
                pend,
                wait,
                tmo,
                order,
                value,
                bounds,
                self_stop: svc.stops.iter().any(|r| r.id == s),
                stops,
                delayers: others(|t| &t.delays),
                forbidders: others(|t| &t.forbids),
                auto: svc.kind == ServiceKind::Auto,
                control_uses: svc
                    .control
                    .map(|k| c.codels[k].structures())
                    .unwrap_or_default(),
                placement: None,
                watch: None,
                watch_exact: true,
                armed: None,
                watchdog: svc.max_time.is_some(),
                ctl_wcet,
            });
        }
        let _ = n;
        // Threads' variables.
        for (t, period, members, period_clock, exec_clock) in thrs {
            let th = &c.threads[t];
            let k = members.len();
            let kk = k as i64;
            let names: Vec<&str> = members.iter().map(|&s| self.sname(s)).collect();
            let slots = names
                .iter()
                .enumerate()
                .map(|(i, n)| format!("{i} {n}"))
                .collect::<Vec<_>>()
                .join(", ");
            let elig = self.int(
                &format!("{}_eligible", th.name.name),
                Some(u32::try_from(k + 1).unwrap_or(u32::MAX)),
                0,
                1,
                0,
                th.name.span,
                format!(
                    "slots of thread {} that still run a codel this {} (slots: {slots}; the last element is always 0)",
                    th.name.name,
                    if period.is_some() { "period" } else { "round" }
                ),
            );
            let ord = self.int(
                &format!("{}_order", th.name.name),
                Some(u32::try_from(k).unwrap_or(u32::MAX)),
                0,
                kk,
                kk,
                th.name.span,
                format!(
                    "slots of thread {} with an instance, in acknowledgment order ({kk}: empty)",
                    th.name.name
                ),
            );
            let turn = self.int(
                &format!("{}_turn", th.name.name),
                None,
                0,
                kk,
                kk,
                th.name.span,
                format!(
                    "first eligible slot of thread {} in acknowledgment order ({kk}: none)",
                    th.name.name
                ),
            );
            let busy = self.int(
                &format!("{}_busy", th.name.name),
                None,
                0,
                1,
                0,
                th.name.span,
                format!("1 while thread {} runs a codel", th.name.name),
            );
            let idx = self.thrs.len();
            for (slot, &s) in members.iter().enumerate() {
                self.svcs[index(s)].placement = Some((idx, slot));
            }
            for &s in &members {
                for &k in &c.services[s].codels {
                    if Some(k) != c.services[s].control {
                        max_const = max_const.max(self.wcet[k.0 as usize]);
                    }
                }
            }
            self.thrs.push(Thr {
                id: t,
                name: th.name.name.clone(),
                period,
                members,
                period_clock,
                exec_clock,
                elig,
                ord,
                turn,
                busy,
            });
        }
        // Locks: structures used by codels that run on a thread.
        let nthreads = self.thrs.len() as i64;
        let mut used: BTreeSet<StructureId> = BTreeSet::new();
        for s in &self.svcs {
            if s.placement.is_none() {
                continue;
            }
            for k in self.running_codels(s.id) {
                used.extend(c.codels[k].structures().into_iter().map(|(d, _)| d));
            }
        }
        for d in used {
            let st = &c.structures[d];
            let path = st.path();
            let r = self.int(
                &format!("lock_{}_r", path),
                None,
                0,
                nthreads,
                0,
                st.span,
                format!("running thread codels that read {path} (const)"),
            );
            let w = self.int(
                &format!("lock_{}_w", path),
                None,
                0,
                nthreads,
                0,
                st.span,
                format!("running thread codels that may write {path}"),
            );
            self.locks.insert(d, (r, w));
        }
        if self.ctl_clock.is_some() {
            let n = c.services.len() as i64;
            let names = self
                .svcs
                .iter()
                .filter(|s| s.ctl_wcet.is_some())
                .map(|s| format!("{} {}", s.id.0, s.name))
                .collect::<Vec<_>>()
                .join(", ");
            self.ctl = Some(self.int(
                "control_running",
                None,
                0,
                n,
                n,
                cspan,
                format!("the service whose control codel runs ({names}; {n}: none)"),
            ));
        }
        // Watchdog clocks.
        for &s in &all {
            let svc = &c.services[s];
            let Some(mt) = svc.max_time else { continue };
            // The engine computes the max-time in its cluster's unit
            // (exact for services with a start codel; truncated otherwise).
            let cl = &clusters[s.0 as usize];
            let cu = unit_ns(c, cl);
            // As the engine: exact, or from the horizon on for a looping
            // service whose max-time is beyond it.
            let (ns, exact) = c.watchdog_instant_ns(s, self.machine(s).active_loop, cl);
            let max = units(ns, cu).saturating_mul(i64::try_from(cu / unit.max(1)).unwrap_or(1));
            self.svcs[index(s)].watch_exact = exact;
            max_const = max_const.max(max);
            let clock = self.clock(
                &format!("{}_watch", svc.name.name),
                ClockRole::Watchdog(s),
                mt.span,
                format!(
                    "time since {}'s instance was acknowledged (max-time {max})",
                    svc.name.name
                ),
            );
            self.svcs[index(s)].watch = Some((clock, max));
            let armed = self.int(
                &format!("{}_armed", svc.name.name),
                None,
                0,
                1,
                0,
                mt.span,
                format!(
                    "1 while {}'s watchdog follows an instance (its location `on`)",
                    svc.name.name
                ),
            );
            self.svcs[index(s)].armed = Some(armed);
        }
        self.net.horizon = max_const + 1;
        self.net.services = self
            .svcs
            .iter()
            .map(|s| ServiceVars {
                service: s.id,
                name: s.name.clone(),
                pos: s.pos,
                pend: s.pend,
                wait: s.wait,
                timed_out: s.tmo,
                positions: s.order.clone(),
                watchdog: s.watchdog,
                delayers: s.delayers.clone(),
            })
            .collect();
    }

    fn position_text(&self, p: Position) -> String {
        let name = |k: CodelId| self.c.codels[k].name.name.clone();
        match p {
            Position::Idle => "idle".to_owned(),
            Position::Ready { codel, on_inter } => match on_inter {
                Some(i) => format!("ready at {} (on-inter {})", name(codel), name(i)),
                None => format!("ready at {}", name(codel)),
            },
            Position::Running { codel, interrupted } => {
                if interrupted {
                    format!("running {} (interrupted)", name(codel))
                } else {
                    format!("running {}", name(codel))
                }
            }
            Position::StopReady { codel } => format!("stopping, ready at {}", name(codel)),
            Position::StopRunning { codel } => format!("stopping, running {}", name(codel)),
        }
    }

    /// Codels that can be running (in a running position), in codel order.
    fn running_codels(&self, s: ServiceId) -> Vec<CodelId> {
        let m = self.machine(s);
        let set: BTreeSet<CodelId> = m
            .positions
            .iter()
            .filter(|p| p.is_running())
            .filter_map(|p| p.codel())
            .collect();
        set.into_iter().collect()
    }

    // ----- expressions over the state ---------------------------------------

    fn pos(&self, s: ServiceId) -> Expr {
        Expr::var(self.svc(s).pos)
    }

    fn pend(&self, s: ServiceId) -> Expr {
        Expr::var(self.svc(s).pend)
    }

    fn value(&self, s: ServiceId, p: PosId) -> i64 {
        self.svc(s).value[usize::from(p)]
    }

    fn at(&self, s: ServiceId, p: PosId) -> Expr {
        Expr::eq(self.pos(s), Expr::int(self.value(s, p)))
    }

    fn has_instance(&self, s: ServiceId) -> Expr {
        Expr::or([
            Expr::ne(self.pos(s), Expr::int(0)),
            Expr::eq(self.pend(s), Expr::int(1)),
        ])
    }

    fn no_instance(&self, s: ServiceId) -> Expr {
        Expr::and([
            Expr::eq(self.pos(s), Expr::int(0)),
            Expr::eq(self.pend(s), Expr::int(0)),
        ])
    }

    fn ready(&self, s: ServiceId) -> Expr {
        let (lo, hi) = self.svc(s).ready();
        Expr::within(&self.pos(s), lo, hi)
    }

    fn watchable(&self, s: ServiceId) -> Expr {
        let (lo, hi) = self.svc(s).watchable();
        Expr::within(&self.pos(s), lo, hi)
    }

    fn live(&self, s: ServiceId) -> Expr {
        Expr::or([self.watchable(s), Expr::eq(self.pend(s), Expr::int(1))])
    }

    /// No running thread codel conflicts with `uses`.
    fn locks_free(&self, uses: &[(StructureId, bool)]) -> Expr {
        Expr::and(uses.iter().filter_map(|&(d, w)| {
            let &(r, wv) = self.locks.get(&d)?;
            Some(if w {
                Expr::and([
                    Expr::eq(Expr::var(r), Expr::int(0)),
                    Expr::eq(Expr::var(wv), Expr::int(0)),
                ])
            } else {
                Expr::eq(Expr::var(wv), Expr::int(0))
            })
        }))
    }

    /// No running control codel conflicts with `uses`.
    fn control_free(&self, uses: &[(StructureId, bool)]) -> Expr {
        let Some(ctl) = self.ctl else {
            return Expr::TRUE;
        };
        Expr::and(
            self.svcs
                .iter()
                .filter(|r| r.ctl_wcet.is_some() && conflict(uses, &r.control_uses))
                .map(|r| Expr::ne(Expr::var(ctl), Expr::int(i64::from(r.id.0)))),
        )
    }

    /// Steps 1–3 and the lock test of the untimed `request_enabled`.
    fn request_enabled(&self, s: ServiceId) -> Expr {
        let v = self.svc(s);
        let mut parts = Vec::new();
        if let Some(init) = self.c.init_service().filter(|&i| i != s) {
            let _ = init;
            parts.push(Expr::eq(Expr::var(self.init_done), Expr::int(1)));
        }
        for &t in &v.forbidders {
            parts.push(self.no_instance(t));
        }
        if !v.self_stop {
            parts.push(self.no_instance(s));
        }
        parts.push(self.locks_free(&v.control_uses));
        Expr::and(parts)
    }

    /// Some thread at its turn, idle, wants a lock `s`'s control codel
    /// would take.
    fn thread_waits_for(&self, s: ServiceId) -> Expr {
        let uses = &self.svc(s).control_uses;
        let mut out = Vec::new();
        for t in &self.thrs {
            for (slot, &j) in t.members.iter().enumerate() {
                let m = self.machine(j);
                let positions: Vec<Expr> = m
                    .positions
                    .iter()
                    .enumerate()
                    .filter(|(_, p)| {
                        matches!(p, Position::Ready { .. } | Position::StopReady { .. })
                    })
                    .filter(|(_, p)| {
                        p.codel()
                            .is_some_and(|k| conflict(&self.c.codels[k].structures(), uses))
                    })
                    .filter_map(|(i, _)| PosId::try_from(i).ok())
                    .map(|p| self.at(j, p))
                    .collect();
                if positions.is_empty() {
                    continue;
                }
                out.push(Expr::and([
                    Expr::eq(Expr::var(t.busy), Expr::int(0)),
                    Expr::eq(Expr::var(t.turn), Expr::int(slot as i64)),
                    Expr::or(positions),
                ]));
            }
        }
        Expr::or(out)
    }

    /// The guard of a codel begin of `s` at ready position `p`.
    fn begin_guard(&self, s: ServiceId, p: PosId) -> Expr {
        let v = self.svc(s);
        let Some((k, slot)) = v.placement else {
            return Expr::FALSE;
        };
        let t = &self.thrs[k];
        let m = self.machine(s);
        let Some(codel) = m.positions[usize::from(p)].codel() else {
            return Expr::FALSE;
        };
        let uses = self.c.codels[codel].structures();
        Expr::and([
            Expr::eq(Expr::var(t.busy), Expr::int(0)),
            self.at(s, p),
            Expr::eq(Expr::var(t.turn), Expr::int(slot as i64)),
            self.locks_free(&uses),
            self.control_free(&uses),
        ])
    }

    fn elig_sum(&self, k: usize) -> Expr {
        let t = &self.thrs[k];
        Expr::add((0..t.members.len()).map(|i| Expr::elem(t.elig, i as i64)))
    }

    fn round_guard(&self, k: usize) -> Expr {
        let t = &self.thrs[k];
        if t.period.is_some() {
            return Expr::FALSE;
        }
        Expr::and([
            Expr::eq(self.elig_sum(k), Expr::int(0)),
            Expr::eq(Expr::var(t.busy), Expr::int(0)),
            Expr::or(t.members.iter().map(|&s| self.ready(s))),
        ])
    }

    /// The urgent edges of thread `k`'s `idle` location, as guards.
    fn thread_urgency(&self, k: usize) -> Expr {
        let t = &self.thrs[k];
        let mut parts = vec![self.round_guard(k)];
        for &s in &t.members {
            for p in self.ready_positions(s) {
                parts.push(self.begin_guard(s, p));
            }
        }
        Expr::or(parts)
    }

    fn engine_urgency(&self) -> Expr {
        Expr::or((0..self.thrs.len()).map(|k| self.thread_urgency(k)))
    }

    /// The guards of a watchdog's urgent edges: (arm, disarm).
    fn arming(&self, s: ServiceId) -> Option<(Expr, Expr)> {
        let armed = Expr::var(self.svc(s).armed?);
        let live = self.live(s);
        Some((
            Expr::and([Expr::eq(armed.clone(), Expr::int(0)), live.clone()]),
            Expr::and([Expr::eq(armed, Expr::int(1)), Expr::negation(live)]),
        ))
    }

    /// Some urgent edge of the network is enabled: the engine's urgency
    /// plus the arming and disarming of watchdogs.
    fn network_urgency(&self) -> Expr {
        let mut parts = vec![self.engine_urgency()];
        for v in &self.svcs {
            if let Some((arm, disarm)) = self.arming(v.id) {
                parts.push(arm);
                parts.push(disarm);
            }
        }
        Expr::or(parts)
    }

    fn ready_positions(&self, s: ServiceId) -> Vec<PosId> {
        let v = self.svc(s);
        let (lo, hi) = v.ready();
        (lo..=hi)
            .filter_map(|x| v.order.get(usize::try_from(x).ok()?).copied())
            .collect()
    }

    fn running_positions(&self, s: ServiceId) -> Vec<PosId> {
        let v = self.svc(s);
        (v.bounds[2]..v.bounds[4])
            .filter_map(|x| v.order.get(usize::try_from(x).ok()?).copied())
            .collect()
    }

    // ----- statements mirroring the engine ----------------------------------

    /// `System::end`: the main instance of `s` ends.
    fn end(&self, s: ServiceId, ending: Ending) -> Vec<Stmt> {
        let v = self.svc(s);
        let mut out = vec![Stmt::set(v.pos, Expr::int(0))];
        if let Some(t) = v.tmo {
            out.push(Stmt::set(t, Expr::int(0)));
        }
        for k in &self.svcs {
            for (bit, &t) in k.stops.iter().enumerate() {
                if t == s {
                    if let Some(w) = k.wait {
                        out.push(Stmt::set_elem(w, bit as i64, Expr::int(0)));
                    }
                }
            }
        }
        if ending == Ending::Success && self.c.init_service() == Some(s) {
            let mut then = vec![Stmt::set(self.init_done, Expr::int(1))];
            then.extend(self.start_autos());
            Stmt::push_if(
                &mut out,
                Expr::eq(Expr::var(self.init_done), Expr::int(0)),
                then,
                Vec::new(),
            );
        }
        out
    }

    /// Initialisation completes: every auto service becomes active at its
    /// start codel (never pending; one without start codel completes at
    /// once, which changes nothing here).
    fn start_autos(&self) -> Vec<Stmt> {
        let mut out = Vec::new();
        for a in self.svcs.iter().filter(|a| a.auto) {
            let Some(p) = self.machine(a.id).start else {
                continue;
            };
            Stmt::push_if(
                &mut out,
                self.no_instance(a.id),
                vec![Stmt::set(a.pos, Expr::int(self.value(a.id, p)))],
                Vec::new(),
            );
        }
        out
    }

    fn interrupt_pending(&self, t: ServiceId) -> Vec<Stmt> {
        let v = self.svc(t);
        let mut then = vec![Stmt::set(v.pend, Expr::int(0))];
        if let Some(w) = v.wait {
            for bit in 0..v.stops.len() {
                then.push(Stmt::set_elem(w, bit as i64, Expr::int(0)));
            }
        }
        let mut out = Vec::new();
        Stmt::push_if(
            &mut out,
            Expr::eq(self.pend(t), Expr::int(1)),
            then,
            Vec::new(),
        );
        out
    }

    /// `System::interrupt_main`: one `if` per interruptible position (the
    /// positions they lead to are not interruptible, so the tests are
    /// exclusive even in sequence).
    fn interrupt_main(&self, t: ServiceId, watchdog: bool) -> Vec<Stmt> {
        let v = self.svc(t);
        let m = self.machine(t);
        let mut out = Vec::new();
        for &p in &v.order {
            let Some(effect) = m.interrupt[usize::from(p)] else {
                continue;
            };
            let then = match effect {
                Effect::Goto(q) => {
                    let mut s = vec![Stmt::set(v.pos, Expr::int(self.value(t, q)))];
                    if let (true, Some(tmo)) = (watchdog, v.tmo) {
                        s.push(Stmt::set(tmo, Expr::int(1)));
                    }
                    s
                }
                Effect::End(ending) => self.end(t, ending),
            };
            Stmt::push_if(&mut out, self.at(t, p), then, Vec::new());
        }
        out
    }

    /// Step 7: starts pending instances among `candidates`, first one first,
    /// until none can.
    fn closure(&mut self, candidates: &BTreeSet<ServiceId>) -> Vec<Stmt> {
        if candidates.is_empty() {
            return Vec::new();
        }
        let go = self.local();
        let g = || Expr::Local(go.clone());
        let mut body = vec![Stmt::Assign(LValue::Local(go.clone()), Expr::int(0))];
        for &s in candidates {
            let v = self.svc(s);
            let mut cond = vec![
                Expr::eq(g(), Expr::int(0)),
                Expr::eq(self.pend(s), Expr::int(1)),
                Expr::eq(self.pos(s), Expr::int(0)),
            ];
            if let Some(w) = v.wait {
                for bit in 0..v.stops.len() {
                    cond.push(Expr::eq(Expr::elem(w, bit as i64), Expr::int(0)));
                }
            }
            for &d in &v.delayers {
                cond.push(self.no_instance(d));
            }
            let mut then = vec![Stmt::set(v.pend, Expr::int(0))];
            match self.machine(s).start {
                Some(p) => then.push(Stmt::set(v.pos, Expr::int(self.value(s, p)))),
                None => then.extend(self.end(s, Ending::Success)),
            }
            then.push(Stmt::Assign(LValue::Local(go.clone()), Expr::int(1)));
            Stmt::push_if(&mut body, Expr::and(cond), then, Vec::new());
        }
        vec![
            Stmt::Local(go.clone(), Expr::int(1)),
            Stmt::While(Expr::eq(g(), Expr::int(1)), body),
        ]
    }

    /// The services whose instances may change when those of `seeds` do
    /// (and the urgent starts follow): `stops`/`delays` dependents, and the
    /// auto services when the init service is among them.
    fn affected(&self, seeds: impl IntoIterator<Item = ServiceId>) -> BTreeSet<ServiceId> {
        let mut set: BTreeSet<ServiceId> = seeds.into_iter().collect();
        let mut stack: Vec<ServiceId> = set.iter().copied().collect();
        let init = self.c.init_service();
        while let Some(x) = stack.pop() {
            for k in &self.svcs {
                let depends =
                    k.stops.contains(&x) || k.delayers.contains(&x) || (Some(x) == init && k.auto);
                if depends && set.insert(k.id) {
                    stack.push(k.id);
                }
            }
        }
        set
    }

    fn tracked(&self, s: ServiceId) -> bool {
        let v = self.svc(s);
        v.placement.is_some() || v.watch.is_some()
    }

    /// Saves, for the bookkeeping, the position and pending flag of the
    /// tracked `affected` services (and `init_done` when autos may be
    /// acknowledged).
    fn save(&mut self, affected: &BTreeSet<ServiceId>) -> (Vec<Stmt>, Before) {
        let mut out = Vec::new();
        let mut before = Before::default();
        for &s in affected {
            if !self.tracked(s) {
                continue;
            }
            let (lp, lq) = (self.local(), self.local());
            out.push(Stmt::Local(lp.clone(), self.pos(s)));
            out.push(Stmt::Local(lq.clone(), self.pend(s)));
            before.saved.insert(s, (Expr::Local(lp), Expr::Local(lq)));
        }
        let autos = affected
            .iter()
            .any(|&s| self.svc(s).auto && self.tracked(s));
        if autos && self.c.init_service().is_some() {
            let l = self.local();
            out.push(Stmt::Local(l.clone(), Expr::var(self.init_done)));
            before.init = Some(Expr::Local(l));
        }
        (out, before)
    }

    /// `TimedSystem::bookkeep` for the affected services.
    fn bookkeep(
        &self,
        affected: &BTreeSet<ServiceId>,
        before: &Before,
        requested: Option<ServiceId>,
        initial: bool,
    ) -> Vec<Stmt> {
        let mut out = Vec::new();
        for &s in affected {
            if !self.tracked(s) {
                continue;
            }
            let v = self.svc(s);
            let (bp, bq) = before
                .saved
                .get(&s)
                .cloned()
                .unwrap_or((Expr::int(0), Expr::int(0)));
            let acked = if requested == Some(s) {
                Expr::TRUE
            } else if initial {
                self.has_instance(s)
            } else if v.auto {
                match &before.init {
                    Some(bi) => Expr::and([
                        Expr::eq(bi.clone(), Expr::int(0)),
                        Expr::eq(Expr::var(self.init_done), Expr::int(1)),
                    ]),
                    None => Expr::FALSE,
                }
            } else {
                Expr::FALSE
            };
            let pos = self.pos(s);
            let pend = self.pend(s);
            let started_by_start = match self.machine(s).start {
                Some(p) => {
                    let sv = Expr::int(self.value(s, p));
                    Expr::and([
                        Expr::eq(bq.clone(), Expr::int(1)),
                        Expr::eq(pend.clone(), Expr::int(0)),
                        Expr::eq(pos.clone(), sv.clone()),
                        Expr::ne(bp.clone(), sv),
                    ])
                }
                None => Expr::FALSE,
            };
            let started = Expr::or([
                started_by_start,
                Expr::and([
                    acked.clone(),
                    Expr::eq(pend.clone(), Expr::int(0)),
                    Expr::ne(pos.clone(), Expr::int(0)),
                ]),
            ]);
            let ended = Expr::and([
                Expr::ne(bp, Expr::int(0)),
                Expr::or([Expr::eq(pos.clone(), Expr::int(0)), started]),
            ]);
            if let Some((clock, _)) = v.watch {
                Stmt::push_if(
                    &mut out,
                    acked.clone(),
                    vec![Stmt::Reset(clock)],
                    Vec::new(),
                );
            }
            if let Some((k, slot)) = v.placement {
                let t = &self.thrs[k];
                Stmt::push_if(
                    &mut out,
                    ended,
                    vec![Stmt::set_elem(t.elig, slot as i64, Expr::int(0))],
                    Vec::new(),
                );
                let mut requeue = self.order_remove(k, slot);
                requeue.extend(self.order_push(k, slot));
                let mut drop = Vec::new();
                Stmt::push_if(
                    &mut drop,
                    self.no_instance(s),
                    self.order_remove(k, slot),
                    Vec::new(),
                );
                Stmt::push_if(&mut out, acked, requeue, drop);
            }
        }
        out
    }

    /// Removes `slot` from thread `k`'s order (bubbling it to the end).
    fn order_remove(&self, k: usize, slot: usize) -> Vec<Stmt> {
        let t = &self.thrs[k];
        let n = t.members.len() as i64;
        let s = slot as i64;
        let mut out = Vec::new();
        for i in 0..n - 1 {
            out.push(Stmt::If(
                Expr::eq(Expr::elem(t.ord, i), Expr::int(s)),
                vec![
                    Stmt::set_elem(t.ord, i, Expr::elem(t.ord, i + 1)),
                    Stmt::set_elem(t.ord, i + 1, Expr::int(s)),
                ],
                Vec::new(),
            ));
        }
        out.push(Stmt::If(
            Expr::eq(Expr::elem(t.ord, n - 1), Expr::int(s)),
            vec![Stmt::set_elem(t.ord, n - 1, Expr::int(n))],
            Vec::new(),
        ));
        out
    }

    /// Appends `slot` to thread `k`'s order (at the first empty entry).
    fn order_push(&self, k: usize, slot: usize) -> Vec<Stmt> {
        let t = &self.thrs[k];
        let n = t.members.len() as i64;
        let s = slot as i64;
        (0..n)
            .map(|i| {
                let mut cond = vec![Expr::eq(Expr::elem(t.ord, i), Expr::int(n))];
                if i > 0 {
                    cond.push(Expr::ne(Expr::elem(t.ord, i - 1), Expr::int(n)));
                    cond.push(Expr::ne(Expr::elem(t.ord, i - 1), Expr::int(s)));
                }
                Stmt::If(
                    Expr::and(cond),
                    vec![Stmt::set_elem(t.ord, i, Expr::int(s))],
                    Vec::new(),
                )
            })
            .collect()
    }

    /// Recomputes thread `k`'s turn: the first eligible slot in order.
    fn turn(&self, k: usize) -> Vec<Stmt> {
        let t = &self.thrs[k];
        let n = t.members.len() as i64;
        let mut out = vec![Stmt::set(t.turn, Expr::int(n))];
        for i in (0..n).rev() {
            let at = Expr::elem(t.ord, i);
            out.push(Stmt::If(
                Expr::eq(Expr::elem_at(t.elig, at.clone()), Expr::int(1)),
                vec![Stmt::set(t.turn, at)],
                Vec::new(),
            ));
        }
        out
    }

    fn threads_of(&self, services: &BTreeSet<ServiceId>) -> BTreeSet<usize> {
        services
            .iter()
            .filter_map(|&s| self.svc(s).placement.map(|(k, _)| k))
            .collect()
    }

    /// The common tail of a step: urgent starts, bookkeeping, turns.
    fn settle(
        &mut self,
        affected: &BTreeSet<ServiceId>,
        before: &Before,
        requested: Option<ServiceId>,
        initial: bool,
        extra_threads: &[usize],
    ) -> Vec<Stmt> {
        let mut out = self.closure(affected);
        out.extend(self.bookkeep(affected, before, requested, initial));
        let mut threads = self.threads_of(affected);
        threads.extend(extra_threads.iter().copied());
        for k in threads {
            out.extend(self.turn(k));
        }
        out
    }

    /// A whole accepted request of `s` (steps 5–7 and the bookkeeping).
    fn request(&mut self, s: ServiceId) -> Vec<Stmt> {
        self.locals = 0;
        let v = self.svc(s).clone();
        let mut seeds = vec![s];
        seeds.extend(v.stops.iter().copied());
        let affected = self.affected(seeds);
        let (mut out, before) = self.save(&affected);
        for &t in &v.stops {
            out.extend(self.interrupt_pending(t));
            out.extend(self.interrupt_main(t, false));
        }
        out.push(Stmt::set(v.pend, Expr::int(1)));
        if let Some(w) = v.wait {
            for (bit, &t) in v.stops.iter().enumerate() {
                out.push(Stmt::set_elem(
                    w,
                    bit as i64,
                    Expr::ne(self.pos(t), Expr::int(0)),
                ));
            }
        }
        out.extend(self.settle(&affected, &before, Some(s), false, &[]));
        out
    }

    // ----- processes ---------------------------------------------------------

    fn add_process(
        &mut self,
        name: &str,
        kind: ProcessKind,
        span: Span,
        description: String,
    ) -> ProcessId {
        let name = self.fresh(name);
        let id = ProcessId(u32::try_from(self.net.processes.len()).unwrap_or(u32::MAX));
        self.net.processes.push(Process {
            name,
            kind,
            locations: Vec::new(),
            edges: Vec::new(),
            span,
            description,
        });
        id
    }

    fn add_location(&mut self, p: ProcessId, loc: Location) -> LocationId {
        self.add_labelled(p, loc, None)
    }

    fn add_labelled(&mut self, p: ProcessId, loc: Location, kind: Option<LabelKind>) -> LocationId {
        let proc = &mut self.net.processes[p.0 as usize];
        let mut name = sanitize(&loc.name);
        let base = name.clone();
        let mut k = 2;
        while proc.locations.iter().any(|l| l.name == name) {
            name = format!("{base}_{k}");
            k += 1;
        }
        let id = LocationId(u32::try_from(proc.locations.len()).unwrap_or(u32::MAX));
        if let Some(kind) = kind {
            for l in &loc.labels {
                self.net.labels.push(Label {
                    name: l.clone(),
                    kind,
                    process: p,
                    location: id,
                });
            }
        }
        proc.locations.push(Location { name, ..loc });
        id
    }

    fn add_edge(&mut self, p: ProcessId, e: Edge) {
        if e.guard.is_false() {
            return;
        }
        self.net.processes[p.0 as usize].edges.push(e);
    }

    fn frozen_ok(&self) -> Expr {
        Expr::eq(Expr::var(self.net.frozen), Expr::int(0))
    }

    fn control_process(&mut self) {
        let c = self.c;
        let p = self.add_process(
            "control_thread",
            ProcessKind::Control,
            c.name.span,
            "the control thread: handles client requests one at a time and runs control codels"
                .to_owned(),
        );
        let start = self.add_location(
            p,
            loc(
                "start",
                c.name.span,
                "the component starts (committed: the start step happens at time 0)",
            ),
        );
        self.net.processes[p.0 as usize].locations[0].initial = true;
        self.net.processes[p.0 as usize].locations[0].committed = true;
        let idle = self.add_location(p, loc("idle", c.name.span, "no request being handled"));
        // The start: autos, urgent starts, bookkeeping, first wake-ups.
        self.locals = 0;
        let all: BTreeSet<ServiceId> = c.services.ids().collect();
        let mut st = Vec::new();
        if c.init_service().is_none() {
            st.extend(self.start_autos());
            st.extend(self.closure(&all));
        }
        st.extend(self.bookkeep(&all, &Before::default(), None, true));
        for k in 0..self.thrs.len() {
            if self.thrs[k].period.is_some() {
                st.extend(self.fresh_round(k));
            }
        }
        for k in 0..self.thrs.len() {
            st.extend(self.turn(k));
        }
        self.add_edge(
            p,
            Edge {
                from: start,
                to: idle,
                event: event_id("setup"),
                guard: Expr::TRUE,
                clock_guard: Vec::new(),
                statements: st,
                urgent: false,
                labels: Vec::new(),
                span: c.name.span,
                description: "the component starts: auto services are acknowledged (without init service) and start, periodic threads wake up".to_owned(),
            },
        );
        for s in c.services.ids() {
            let svc = &c.services[s];
            let name = svc.name.name.clone();
            let v = self.svc(s).clone();
            let enabled = self.request_enabled(s);
            match (v.ctl_wcet, svc.control, self.ctl, self.ctl_clock) {
                (Some(w), Some(k), Some(ctl), Some(clock)) => {
                    let span = c.codels[k].name.span;
                    let label = self.fresh_label(&format!("codel_{name}_control"));
                    let l = self.add_labelled(
                        p,
                        Location {
                            invariant: vec![ClockConstraint {
                                clock,
                                op: CmpOp::Le,
                                bound: w,
                            }],
                            labels: vec![label.clone()],
                            ..loc(
                                &format!("{name}_control"),
                                span,
                                &format!("the control codel of {name} runs (WCET {w})"),
                            )
                        },
                        Some(LabelKind::Codel(k)),
                    );
                    let guard = Expr::and([
                        self.frozen_ok(),
                        enabled.clone(),
                        Expr::negation(self.thread_waits_for(s)),
                    ]);
                    self.add_edge(
                        p,
                        Edge {
                            from: idle,
                            to: l,
                            event: event_id("request"),
                            guard,
                            clock_guard: Vec::new(),
                            statements: vec![
                                Stmt::set(ctl, Expr::int(i64::from(s.0))),
                                Stmt::Reset(clock),
                            ],
                            urgent: false,
                            labels: Vec::new(),
                            span: svc.name.span,
                            description: format!(
                                "a client requests {name} (not initialising, not forbidden, not busy, locks free, no thread waiting for them): its control codel runs"
                            ),
                        },
                    );
                    let mut st = vec![Stmt::set(ctl, Expr::int(c.services.len() as i64))];
                    st.extend(self.request(s));
                    self.add_edge(
                        p,
                        Edge {
                            from: l,
                            to: idle,
                            event: event_id("accept"),
                            guard: Expr::and([self.frozen_ok(), enabled]),
                            clock_guard: Vec::new(),
                            statements: st,
                            urgent: false,
                            labels: vec![label.clone()],
                            span,
                            description: format!(
                                "the control codel accepts: {name}'s stops targets are interrupted, {name} is acknowledged and starts when it can"
                            ),
                        },
                    );
                    if !svc.reports.is_empty() {
                        self.add_edge(
                            p,
                            Edge {
                                from: l,
                                to: idle,
                                event: event_id("reject"),
                                guard: self.frozen_ok(),
                                clock_guard: Vec::new(),
                                statements: vec![Stmt::set(
                                    ctl,
                                    Expr::int(c.services.len() as i64),
                                )],
                                urgent: false,
                                labels: vec![label],
                                span,
                                description: format!(
                                    "the control codel rejects the request of {name} with a report"
                                ),
                            },
                        );
                    }
                }
                _ => {
                    let st = self.request(s);
                    self.add_edge(
                        p,
                        Edge {
                            from: idle,
                            to: idle,
                            event: event_id("request"),
                            guard: Expr::and([self.frozen_ok(), enabled]),
                            clock_guard: Vec::new(),
                            statements: st,
                            urgent: false,
                            labels: Vec::new(),
                            span: svc.name.span,
                            description: format!(
                                "a client requests {name} (no control codel): its stops targets are interrupted, it is acknowledged and starts when it can"
                            ),
                        },
                    );
                }
            }
        }
    }

    /// `eligible := active ready members` for thread `k`.
    fn fresh_round(&self, k: usize) -> Vec<Stmt> {
        let t = &self.thrs[k];
        t.members
            .iter()
            .enumerate()
            .map(|(slot, &s)| Stmt::set_elem(t.elig, slot as i64, self.ready(s)))
            .collect()
    }

    fn lock_update(&self, codel: CodelId, delta: i64) -> Vec<Stmt> {
        self.c.codels[codel]
            .structures()
            .into_iter()
            .filter_map(|(d, w)| {
                let &(r, wv) = self.locks.get(&d)?;
                let v = if w { wv } else { r };
                Some(Stmt::set(v, Expr::add([Expr::var(v), Expr::int(delta)])))
            })
            .collect()
    }

    fn thread_process(&mut self, k: usize) {
        let c = self.c;
        let t = self.thrs[k].clone();
        let th = &c.threads[t.id];
        let kind = match t.period {
            Some(p) => format!("periodic, period {p}"),
            None => "aperiodic".to_owned(),
        };
        let p = self.add_process(
            &t.name,
            ProcessKind::Thread(t.id),
            th.name.span,
            format!(
                "execution thread {} ({kind}): runs one codel of each eligible service per {}, in acknowledgment order",
                t.name,
                if t.period.is_some() { "period" } else { "round" }
            ),
        );
        let period_inv: Vec<ClockConstraint> = match (t.period, t.period_clock) {
            (Some(per), Some(x)) => vec![ClockConstraint {
                clock: x,
                op: CmpOp::Le,
                bound: per,
            }],
            _ => Vec::new(),
        };
        let idle = self.add_location(
            p,
            Location {
                initial: true,
                invariant: period_inv.clone(),
                ..loc("idle", th.name.span, "no codel running")
            },
        );
        let overrun = t.period.map(|_| {
            let label = self.fresh_label(&format!("overrun_{}", t.name));
            self.add_labelled(
                p,
                Location {
                    committed: true,
                    labels: vec![label],
                    ..loc(
                        "overrun",
                        th.name.span,
                        &format!(
                            "thread {} woke up with codels of its previous period unfinished (violation: nothing happens any more)",
                            t.name
                        ),
                    )
                },
                Some(LabelKind::Overrun(t.id)),
            )
        });
        // Running locations.
        let mut running: BTreeMap<CodelId, LocationId> = BTreeMap::new();
        for &s in &t.members {
            for codel in self.running_codels(s) {
                let kd = &c.codels[codel];
                let sname = self.sname(s);
                let w = self.wcet[codel.0 as usize];
                let label = self.fresh_label(&format!("codel_{sname}_{}", kd.name.name));
                let mut inv = period_inv.clone();
                inv.push(ClockConstraint {
                    clock: t.exec_clock,
                    op: CmpOp::Le,
                    bound: w,
                });
                let l = self.add_labelled(
                    p,
                    Location {
                        invariant: inv,
                        labels: vec![label],
                        ..loc(
                            &format!("run_{sname}_{}", kd.name.name),
                            kd.name.span,
                            &format!(
                                "{} runs {} codel {} of {sname} (WCET {w})",
                                t.name,
                                kd.kind.keyword(),
                                kd.name.name
                            ),
                        )
                    },
                    Some(LabelKind::Codel(codel)),
                );
                running.insert(codel, l);
            }
        }
        // Begins (urgent).
        for &s in &t.members {
            for pos in self.ready_positions(s) {
                let m = self.machine(s);
                let Some(q) = m.begin[usize::from(pos)] else {
                    continue;
                };
                let Some(codel) = m.positions[usize::from(q)].codel() else {
                    continue;
                };
                let Some(&to) = running.get(&codel) else {
                    continue;
                };
                let v = self.svc(s).clone();
                let mut st = vec![
                    Stmt::set(v.pos, Expr::int(self.value(s, q))),
                    Stmt::set(t.busy, Expr::int(1)),
                ];
                st.extend(self.lock_update(codel, 1));
                st.push(Stmt::Reset(t.exec_clock));
                let text = self.position_text(m.positions[usize::from(pos)]);
                self.add_edge(
                    p,
                    Edge {
                        from: idle,
                        to,
                        event: event_id("begin"),
                        guard: self.begin_guard(s, pos),
                        clock_guard: Vec::new(),
                        statements: st,
                        urgent: true,
                        labels: Vec::new(),
                        span: c.codels[codel].name.span,
                        description: format!(
                            "{} begins {}::{} ({} {text}; its turn, its locks free)",
                            t.name, v.name, c.codels[codel].name.name, v.name
                        ),
                    },
                );
            }
        }
        // Finishes.
        for &s in &t.members {
            let (_, slot) = self.svc(s).placement.unwrap_or((k, 0));
            for pos in self.running_positions(s) {
                let m = self.machine(s);
                let Some(codel) = m.positions[usize::from(pos)].codel() else {
                    continue;
                };
                let Some(&from) = running.get(&codel) else {
                    continue;
                };
                let label = self.net.processes[p.0 as usize].locations[from.0 as usize]
                    .labels
                    .clone();
                for (fk, f) in m.finish[usize::from(pos)].iter().enumerate() {
                    self.locals = 0;
                    let v = self.svc(s).clone();
                    let mut st = vec![
                        Stmt::set_elem(t.elig, slot as i64, Expr::int(0)),
                        Stmt::set(t.busy, Expr::int(0)),
                    ];
                    st.extend(self.lock_update(codel, -1));
                    let what = match f.effect {
                        Effect::Goto(q) => {
                            st.push(Stmt::set(v.pos, Expr::int(self.value(s, q))));
                            st.extend(self.turn(k));
                            self.position_text(m.positions[usize::from(q)])
                        }
                        Effect::End(ending) => {
                            let affected = self.affected([s]);
                            let (saved, before) = self.save(&affected);
                            let mut all = saved;
                            all.extend(st);
                            st = all;
                            st.extend(self.end(s, ending));
                            st.extend(self.settle(&affected, &before, None, false, &[k]));
                            match ending {
                                Ending::Success => "ends (success)".to_owned(),
                                Ending::Report(r) => format!(
                                    "ends with report {}",
                                    c.services[s]
                                        .reports
                                        .get(r)
                                        .map_or("?", |n| n.name.as_str())
                                ),
                                Ending::Interrupted => "ends (INTERRUPTED or TIMEOUT)".to_owned(),
                            }
                        }
                    };
                    let outcome = match f.outcome {
                        Some(o) => match o {
                            crate::component::Outcome::Codel(n) => {
                                format!("with {}", c.codels[n].name.name)
                            }
                            crate::component::Outcome::End => "with end".to_owned(),
                            crate::component::Outcome::Report(r) => format!(
                                "with {}",
                                c.services[s]
                                    .reports
                                    .get(r)
                                    .map_or("?", |n| n.name.as_str())
                            ),
                        },
                        None => "(interrupted: its on-inter follows)".to_owned(),
                    };
                    let from_text = self.position_text(m.positions[usize::from(pos)]);
                    self.add_edge(
                        p,
                        Edge {
                            from,
                            to: idle,
                            event: event_id("finish"),
                            guard: Expr::and([self.frozen_ok(), self.at(s, pos)]),
                            clock_guard: Vec::new(),
                            statements: st,
                            urgent: false,
                            labels: label.clone(),
                            span: c.codels[codel].name.span,
                            description: format!(
                                "{}::{} ends {outcome} ({from_text}, outcome {fk}): {} {what}",
                                v.name, c.codels[codel].name.name, v.name
                            ),
                        },
                    );
                }
            }
        }
        // Wake-ups or rounds.
        match (t.period, t.period_clock, overrun) {
            (Some(per), Some(x), Some(ov)) => {
                let at_period = vec![ClockConstraint {
                    clock: x,
                    op: CmpOp::Ge,
                    bound: per,
                }];
                let mut st = vec![Stmt::Reset(x)];
                st.extend(self.fresh_round(k));
                st.extend(self.turn(k));
                self.add_edge(
                    p,
                    Edge {
                        from: idle,
                        to: idle,
                        event: event_id("wake"),
                        guard: Expr::and([
                            self.frozen_ok(),
                            Expr::eq(self.elig_sum(k), Expr::int(0)),
                        ]),
                        clock_guard: at_period.clone(),
                        statements: st,
                        urgent: false,
                        labels: Vec::new(),
                        span: th.name.span,
                        description: format!(
                            "{} wakes up (period {per}): every service at a ready position becomes eligible",
                            t.name
                        ),
                    },
                );
                self.idle_overruns(k, p, idle, ov, &at_period);
                for (&codel, &from) in &running {
                    // A codel that has run its whole WCET ends at this
                    // instant, before the wake-up (codel ends at the same
                    // instant take priority): only a codel that could still
                    // run makes the wake-up an overrun.
                    let w = self.wcet[codel.0 as usize];
                    if w == 0 {
                        continue;
                    }
                    let mut guard = at_period.clone();
                    guard.push(ClockConstraint {
                        clock: t.exec_clock,
                        op: CmpOp::Lt,
                        bound: w,
                    });
                    let label = self.net.processes[p.0 as usize].locations[from.0 as usize]
                        .labels
                        .clone();
                    self.add_edge(
                        p,
                        Edge {
                            from,
                            to: ov,
                            event: event_id("overrun"),
                            guard: self.frozen_ok(),
                            clock_guard: guard,
                            statements: Vec::new(),
                            urgent: false,
                            labels: label,
                            span: th.name.span,
                            description: format!(
                                "{} wakes up while a codel still runs, before its WCET: overrun",
                                t.name
                            ),
                        },
                    );
                }
            }
            _ => {
                let mut st = self.fresh_round(k);
                st.extend(self.turn(k));
                self.add_edge(
                    p,
                    Edge {
                        from: idle,
                        to: idle,
                        event: event_id("round"),
                        guard: self.round_guard(k),
                        clock_guard: Vec::new(),
                        statements: st,
                        urgent: true,
                        labels: Vec::new(),
                        span: th.name.span,
                        description: format!(
                            "{} starts a round: every service at a ready position becomes eligible",
                            t.name
                        ),
                    },
                );
            }
        }
    }

    /// The overruns of thread `k` woken up idle with services still to run
    /// a codel this period (the engine's `overrun_zone`): genuine when one
    /// of those codels has a positive WCET; when all take no time, only
    /// while one waits for a lock held by a running codel of another
    /// thread (or the control codel) that is below its WCET (at its WCET it
    /// ends first, at the same instant).
    fn idle_overruns(
        &mut self,
        k: usize,
        p: ProcessId,
        idle: LocationId,
        ov: LocationId,
        at_period: &[ClockConstraint],
    ) {
        let t = self.thrs[k].clone();
        let mut positive = Vec::new();
        let mut zero = Vec::new();
        for (slot, &s) in t.members.iter().enumerate() {
            for pos in self.ready_positions(s) {
                let Some(codel) = self.machine(s).positions[usize::from(pos)].codel() else {
                    continue;
                };
                let at = Expr::and([
                    Expr::eq(Expr::elem(t.elig, slot as i64), Expr::int(1)),
                    self.at(s, pos),
                ]);
                if self.wcet[codel.0 as usize] > 0 {
                    positive.push(at);
                } else {
                    zero.push((at, codel));
                }
            }
        }
        let any_positive = Expr::or(positive);
        let span = self.c.threads[t.id].name.span;
        let mut edges = vec![(
            Expr::and([self.frozen_ok(), any_positive.clone()]),
            at_period.to_vec(),
            "a service still to run has a codel with a WCET",
        )];
        for (at, codel) in zero {
            for (holder, clock, w) in self.lock_holders(k, codel) {
                let mut cg = at_period.to_vec();
                cg.push(ClockConstraint {
                    clock,
                    op: CmpOp::Lt,
                    bound: w,
                });
                let guard = Expr::and([
                    self.frozen_ok(),
                    Expr::negation(any_positive.clone()),
                    at.clone(),
                    holder,
                ]);
                edges.push((
                    guard,
                    cg,
                    "a service still to run waits for a lock held by a running codel",
                ));
            }
        }
        for (guard, clock_guard, why) in edges {
            self.add_edge(
                p,
                Edge {
                    from: idle,
                    to: ov,
                    event: event_id("overrun"),
                    guard,
                    clock_guard,
                    statements: Vec::new(),
                    urgent: false,
                    labels: Vec::new(),
                    span,
                    description: format!("{} wakes up with work left ({why}): overrun", t.name),
                },
            );
        }
    }

    /// The running codels of other threads, and the control codels, that
    /// hold a lock `codel` of thread `k` needs: (it runs, its execution
    /// clock, its WCET), for those with a positive WCET.
    fn lock_holders(&self, k: usize, codel: CodelId) -> Vec<(Expr, ClockId, i64)> {
        let uses = self.c.codels[codel].structures();
        let mut out = Vec::new();
        for (k2, t2) in self.thrs.iter().enumerate().filter(|&(k2, _)| k2 != k) {
            let _ = k2;
            for &s2 in &t2.members {
                for q in self.running_positions(s2) {
                    let Some(c2) = self.machine(s2).positions[usize::from(q)].codel() else {
                        continue;
                    };
                    let w = self.wcet[c2.0 as usize];
                    if w > 0 && conflict(&uses, &self.c.codels[c2].structures()) {
                        out.push((self.at(s2, q), t2.exec_clock, w));
                    }
                }
            }
        }
        if let (Some(ctl), Some(clock)) = (self.ctl, self.ctl_clock) {
            for r in &self.svcs {
                let Some(w) = r.ctl_wcet.filter(|&w| w > 0) else {
                    continue;
                };
                if conflict(&uses, &r.control_uses) {
                    out.push((
                        Expr::eq(Expr::var(ctl), Expr::int(i64::from(r.id.0))),
                        clock,
                        w,
                    ));
                }
            }
        }
        out
    }

    fn watchdog_process(&mut self, s: ServiceId) {
        let c = self.c;
        let svc = &c.services[s];
        let Some(mt) = svc.max_time else { return };
        let v = self.svc(s).clone();
        let Some((clock, max)) = v.watch else { return };
        let name = v.name.clone();
        let p = self.add_process(
            &format!("{name}_watchdog"),
            ProcessKind::Watchdog(s),
            mt.span,
            if v.watch_exact {
                format!("the max-time watchdog of {name}: interrupts its instance {max} after acknowledgment")
            } else {
                format!(
                    "the max-time watchdog of {name}: its codels loop and its max-time is beyond the exactly timed horizon, so it interrupts its instance at any time from {max} after acknowledgment on"
                )
            },
        );
        let fire = |b: &mut Builder<'a>, pending: bool| -> Vec<Stmt> {
            b.locals = 0;
            let affected = b.affected([s]);
            let (mut st, before) = b.save(&affected);
            if pending {
                st.extend(b.interrupt_pending(s));
            } else {
                st.extend(b.interrupt_main(s, true));
            }
            st.extend(b.settle(&affected, &before, None, false, &[]));
            st
        };
        let off = self.add_location(
            p,
            Location {
                initial: true,
                ..loc(
                    "off",
                    mt.span,
                    &format!("{name} has no instance the watchdog can interrupt"),
                )
            },
        );
        let bound = |op| ClockConstraint {
            clock,
            op,
            bound: max,
        };
        let on = self.add_location(
                p,
                Location {
                    invariant: if v.watch_exact {
                        vec![bound(CmpOp::Le)]
                    } else {
                        Vec::new()
                    },
                    ..loc(
                        "on",
                        mt.span,
                        &format!(
                            "{name} has a pending or interruptible active instance, acknowledged at most {max} ago"
                        ),
                    )
                },
            );
        let (arm, disarm) = self.arming(s).unwrap_or((Expr::FALSE, Expr::FALSE));
        let armed = v.armed.unwrap_or(self.net.frozen);
        self.add_edge(
            p,
            Edge {
                from: off,
                to: on,
                event: event_id("arm"),
                guard: arm,
                clock_guard: Vec::new(),
                statements: vec![Stmt::set(armed, Expr::int(1))],
                urgent: true,
                labels: Vec::new(),
                span: mt.span,
                description: format!("{name} has an instance to watch"),
            },
        );
        self.add_edge(
            p,
            Edge {
                from: on,
                to: off,
                event: event_id("disarm"),
                guard: disarm,
                clock_guard: Vec::new(),
                statements: vec![Stmt::set(armed, Expr::int(0))],
                urgent: true,
                labels: Vec::new(),
                span: mt.span,
                description: format!(
                    "{name} has no instance to watch any more (ended or interrupted)"
                ),
            },
        );
        let st = fire(self, false);
        self.add_edge(
            p,
            Edge {
                from: on,
                to: on,
                event: event_id("watchdog"),
                guard: Expr::and([self.frozen_ok(), self.watchable(s)]),
                clock_guard: vec![bound(CmpOp::Ge)],
                statements: st,
                urgent: false,
                labels: Vec::new(),
                span: mt.span,
                description: format!(
                    "max-time reached: the watchdog interrupts {name}'s active instance"
                ),
            },
        );
        let st = fire(self, true);
        self.add_edge(
            p,
            Edge {
                from: on,
                to: on,
                event: event_id("watchdog"),
                guard: Expr::and([self.frozen_ok(), Expr::eq(self.pend(s), Expr::int(1))]),
                clock_guard: vec![bound(CmpOp::Ge)],
                statements: st,
                urgent: false,
                labels: Vec::new(),
                span: mt.span,
                description: format!(
                    "max-time reached: the watchdog ends {name}'s pending instance (TIMEOUT)"
                ),
            },
        );
        // A looping service's max-time is enforced by its watchdog: no
        // deadline to miss, so no probe (the engine reports advice).
        if !self.machine(s).active_loop {
            self.watchdog_probe(p, s, on, (clock, max));
        }
    }

    /// The observer of a watchdog process `p` (location `on`): at the
    /// max-time, in a non-urgent state, it freezes every other process and
    /// checks whether time can pass the max-time (`late`).
    fn watchdog_probe(
        &mut self,
        p: ProcessId,
        s: ServiceId,
        on: LocationId,
        (clock, max): (ClockId, i64),
    ) {
        let Some(mt) = self.c.services[s].max_time else {
            return;
        };
        let name = self.svc(s).name.clone();
        let bound = |op| ClockConstraint {
            clock,
            op,
            bound: max,
        };
        let probe = self.add_location(
            p,
            loc(
                "probe",
                mt.span,
                &format!("observer: at {name}'s max-time, everything else frozen, can time pass?"),
            ),
        );
        let label = self.fresh_label(&format!("timeout_{name}"));
        let late = self.add_labelled(
            p,
            Location {
                committed: true,
                labels: vec![label],
                ..loc(
                    "late",
                    mt.span,
                    &format!(
                        "{name}'s instance is still running after its max-time (max-time exceeded)"
                    ),
                )
            },
            Some(LabelKind::Timeout(s)),
        );
        let live = self.live(s);
        let urgency = self.engine_urgency();
        self.add_edge(
            p,
            Edge {
                from: on,
                to: probe,
                event: event_id("probe"),
                guard: Expr::and([self.frozen_ok(), live, Expr::negation(urgency)]),
                clock_guard: vec![bound(CmpOp::Ge)],
                statements: vec![Stmt::set(self.net.frozen, Expr::int(1))],
                urgent: false,
                labels: Vec::new(),
                span: mt.span,
                description: format!(
                    "observer: {name}'s max-time is reached in a state where time may pass; freeze everything else"
                ),
            },
        );
        self.add_edge(
            p,
            Edge {
                from: probe,
                to: late,
                event: event_id("exceed"),
                guard: Expr::TRUE,
                clock_guard: vec![bound(CmpOp::Gt)],
                statements: Vec::new(),
                urgent: false,
                labels: Vec::new(),
                span: mt.span,
                description: format!(
                    "observer: time passes beyond {name}'s max-time with its instance still running"
                ),
            },
        );
        self.add_edge(
            p,
            Edge {
                from: probe,
                to: on,
                event: event_id("resume"),
                guard: Expr::TRUE,
                clock_guard: vec![bound(CmpOp::Le)],
                statements: vec![Stmt::set(self.net.frozen, Expr::int(0))],
                urgent: false,
                labels: Vec::new(),
                span: mt.span,
                description: format!(
                    "observer: time cannot pass {name}'s max-time here; everything resumes"
                ),
            },
        );
    }
}

/// The saved state of a step's affected services.
#[derive(Debug, Clone, Default)]
struct Before {
    saved: BTreeMap<ServiceId, (Expr, Expr)>,
    init: Option<Expr>,
}

fn loc(name: &str, span: Span, description: &str) -> Location {
    Location {
        name: name.to_owned(),
        initial: false,
        urgent: false,
        committed: false,
        invariant: Vec::new(),
        labels: Vec::new(),
        span,
        description: description.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expressions_fold_constants() {
        assert_eq!(Expr::and([Expr::TRUE, Expr::TRUE]), Expr::TRUE);
        assert_eq!(Expr::or([Expr::FALSE]), Expr::FALSE);
        assert_eq!(Expr::and([Expr::FALSE, Expr::var(VarId(0))]), Expr::FALSE);
        let v = Expr::var(VarId(1));
        assert_eq!(
            Expr::negation(Expr::eq(v.clone(), Expr::int(2))),
            Expr::ne(v.clone(), Expr::int(2))
        );
        assert_eq!(Expr::within(&v, 3, 2), Expr::FALSE);
        assert_eq!(Expr::add([Expr::int(1), Expr::int(2)]), Expr::int(3));
        assert_eq!(
            Expr::ite(Expr::TRUE, Expr::int(4), Expr::int(5)),
            Expr::int(4)
        );
    }

    #[test]
    fn negation_and_intervals() {
        for op in [
            CmpOp::Eq,
            CmpOp::Ne,
            CmpOp::Lt,
            CmpOp::Le,
            CmpOp::Gt,
            CmpOp::Ge,
        ] {
            assert_eq!(op.negate().negate(), op);
            for (a, b) in [(1, 2), (2, 2), (3, 2)] {
                assert_ne!(op.eval(a, b), op.negate().eval(a, b), "{op:?} {a} {b}");
            }
        }
        let v = Expr::var(VarId(0));
        assert_eq!(Expr::within(&v, 2, 2), Expr::eq(v.clone(), Expr::int(2)));
        assert!(matches!(Expr::within(&v, 1, 3), Expr::And(ref items) if items.len() == 2));
        assert_eq!(Expr::or([Expr::TRUE, v.clone()]), Expr::TRUE);
        assert_eq!(
            Expr::and([v.clone(), v.clone()]),
            v,
            "duplicates are dropped"
        );
    }

    #[test]
    fn fresh_names_avoid_keywords_and_used_names() {
        let mut r = Renaming::default();
        r.used.insert("hurry".to_owned());
        assert_eq!(r.fresh("hurry"), "hurry_");
        assert_eq!(r.fresh("hurry"), "hurry__");
        assert_eq!(r.fresh("int"), "int_");
        assert_eq!(r.get("int"), "int__", "a renaming avoids fresh names too");
        assert_eq!(r.name("int"), "int__");
        assert_eq!(r.name("plain"), "plain");
    }

    #[test]
    fn keywords_are_renamed_once_and_consistently() {
        let net = Network {
            name: "sync".to_owned(),
            unit_ns: 1,
            horizon: 1,
            clocks: Vec::new(),
            vars: vec![IntVar {
                name: "sync_".to_owned(),
                size: 1,
                min: 0,
                max: 1,
                init: 0,
                array: false,
                span: Span::default(),
                description: String::new(),
            }],
            events: Vec::new(),
            processes: Vec::new(),
            syncs: Vec::new(),
            labels: Vec::new(),
            services: Vec::new(),
            frozen: VarId(0),
            urgency: Expr::FALSE,
        };
        let mut r = Renaming::new(&net, &[]);
        assert_eq!(r.get("sync"), "sync__");
        assert_eq!(r.get("sync_"), "sync_");
        assert_eq!(r.renamed, vec![("sync".to_owned(), "sync__".to_owned())]);
    }
}
