//! The model-checking engines of genom-check, on the resolved component
//! model only: the untimed explorer and its verdicts ([`engine`]), the timed
//! engine ([`timed`]) over clock zones ([`zones`]), symbolic (BDD)
//! reachability of large clusters ([`symbolic`]). The independent replays
//! of their traces are in `genom-oracles` (a dev-dependency).

pub mod engine;
pub mod genom3;
pub mod symbolic;
#[cfg(test)]
mod testing;
pub mod timed;
pub mod zones;
