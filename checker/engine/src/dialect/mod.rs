//! The LANGUAGE.md behavioural engine (on the [`crate::kernel`]):
//! exhaustive exploration of the component's
//! untimed semantics and the properties read off the reachable states
//! (deadlock, starvation, unbounded interrupts, codel reachability, services
//! that start).
//!
//! Exploration is compositional and exact: before the `init` service
//! completes nothing else can run, so the *pre-init* phase explores the init
//! service alone; afterwards the component splits into independent
//! *clusters*, the connected components of the `stops`/`delays`/`forbids`
//! relation. Services of different clusters never influence which states
//! the others reach (threads and locks only delay codels that always finish),
//! so each cluster is explored on its own from the unique post-init state,
//! and every witness is replayed in the whole component for its trace.
//! A cluster that splits into parts (strongly connected components of the
//! depends-on relation) is explored part by part with an automaton of its
//! upstream ([`compose`]); a cluster explored whole uses a partial-order
//! reduction of quiet codel steps ([`reduction`]).

pub mod analysis;
mod clusters;
pub mod compose;
pub mod method;
mod pending;
pub mod reduction;
pub mod system;
pub(crate) mod witness;

#[cfg(test)]
mod speed_tests;

pub use crate::kernel::{Limits, Stop};
pub use analysis::{Analysis, Blocked, Decided};
pub use method::{Method, analyse, analyse_using, analyse_with};
