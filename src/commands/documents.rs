//! `genom-check completions SHELL` and `genom-check manpage`: documents
//! generated from the command-line definition itself (clap_complete,
//! clap_mangen), so they never drift from the options.

use clap::CommandFactory as _;

use super::{EXIT_OK, EXIT_USAGE};
use crate::cli::{Cli, CompletionsArgs};
use crate::terminal;

/// Prints the completion script of `args.shell`.
pub fn completions(args: &CompletionsArgs) -> u8 {
    let mut script = Vec::new();
    clap_complete::generate(args.shell, &mut Cli::command(), "genom-check", &mut script);
    emit_bytes(script)
}

/// Prints the manual page in roff.
pub fn manpage() -> u8 {
    let mut page = Vec::new();
    if let Err(e) = clap_mangen::Man::new(Cli::command()).render(&mut page) {
        eprintln!("error: cannot render the manual page: {e}");
        return EXIT_USAGE;
    }
    emit_bytes(page)
}

fn emit_bytes(bytes: Vec<u8>) -> u8 {
    match String::from_utf8(bytes) {
        Ok(text) => {
            terminal::emit(&text);
            EXIT_OK
        }
        Err(e) => {
            eprintln!("error: the generated text is not UTF-8: {e}");
            EXIT_USAGE
        }
    }
}
