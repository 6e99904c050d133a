//! Test support shared by the export tests: the files of `specs/` and
//! checking a file as the product does, with the lower crates (the
//! front-end of its language, then the checker).

#![allow(clippy::expect_used, dead_code)] // test support; not every test uses all of it

pub mod nets;

use std::path::{Path, PathBuf};
use std::time::Instant;

use genom_checker::{CheckOptions, Checked};
use genom_export::{ExportInput, Format, Verification};
use genom_model::frontend::{Frontend, Input};
use genom_parser::{FsLoader, GenFrontend, Loader};
use genom3_frontend::Genom3Frontend;

/// What the whole check of a file found.
pub type CheckResult = Checked;

/// Every `.gen` file of `specs/`, sorted, as a path relative to this crate
/// (the tests' working directory), so that hashed paths are stable.
pub fn specs() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir("../specs")
        .expect("specs/ is readable")
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "gen"))
        .map(|p| Path::new("../specs").join(p.file_name().expect("file name")))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no spec found");
    files
}

/// The full check of the LANGUAGE.md file `path` with the default options.
pub fn check(path: &Path) -> CheckResult {
    check_with(path, &CheckOptions::new())
}

/// The full check of the LANGUAGE.md file `path` (as
/// `genom_check::check_file`).
pub fn check_with(path: &Path, options: &CheckOptions) -> CheckResult {
    let text = FsLoader.load(path).expect("the file is readable");
    check_text(path, text, options)
}

/// The full check of `text` as the LANGUAGE.md file `path`, its includes
/// read from disk (as `genom_check::check_source`).
pub fn check_text(path: &Path, text: String, options: &CheckOptions) -> CheckResult {
    run(&GenFrontend, Input::new(path, &FsLoader), text, options)
}

/// The full check of the GenoM3 file `path`, with include folders and a
/// WCET file (as `genom_check::check_path` with those inputs).
pub fn check_genom3(
    path: &Path,
    include_dirs: &[PathBuf],
    wcet_file: Option<&Path>,
    options: &CheckOptions,
) -> CheckResult {
    let text = FsLoader.load(path).expect("the file is readable");
    let input = Input {
        include_dirs,
        wcet_file,
        ..Input::new(path, &FsLoader)
    };
    run(&Genom3Frontend, input, text, options)
}

/// Loads `text` with `frontend`, then checks what it loaded.
fn run(frontend: &dyn Frontend, input: Input<'_>, text: String, options: &CheckOptions) -> Checked {
    let started = Instant::now();
    let input = Input {
        watch: options.watch(started),
        ..input
    };
    let loaded = frontend
        .load(input, text)
        .expect("the side files are readable");
    genom_checker::check(loaded, options, started)
}

/// The main file of the `format` export of a checked spec, marked verified.
pub fn export(result: &CheckResult, format: Format) -> String {
    let component = result.component.as_ref().expect("spec has a component");
    let verification = Verification {
        verified: true,
        tool_version: "0.0.0-test".to_owned(),
        ..Verification::default()
    };
    let input = ExportInput {
        component,
        sources: &result.sources,
        verification: &verification,
    };
    genom_export::export(format, &input)
        .expect("export succeeds")
        .main
}
