//! Test support for check files: run the whole pipeline on a source text
//! and look at its diagnostics or rendered report.

use std::path::Path;

use genom_model::Code;
use genom_model::render::{FileReport, human};
use genom_parser::MemoryLoader;

use crate::{CheckOptions, CheckResult, check_source};

/// Checks `src` as `test.gen`; `files` are other files available for
/// includes, as `(path, text)`.
pub fn check_with(src: &str, files: &[(&str, &str)]) -> CheckResult {
    let loader = files
        .iter()
        .fold(MemoryLoader::new(), |l, (p, t)| l.with(p, *t));
    check_source(
        Path::new("test.gen"),
        src.to_owned(),
        &loader,
        &CheckOptions::new(),
    )
}

/// Checks `src` as `test.gen` with no includes available.
pub fn check(src: &str) -> CheckResult {
    check_with(src, &[])
}

/// The codes of every diagnostic of `src`, in order, except the
/// `missing-wcet` advice that every snippet without WCETs on a periodic
/// thread gets (its own tests look at [`check`]'s diagnostics).
pub fn codes(src: &str) -> Vec<Code> {
    check(src)
        .diagnostics
        .iter()
        .map(|d| d.code)
        .filter(|&c| c != Code::MissingWcet)
        .collect()
}

/// How many diagnostics of `src` have `code`.
pub fn count(src: &str, code: Code) -> usize {
    codes(src).into_iter().filter(|&c| c == code).count()
}

/// The rendered human report (colour off, width 100) with the summary, for
/// snapshots.
pub fn render(src: &str) -> String {
    let result = check(src);
    let report = FileReport {
        path: "test.gen",
        sources: &result.sources,
        diagnostics: &result.diagnostics,
        statistics: None,
    };
    let options = human::HumanOptions {
        color: false,
        width: 100,
    };
    let mut out = human::render_diagnostics(&report, options);
    out.push_str(&human::render_summary("test.gen", report.counts()));
    out
}

/// A valid component header and thread for snippets.
pub const HEADER: &str = "component t { lang: C; }\nthread main { period: 10ms; }\n";
