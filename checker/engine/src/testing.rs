//! Test support: resolve a source text with the whole check, for the
//! engines' unit tests.

use std::path::Path;

use genom_checker::{CheckOptions, CheckResult, check_source};
use genom_parser::MemoryLoader;

/// Checks `src` as `test.gen` with no includes available.
pub fn check(src: &str) -> CheckResult {
    check_source(
        Path::new("test.gen"),
        src.to_owned(),
        &MemoryLoader::new(),
        &CheckOptions::new(),
    )
}

/// A valid component header and thread for snippets.
pub const HEADER: &str = "component t { lang: C; }\nthread main { period: 10ms; }\n";
