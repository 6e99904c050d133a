//! The model-checking engines of genom-check, on the resolved component
//! model only: the untimed explorer and its verdicts ([`engine`]), the timed
//! engine ([`timed`]) over clock zones ([`zones`]), symbolic (BDD)
//! reachability of large clusters ([`symbolic`]), and the replay of traces
//! against the semantics ([`replay`]).

pub mod engine;
pub mod genom3;
pub mod replay;
pub mod symbolic;
#[cfg(test)]
mod testing;
pub mod timed;
pub mod zones;
