//! The command line: options, exit statuses, output formats, exports, project configuration, the generator and the benchmark script.
//! One test binary for these files (one link instead of 8); each file is a
//! module and keeps its own header.

#![allow(clippy::expect_used, clippy::unwrap_used)] // test support code

mod bench_table;
mod cli;
mod cli_conventions;
#[path = "../common/mod.rs"]
mod common;
mod engine_option;
mod export_cli;
mod generate;
mod genom3_generate;
mod project_config;
mod system;
