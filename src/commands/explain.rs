//! `genom-check explain CODE`.

use genom_model::Code;

use super::{EXIT_OK, EXIT_USAGE};
use crate::cli::{DialectArg, ExplainArgs};
use genom_model::dialect::Dialect;
use genom_render::FileReport;

/// Prints the explanation of a code.
pub fn run(args: &ExplainArgs) -> u8 {
    match args.code.parse::<Code>() {
        Ok(code) => {
            let dialect = match args.dialect {
                Some(DialectArg::Genom3) => Dialect::Genom3,
                Some(DialectArg::Gen) | None => Dialect::Gen,
            };
            crate::terminal::emit(&text_for(code, dialect));
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

/// The explanation of `code` for a user of `dialect`, from whichever
/// front-end or check owns it.
pub fn text_for(code: Code, dialect: Dialect) -> String {
    genom_check::explain::explanation_for(code, dialect)
}

/// The SARIF log of `reports`, the rules' help in the words of their
/// dialect ([`common_dialect`]).
pub fn sarif(reports: &[FileReport<'_>]) -> String {
    let dialect = common_dialect(reports);
    genom_render::sarif::render(
        reports,
        &|code| text_for(code, dialect),
        env!("CARGO_PKG_VERSION"),
    )
}

/// GenoM3 when every report is a GenoM3 file's (its explanations then put
/// GenoM3's words first), else LANGUAGE.md's dialect.
pub fn common_dialect(reports: &[FileReport<'_>]) -> Dialect {
    if !reports.is_empty() && reports.iter().all(|r| r.dialect == Dialect::Genom3) {
        Dialect::Genom3
    } else {
        Dialect::Gen
    }
}
