//! The model-checking engines of genom-check, on the resolved component
//! model only: the analysis kernel every semantics uses ([`kernel`]:
//! explorer, store, parts); the LANGUAGE.md semantics, its untimed explorer
//! and verdicts ([`dialect`]), its timed engine ([`timed`]) over clock
//! zones ([`zones`]) and symbolic (BDD) reachability of large clusters
//! ([`symbolic`]); GenoM3's untimed and timed engines ([`genom3`]). The independent replays
//! of their traces are in `genom-oracles` (a dev-dependency).

pub mod dialect;
pub mod genom3;
pub mod kernel;
pub mod symbolic;
#[cfg(test)]
mod testing;
pub mod timed;
pub mod zones;
