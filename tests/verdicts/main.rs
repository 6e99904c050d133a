//! Verdicts of the dialect: static and behavioural checks, timing, response times, the compositional engine, regressions.
//! One test binary for these files (one link instead of 6); each file is a
//! module and keeps its own header.

#![allow(clippy::expect_used, clippy::unwrap_used)] // test support code

#[path = "../common/mod.rs"]
mod common;
mod compose;
mod regressions;
mod response_times;
mod static_checks;
#[path = "../timed_trace/mod.rs"]
mod timed_trace;
mod timing;
mod verdicts;
