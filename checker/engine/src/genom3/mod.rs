//! The GenoM3 engine: GenoM3's own execution semantics
//! (`docs/genom3-semantics.md`), untimed. A GenoM3 component runs several
//! instances of one activity at once (anonymous, counted as a multiset up
//! to a bound), each task has a permanent activity started before any
//! request, requests are admitted by `after`/`before` and interrupt with
//! `interrupts` (the interrupter waits for the stop paths), functions
//! interrupt after their codels succeeded, `kill` and `abort_activity` are
//! interruption sources, and any codel may end its instance with an
//! exception. Time is abstracted away: a paused instance resumes at some
//! later wake-up (a tick, or any request for an aperiodic task), so every
//! interleaving of codels is explored.
//!
//! - [`machine`]: the component as the engine reads it;
//! - [`state`]: a state and its packed form;
//! - [`parts`]: the independent parts explored one by one;
//! - [`steps`]: the transitions (an [`crate::kernel::explore::Model`]);
//! - [`analysis`]: exploration and the verdicts read off it;
//! - [`trace`]: traces, in the vocabulary the replay reads;
//! - [`timed`]: the same rules with GenoM3's task loop in time (ticks,
//!   sweeps, WCETs, locks): schedulability.

pub mod analysis;
pub mod machine;
pub mod parts;
#[cfg(test)]
mod sets_tests;
pub mod state;
pub mod steps;
#[cfg(test)]
mod tests;
pub mod timed;
pub mod trace;

pub use analysis::{
    Cycle, G3Analysis, Livelock, analyse_genom3, analyse_machine, analyse_machine_by,
    analyse_machine_with, unpaused_cycles,
};
pub use machine::{Machine, Owner, POOL};
