//! The subcommands. Each returns the process exit status.

mod budget;
mod check;
mod documents;
mod explain;
mod export;
mod generate;
mod system;
mod wcet_template;

use crate::cli::{Cli, Command};
pub use crate::exit::{EXIT_ERRORS, EXIT_OK, EXIT_USAGE};

/// Runs the command line. A failed write to stdout (other than a closed
/// pipe) is an I/O problem: reported, and the status is 2.
pub fn run(cli: Cli) -> u8 {
    let status = command(cli);
    match crate::terminal::failure() {
        Some(e) => {
            eprintln!("error: cannot write to standard output: {e}");
            EXIT_USAGE
        }
        None => status,
    }
}

fn command(cli: Cli) -> u8 {
    match cli.command {
        Some(Command::Check(args)) => match &args.system {
            Some(system) => system::run(system, &args, &cli.output),
            None => check::run(&args, &cli.output),
        },
        Some(Command::Explain(args)) => explain::run(&args),
        Some(Command::Export(args)) => export::run(&args, &cli.output),
        Some(Command::Generate(args)) => generate::run(&args),
        Some(Command::Budget(args)) => budget::run(&args, &cli.output),
        Some(Command::WcetTemplate(args)) => wcet_template::run(&args, &cli.output),
        Some(Command::Completions(args)) => documents::completions(&args),
        Some(Command::Manpage) => documents::manpage(),
        Some(Command::Lsp(args)) => crate::lsp::run(&args),
        None => match &cli.check.system {
            Some(system) => system::run(system, &cli.check, &cli.output),
            None => check::run(&cli.check, &cli.output),
        },
    }
}
