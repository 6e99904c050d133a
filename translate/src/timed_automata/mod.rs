//! The translation of a component into a network of timed automata
//! ([`genom_model::timed_automata::Network`], the intermediate
//! representation that the UPPAAL and TChecker exports print), from the
//! [`Component`] and its [`Behaviour`] so that it encodes exactly the timed
//! semantics of the zone engine (`checker/engine/src/timed/model/`, on
//! top of the untimed semantics of `checker/engine/src/dialect/system/`);
//! and of a GenoM3 component into its network in GenoM3's timed semantics
//! (`genom3`). [`BuildNetwork`] gives both as `Network::build` and
//! `Network::build_genom3`.
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
//! - **Urgency**: edges marked [`Edge::urgent`](genom_model::timed_automata::Edge::urgent) (codel begins, rounds of
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
//! The module's files: `builder` the construction from a LANGUAGE.md
//! component (one file per kind of process or concern), `genom3` the
//! GenoM3 network, and `names` what both share (the empty network, fresh
//! identifiers).

mod builder;
pub mod genom3;
mod names;

use genom_model::behaviour::Behaviour;
use genom_model::component::Component;
use genom_model::timed_automata::Network;

pub use genom3::Genom3NetworkError;

/// The construction of a [`Network`], as associated functions of the
/// network (bring the trait into scope and call `Network::build(c, b)`).
pub trait BuildNetwork: Sized {
    /// Builds the network of a component from its local machines.
    fn build(c: &Component, b: &Behaviour) -> Self;

    /// The network of a GenoM3 component in GenoM3's timed semantics (one
    /// instance per activity, two for an activity that interrupts itself:
    /// genom-check's default `--max-instances 1`).
    fn build_genom3(c: &Component) -> Result<Self, Genom3NetworkError>;
}

impl BuildNetwork for Network {
    fn build(c: &Component, b: &Behaviour) -> Network {
        builder::build(c, b)
    }

    fn build_genom3(c: &Component) -> Result<Network, Genom3NetworkError> {
        genom3::build(c)
    }
}
