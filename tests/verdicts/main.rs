//! Verdicts of the dialect: static and behavioural checks, timing, response times, the compositional engine, regressions.
//! One test binary for these files (one link instead of 6); each file is a
//! module and keeps its own header.

#![allow(clippy::expect_used, clippy::unwrap_used)] // test support code

#[path = "../common/mod.rs"]
mod common;
mod compose;
mod regressions;
mod reporting;
mod response_times;
mod static_checks;
mod timing;
mod verdicts;
