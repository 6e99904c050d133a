//! Helpers shared by the integration tests: run the in-process pipeline on
//! a fixture and render its report exactly as the CLI does (colour off,
//! fixed width).

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use gen_frontend::FsLoader;
use genom_check::{CheckOptions, CheckResult};
use genom_model::Diagnostic;
use genom_model::component::Component;
use genom_model::{Code, Severity};
use genom_render::{FileReport, human};

/// The workspace root (integration tests run from it).
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The GenoM3 corpus, when it is on this machine (it is outside the
/// repository: `../shared/corpus/genom3`); says on stderr when it is not.
#[allow(clippy::print_stderr)] // a skipped test says why
pub fn genom3_corpus() -> Option<PathBuf> {
    let dir = root().join("../shared/corpus/genom3");
    if dir.is_dir() {
        Some(dir)
    } else {
        eprintln!("SKIPPED: the GenoM3 corpus is not at {}", dir.display());
        None
    }
}

/// `path` relative to the workspace root, with `/` separators.
pub fn relative(path: &Path) -> PathBuf {
    path.strip_prefix(root())
        .map_or_else(|_| path.to_path_buf(), Path::to_path_buf)
}

/// Checks a file given relative to the workspace root.
pub fn check(path: &Path) -> CheckResult {
    genom_check::check_file(&relative(path), &FsLoader, &CheckOptions::new())
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
        dialect: genom_model::Dialect::Gen,
        pragmas: &[],
        response_times: &[],
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

pub fn invalid(name: &str) -> PathBuf {
    root().join("tests/fixtures/invalid").join(name)
}

pub fn valid(name: &str) -> PathBuf {
    root().join("tests/fixtures/valid").join(name)
}

pub fn component(result: &CheckResult) -> &Component {
    result
        .component
        .as_ref()
        .expect("the fixture resolves to a component")
}

/// 1-based line of a diagnostic's primary label.
pub fn primary_line(result: &CheckResult, d: &Diagnostic) -> usize {
    let located = result.sources.locate(d.span()).expect("span is in a file");
    let file = result.sources.file(located.file).expect("file exists");
    file.line_col(located.offset).0
}

/// The description without its header comment, line by line.
pub fn body(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).expect("fixture is readable");
    let rest = text.split_once("*/").map_or(text.as_str(), |(_, r)| r);
    rest.lines().map(str::to_owned).collect()
}

/// Lines of `a` not in `b` plus lines of `b` not in `a` (as multisets).
pub fn changed_lines(a: &[String], b: &[String]) -> usize {
    let mut rest: Vec<&String> = b.iter().collect();
    let mut only_a = 0;
    for line in a {
        match rest.iter().position(|l| *l == line) {
            Some(k) => {
                rest.remove(k);
            }
            None => only_a += 1,
        }
    }
    only_a + rest.len()
}

/// The codes of the errors of one file of a JSON report.
pub fn error_codes(file: &serde_json::Value) -> Vec<&str> {
    file["diagnostics"]
        .as_array()
        .expect("diagnostics")
        .iter()
        .filter(|d| d["severity"] == "error")
        .filter_map(|d| d["code"].as_str())
        .collect()
}

/// `VmHWM` (peak resident size) of process `pid`, in bytes; `None` where
/// there is no `/proc` or the process is gone.
pub fn high_water_mark(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}
