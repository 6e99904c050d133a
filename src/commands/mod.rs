//! The subcommands. Each returns the process exit status.

mod budget;
mod check;
mod documents;
mod explain;
mod export;
mod generate;

use crate::cli::{Cli, Command};

/// No error.
pub const EXIT_OK: u8 = 0;
/// Errors found (or warnings with `--deny warnings`).
pub const EXIT_ERRORS: u8 = 1;
/// Usage or I/O problem.
pub const EXIT_USAGE: u8 = 2;

/// Runs the command line.
pub fn run(cli: Cli) -> u8 {
    match cli.command {
        Some(Command::Check(args)) => check::run(&args, &cli.output),
        Some(Command::Explain(args)) => explain::run(&args),
        Some(Command::Export(args)) => export::run(&args, &cli.output),
        Some(Command::Generate(args)) => generate::run(&args),
        Some(Command::Budget(args)) => budget::run(&args, &cli.output),
        Some(Command::Completions(args)) => documents::completions(&args),
        Some(Command::Manpage) => documents::manpage(),
        Some(Command::Lsp(args)) => crate::lsp::run(&args),
        None => check::run(&cli.check, &cli.output),
    }
}
