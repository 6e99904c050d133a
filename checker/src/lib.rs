//! The genom-check verification pipeline: parse, resolve names and types
//! into the component model, run the static checks, and (in later stages)
//! the model-checking engines. Each stage returns its partial result and all
//! its diagnostics; [`check_file`] runs them in order and returns
//! everything, sorted.

#[cfg(feature = "smt")]
pub mod budget;
pub mod checks;
pub mod explain;
mod pipeline;
pub mod resolve;
#[cfg(test)]
pub mod testing;

pub use genom_engine::{engine, replay, timed, zones};
pub use pipeline::{CheckOptions, CheckResult, check_file, check_source};
