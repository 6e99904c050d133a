//! GenoM3 files through the command line: dialect detection and
//! `--dialect`, include folders (`-I`, `GENOM_INCLUDE_PATH`), the WCET side
//! file (`--wcet`), the dialect and pragmas in the reports, the honest
//! `incomplete` when behaviour is asked for, the front-end's fixtures and
//! the real components of the corpus.

#![allow(clippy::expect_used, clippy::unwrap_used, clippy::print_stderr)] // test support code; skips are said on stderr

mod checks;
mod fixtures_and_corpus;
mod support;
