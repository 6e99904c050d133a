//! Hostile and huge inputs: every limit holds (time, memory, nesting, sizes), nothing crashes, no file is clobbered.
//! One test binary for these files (one link instead of 4); each file is a
//! module and keeps its own header.

#![allow(clippy::expect_used, clippy::unwrap_used)] // test support code

#[path = "../common/mod.rs"]
mod common;
mod hostile;
mod hostile_numbers;
mod limits;
mod memory_limit;
