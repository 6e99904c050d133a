//! The genom-check checker: reads only the component model a front-end
//! lowered, runs the static checks on it and the model-checking engines.
//! [`check`] takes what a front-end loaded, runs them in order, and
//! returns every diagnostic, sorted.

#[cfg(feature = "smt")]
pub mod budget;
mod check;
pub mod checks;
#[cfg(test)]
pub mod testing;
mod verify;
mod verify_genom3;

pub use check::{Checked, check};
pub use genom_engine::{dialect, genom3, kernel, timed, zones};
#[cfg(test)]
pub use testing::{CheckResult, check_source};
pub use verify::{CheckOptions, DEFAULT_MAX_INSTANCES, Engine, Verdicts, verify};
pub use verify_genom3::{Genom3Verdicts, verify_genom3};
