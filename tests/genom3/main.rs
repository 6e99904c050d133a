//! GenoM3 through the command line: recognition, includes, timing with WCET files, response times, the differential against genom3 itself.
//! One test binary for these files (one link instead of 5); each file is a
//! module and keeps its own header.

#![allow(clippy::expect_used, clippy::unwrap_used)] // test support code

#[path = "../common/mod.rs"]
mod common;
mod genom3_cli;
mod genom3_diff;
mod genom3_response;
mod genom3_timing;
mod genom3_wcet_files;
