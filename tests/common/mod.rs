//! Helpers shared by the integration tests: run the in-process pipeline on
//! a fixture and render its report exactly as the CLI does (colour off,
//! fixed width).

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use genom_checker::{CheckOptions, CheckResult};
use genom_model::render::{FileReport, human};
use genom_model::{Code, Severity};
use genom_parser::FsLoader;

/// The workspace root (integration tests run from it).
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `path` relative to the workspace root, with `/` separators.
pub fn relative(path: &Path) -> PathBuf {
    path.strip_prefix(root())
        .map_or_else(|_| path.to_path_buf(), Path::to_path_buf)
}

/// Checks a file given relative to the workspace root.
pub fn check(path: &Path) -> CheckResult {
    genom_checker::check_file(&relative(path), &FsLoader, &CheckOptions::new())
        .expect("fixture is readable")
}

/// The rendered human report of a result: diagnostics then the summary.
pub fn render(path: &Path, result: &CheckResult) -> String {
    let shown = relative(path).to_string_lossy().replace('\\', "/");
    let report = FileReport {
        path: &shown,
        sources: &result.sources,
        diagnostics: &result.diagnostics,
        statistics: None,
    };
    let options = human::HumanOptions {
        color: false,
        width: 100,
    };
    let mut out = human::render_diagnostics(&report, options);
    out.push_str(&human::render_summary(&shown, report.counts()));
    out.push('\n');
    out
}

/// The codes of a result's diagnostics of at least `severity`.
pub fn codes(result: &CheckResult, severity: Severity) -> Vec<Code> {
    result
        .diagnostics
        .iter()
        .filter(|d| d.severity >= severity)
        .map(|d| d.code)
        .collect()
}

/// The code a fixture is named after: `syntax.missing-semicolon.gen` → `syntax`.
pub fn expected_code(path: &Path) -> Code {
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or_default();
    let code = name.split('.').next().unwrap_or_default();
    code.parse()
        .unwrap_or_else(|_| panic!("fixture {name} is not named after a diagnostic code"))
}
