//! Test support for check files: run the whole check (the front-end, a
//! dev-dependency, then the checker) on a source text and look at its
//! diagnostics or rendered report.

use std::path::Path;
use std::time::Instant;

use gen_frontend::{GenFrontend, Loader, MemoryLoader};
use genom_model::Code;
use genom_model::component::Component;
use genom_model::frontend::{Frontend as _, Input};
use genom_render::{FileReport, human};

use crate::CheckOptions;

/// Everything a check found about one source text.
pub type CheckResult = crate::Checked;

/// Checks already-loaded text as the product's `genom_check::check_source`
/// does: the LANGUAGE.md front-end lowers it, the checker checks the model.
pub fn check_source(
    path: &Path,
    text: String,
    loader: &dyn Loader,
    options: &CheckOptions,
) -> CheckResult {
    let started = Instant::now();
    let input = Input {
        watch: options.watch(started),
        ..Input::new(path, loader)
    };
    let loaded = GenFrontend
        .load(input, text)
        .unwrap_or_else(|e| panic!("{e:?}"));
    crate::check(loaded, options, started)
}

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
        dialect: genom_model::Dialect::Gen,
        pragmas: &[],
        response_times: &[],
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

/// Loads GenoM3 text as `t.gen` (no include path from the environment);
/// panics on any error, as a test snippet must be valid.
pub fn load_genom3(text: &str) -> Component {
    genom3_frontend::load_clean(text, None).unwrap_or_else(|e| panic!("{e}"))
}
