//! `genom-check explain CODE`.

use genom_model::Code;

use super::{EXIT_OK, EXIT_USAGE};
use crate::cli::ExplainArgs;

/// Prints the explanation of a code.
pub fn run(args: &ExplainArgs) -> u8 {
    match args.code.parse::<Code>() {
        Ok(code) => {
            crate::terminal::emit(&text_of(code));
            EXIT_OK
        }
        Err(e) => {
            let known: Vec<&str> = Code::ALL.iter().map(|c| c.as_str()).collect();
            let hint = gen_frontend::diagnostics::closest(&args.code, known.iter().copied())
                .map(|c| format!(" (did you mean `{c}`?)"))
                .unwrap_or_default();
            eprintln!("error: {e}{hint}; the known codes are:");
            for code in known {
                eprintln!("  {code}");
            }
            EXIT_USAGE
        }
    }
}

/// The explanation of `code`, from whichever front-end or check owns it.
pub fn text_of(code: Code) -> String {
    genom_check::explain::explanation(code)
}
