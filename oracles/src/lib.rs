//! The test oracles of genom-check: second readings of the semantics,
//! written from the specifications (LANGUAGE.md, `docs/semantics.md`,
//! `docs/timing.md`, `docs/genom3-semantics.md`) and checking what the
//! engines produce.
//!
//! This crate depends on the model (`genom-model`) alone, and every other
//! crate of the workspace takes it as a dev-dependency only: no engine can
//! reach an oracle, and no oracle an engine, so that their independence is
//! enforced by Cargo. (Its own unit tests run the engines, a dev-only
//! cycle, to replay the traces they emit.)
//!
//! - [`replay`]: the independent replays of traces: LANGUAGE.md's untimed
//!   semantics, and GenoM3's untimed ([`replay::genom3`]) and timed
//!   ([`replay::genom3_timed`]) rules;
//! - [`timed_trace`]: the timing of LANGUAGE.md's timed traces (ticks,
//!   WCETs, locks, watchdogs);
//! - [`petri`]: the token game of the Petri net, with its own bounded
//!   breadth-first search, and the graph of its stable markings;
//! - [`ta_sim`]: an interpreter of timed-automata networks (explicit
//!   locations and variables, clocks as zones);
//! - [`chain_sim`]: the exact data age and reaction time of a chain of
//!   periodic tasks, by exhaustive discrete-time simulation;
//! - [`fiacre`]: a parser of Fiacre models and an interpreter of the timed
//!   subset the GenoM3 `fiacre` export uses (clocks as zones).

pub mod chain_sim;
pub mod fiacre;
pub mod petri;
pub mod replay;
pub mod ta_sim;
#[cfg(test)]
mod testing;
pub mod timed_trace;
