//! The timing verdicts (`codel-overrun`, `thread-overrun`,
//! `max-time-infeasible`, `max-time-exceeded`, `max-time-watchdog`,
//! `missing-wcet`) and behavioural verdicts decided on a timed model, on
//! their fixtures and near-identical twins; their concrete timed traces,
//! checked step by step by an independent checker of the timing rules
//! (`tests/timed_trace/mod.rs`) and by the untimed replay
//! (`genom_checker::replay`); the exact margins of max-time on the worked
//! example of `docs/timing.md`, and a hand formula for the worst case; the
//! timing verdicts of `specs/`.
//!
//! Four disagreements found between the engine and the contract by the
//! independent checker are regression tests in `regressions.rs` (a
//! codel ending exactly at the next wake-up, the timed trace of
//! `codel-overrun`, one `request` step per request with a control codel,
//! integer instants with a 1 ns unit).
//!
//! The tests are split by topic; `support` holds the helpers they share.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

mod codes;
mod regressions;
mod support;
mod traces_and_margins;
