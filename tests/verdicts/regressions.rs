//! Fuzzing regressions: every file of `tests/fixtures/regressions/` (inputs
//! that crashed, hung or misreported before a fix, minimised with
//! `cargo fuzz tmin`, plus edge cases kept with them) must check without a
//! panic, with every diagnostic label inside a loaded file, both renderers
//! working, and through the CLI an exit status of 0 or 1 (never 101 or a
//! signal). See docs/testing/fuzzing.md.

#![allow(clippy::expect_used)] // test support code

use std::path::{Path, PathBuf};
use std::time::Duration;

use assert_cmd::Command;
use gen_frontend::FsLoader;
use genom_check::CheckOptions;
use genom_model::Severity;
use genom_render::{FileReport, human, json};

/// The regression inputs, sorted.
fn inputs() -> Vec<PathBuf> {
    let dir = Path::new("tests/fixtures/regressions");
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("the regressions directory exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "gen"))
        .collect();
    files.sort();
    files
}

/// The limits the `check` fuzz target uses.
fn options() -> CheckOptions {
    CheckOptions::new()
        .max_states(20_000)
        .timeout(Some(Duration::from_secs(5)))
        .max_memory(64 << 20)
}

#[test]
fn regressions_check_without_panic_and_with_spans_in_files() {
    let files = inputs();
    assert!(!files.is_empty(), "no regression inputs found");
    for path in files {
        let result = genom_check::check_file(&path, &FsLoader, &options())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        for d in &result.diagnostics {
            for label in &d.labels {
                let inside = result.sources.files().any(|(id, f)| {
                    let whole = result.sources.file_span(id);
                    f.base <= label.span.start
                        && label.span.start <= label.span.end
                        && label.span.end <= whole.end
                });
                assert!(
                    inside,
                    "{}: {:?} label outside the files",
                    path.display(),
                    d.code
                );
            }
        }
        let shown = path.to_string_lossy();
        let report = FileReport {
            path: &shown,
            sources: &result.sources,
            diagnostics: &result.diagnostics,
            statistics: result.statistics.as_ref(),
            dialect: genom_model::Dialect::Gen,
            pragmas: &[],
            response_times: &[],
        };
        let text = human::render_diagnostics(&report, human::HumanOptions::default());
        let doc = json::render(&[report]);
        // An input with errors says so in both forms.
        if result
            .diagnostics
            .iter()
            .any(|d| d.severity == Severity::Error)
        {
            assert!(text.contains('×'), "{}:\n{text}", path.display());
            assert!(doc.contains("\"severity\": \"error\""), "{doc}");
        }
    }
}

#[test]
fn regressions_exit_zero_or_one_through_the_cli() {
    for path in inputs() {
        let out = Command::cargo_bin("genom-check")
            .expect("binary is built")
            .env("NO_COLOR", "1")
            .args(["--max-states", "20000", "--timeout", "5s"])
            .arg(&path)
            .output()
            .expect("runs");
        let code = out.status.code();
        assert!(
            matches!(code, Some(0 | 1)),
            "{}: exit {code:?}\n{}",
            path.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        // The summary line is always printed.
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains(&format!("{}: ", path.display())), "{text}");
    }
}
