//! The component as a network of timed automata: the data of the
//! intermediate representation that the UPPAAL and TChecker exports print
//! and the test oracles interpret. The network is built by the
//! `genom-translate` crate (`translate/src/timed_automata/`: the
//! construction from the [`Component`](crate::component::Component) and
//! its [`Behaviour`](crate::behaviour::Behaviour) in the zone engine's
//! timed semantics, and the GenoM3 network in GenoM3's); docs/semantics.md
//! section 7 sums it up, docs/exports/uppaal.md and docs/exports/tchecker.md
//! give the printed forms, queries and labels.
//!
//! The module's files: `expr` the expressions and statements, `network`
//! the network's types (processes, locations, edges, labels), and `names`
//! the keyword renaming that the printers share.

mod expr;
mod names;
mod network;
#[cfg(test)]
mod tests;

use crate::define_id;

pub use expr::{CmpOp, Expr, LValue, Stmt};
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
