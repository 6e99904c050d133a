//! `genom-check`: the command-line front end. Parses arguments, runs the
//! library pipeline and prints; it is the only part of genom-check that
//! prints. Exit status: 0 no error, 1 errors (or warnings with
//! `--deny warnings`), 2 usage or I/O problems.

#![allow(clippy::print_stdout, clippy::print_stderr)]

mod allocator;
mod cli;
mod commands;
mod config;
mod exit;
mod lsp;
mod output;
mod progress;
mod suppress;
mod terminal;

use std::process::ExitCode;

use clap::Parser as _;

#[global_allocator]
static ALLOCATOR: allocator::Bounded = allocator::Bounded;

/// Stack size of the worker thread: deep but legal inputs must never
/// overflow the stack.
const STACK_BYTES: usize = 256 * 1024 * 1024;

/// Set when a write went past the file size limit (`ulimit -f`).
#[cfg(unix)]
static FILE_TOO_LARGE: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

fn main() -> ExitCode {
    // Past the file size limit, the write fails (`File too large`, reported
    // as any write error) instead of SIGXFSZ killing the process and
    // leaving a partial export or temporary file behind.
    #[cfg(unix)]
    let _ = signal_hook::flag::register(signal_hook::consts::SIGXFSZ, &FILE_TOO_LARGE);
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
