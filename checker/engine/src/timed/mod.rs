//! The timed engine: the timed semantics of LANGUAGE.md section 3 over the
//! untimed one, explored with clock zones (difference-bound matrices) by the
//! same explorer as the untimed engine, and the timing verdicts read off the
//! symbolic states.

pub mod analysis;
pub mod clocks;
pub mod model;
pub mod response;
pub mod trace;

pub use analysis::{
    CodelOverrun, Exceeded, Overrun, TimedFacts, analyse_timed, timed_explorations,
};
pub use response::{ServiceResponse, Worst, response_times};
