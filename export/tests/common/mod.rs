//! Test support shared by the export tests: the files of `specs/` and
//! checking one of them.

#![allow(clippy::expect_used, dead_code)] // test support; not every test uses all of it

use std::path::{Path, PathBuf};

use genom_check::{CheckOptions, CheckResult, check_file};
use genom_export::{ExportInput, Format, Verification};
use genom_parser::FsLoader;

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

/// The full check of `path` with the default options.
pub fn check(path: &Path) -> CheckResult {
    check_file(path, &FsLoader, &CheckOptions::new()).expect("spec is readable")
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
