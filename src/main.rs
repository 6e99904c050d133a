//! `genom-check`: the command-line front end. Parses arguments, runs the
//! library pipeline and prints; it is the only part of genom-check that
//! prints. Exit status: 0 no error, 1 errors (or warnings with
//! `--deny warnings`), 2 usage or I/O problems.

#![allow(clippy::print_stdout, clippy::print_stderr)]

mod allocator;
mod cli;
mod commands;
mod config;
mod lsp;
mod suppress;
mod terminal;

use std::process::ExitCode;

use clap::Parser as _;

#[global_allocator]
static ALLOCATOR: allocator::Bounded = allocator::Bounded;

/// Stack size of the worker thread: deep but legal inputs must never
/// overflow the stack.
const STACK_BYTES: usize = 256 * 1024 * 1024;

fn main() -> ExitCode {
    let cli = cli::Cli::parse();
    if let Some(bytes) = cli.max_memory() {
        allocator::limit(bytes);
    }
    let worker = std::thread::Builder::new()
        .stack_size(STACK_BYTES)
        .spawn(move || commands::run(cli));
    match worker.map(std::thread::JoinHandle::join) {
        Ok(Ok(code)) => ExitCode::from(code),
        Ok(Err(_)) => {
            eprintln!(
                "error: genom-check crashed; this is a bug, please report it with the input file"
            );
            ExitCode::from(commands::EXIT_USAGE)
        }
        Err(e) => {
            eprintln!("error: cannot start the checker thread: {e}");
            ExitCode::from(commands::EXIT_USAGE)
        }
    }
}
