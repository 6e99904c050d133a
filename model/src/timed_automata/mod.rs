//! The component as a network of timed automata: an intermediate
//! representation that the UPPAAL and TChecker exports print, built from
//! the [`Component`](crate::component::Component) and its
//! [`Behaviour`](crate::behaviour::Behaviour) so that it encodes exactly the
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
//!
//! The module's files: `expr` the expressions and statements,
//! `network` the network's types, `names` the keyword renaming that the
//! printers share, and `builder` the construction from a component (one
//! file per kind of process or concern).

mod builder;
mod expr;
mod genom3;
mod names;
mod network;
#[cfg(test)]
mod tests;

use crate::define_id;

pub use expr::{CmpOp, Expr, LValue, Stmt};
pub use genom3::Genom3NetworkError;
pub use names::{KEYWORDS, Renaming};
pub use network::{
    Clock, ClockConstraint, ClockRole, Edge, Event, IntVar, Label, LabelKind, Location, Network,
    Process, ProcessKind, ServiceVars, Sync, SyncPart,
};

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
