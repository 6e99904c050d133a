//! The behavioural verdicts (deadlock, starvation, dead-service,
//! unbounded-interrupt, and the dynamic part of unreachable-codel) on their
//! fixtures: each invalid fixture's verdict with its message, primary line
//! and exact trace; each trace replayed step by step by the independent
//! interpreter of LANGUAGE.md section 3 (`genom_checker::replay`), which
//! also checks that the end of the trace shows the claimed violation; the
//! near-identical valid twins, which must not have the verdict; corrupted
//! traces, which the replay must reject; the JSON form of a trace; and the
//! `incomplete` verdict when a state limit stops exploration.
//!
//! The tests are split by topic; `support` holds the helpers they share.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

mod fixtures;
mod json_and_limits;
mod replay;
mod support;
mod twins;
