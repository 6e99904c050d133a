//! `genom-translate`: the translations of the resolved component model
//! into the formalisms the exports print. It owns the builders: the
//! network of timed automata of a LANGUAGE.md component in the zone
//! engine's timed semantics and of a GenoM3 component in GenoM3's
//! ([`timed_automata`], `Network::build` and `Network::build_genom3`
//! through [`BuildNetwork`]), and the Petri net whose stable markings are
//! the untimed explorer's configurations ([`petri`], `PetriNet::build`
//! through [`BuildPetriNet`]), and the Petri net of a GenoM3 component in
//! GenoM3's untimed semantics ([`petri_genom3`], `PetriNet::build_genom3`),
//! both GenoM3 untimed translations reading the component through
//! [`genom3_reading`].
//!
//! The data it builds stays in `genom-model` (`timed_automata::Network`,
//! `petri::PetriNet`), so that what only reads a network or a net (the
//! exports' printers, the test oracles that interpret them) needs no
//! builder. It depends on `genom-model` alone and must not depend on the
//! front-ends, the checker, the engines, the exports or the renderers:
//! the engines do not use it, and a change here rebuilds only the exports,
//! the binary and the tests that build networks or nets.

pub mod genom3_reading;
pub mod petri;
pub mod petri_genom3;
pub mod timed_automata;

pub use petri::BuildPetriNet;
pub use timed_automata::{BuildNetwork, Genom3NetworkError};
