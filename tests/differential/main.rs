//! Differential tests against independent tools and oracles: SPIN, TChecker, DIVINE, the Petri-net checkers.
//! One test binary for these files (one link instead of 9); each file is a
//! module and keeps its own header.

#![allow(clippy::expect_used, clippy::unwrap_used)] // test support code

#[path = "../common/mod.rs"]
mod common;
mod divine_diff_genom3;
mod genom3_untimed;
mod genom3_verdicts;
#[path = "../petri_common/mod.rs"]
mod petri_common;
mod petri_cross_check;
mod petri_cross_check_generator;
mod petri_genom3;
mod spin_diff;
mod spin_diff_genom3;
mod tchecker_diff;
mod tchecker_diff_genom3;
mod tina_net;
