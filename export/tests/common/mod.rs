//! Test support shared by the export tests: the files of `specs/` and
//! checking a file as the product does, with the lower crates (the
//! front-end of its language, then the checker).

#![allow(clippy::expect_used, dead_code)] // test support; not every test uses all of it

pub mod nets;

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use gen_frontend::{FsLoader, GenFrontend, Loader};
use genom_checker::{CheckOptions, Checked};
use genom_export::{ExportInput, Format, Verification};
use genom_model::frontend::{Frontend, Input};
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

/// The `format` export of a checked component as the CLI makes it: marked
/// verified when the check found no error, with the check's assumptions.
pub fn export_as_cli(
    result: &CheckResult,
    format: Format,
) -> Result<genom_export::Exported, genom_export::ExportError> {
    let verification = Verification {
        verified: !result
            .diagnostics
            .iter()
            .any(|d| d.severity == genom_model::Severity::Error),
        tool_version: "0.0.0-test".to_owned(),
        assumptions: result
            .statistics
            .as_ref()
            .map(|s| s.assumptions.clone())
            .unwrap_or_default(),
        ..Verification::default()
    };
    let input = ExportInput {
        component: result.component.as_ref().expect("a component"),
        sources: &result.sources,
        verification: &verification,
    };
    genom_export::export(format, &input)
}

/// The GenoM3 fixtures the diagram tests draw (a permanent task machine,
/// `pause::` yields, `async`, `validate`, functions, attributes,
/// exceptions), each with its WCET file when it has one.
pub const GENOM3_DIAGRAM_FIXTURES: [&str; 5] = [
    "../tests/fixtures/genom3/timing/f3_permanent_lock.gen",
    "../tests/fixtures/genom3/response/r4_validate_and_codel.gen",
    "../tests/fixtures/genom3/timing/f10_restart.gen",
    "../tests/fixtures/genom3/semantics/f6_interrupt_stop.gen",
    "../tests/fixtures/genom3/semantics/f8_async.gen",
];

/// The GenoM3 corpus component `uavatt` (absent on a clean clone).
pub const UAVATT: &str = "../../shared/corpus/genom3/uavatt-genom3/uavatt.gen";

/// The full check of a GenoM3 diagram fixture, with its WCET file (same
/// name, `.wcet`) when there is one and the fixtures' include folder.
pub fn check_genom3_fixture(path: &Path) -> CheckResult {
    let wcet = path.with_extension("wcet");
    let wcet = wcet.exists().then_some(wcet);
    let include = [PathBuf::from("../tests/fixtures/genom3/include")];
    check_genom3(path, &include, wcet.as_deref(), &CheckOptions::new())
}

/// `uavatt` checked with its WCET file, or `None` (with the reason on
/// stderr) when the corpus is not there.
#[allow(clippy::print_stderr)] // a skipped test says why
pub fn check_uavatt() -> Option<CheckResult> {
    let path = Path::new(UAVATT);
    if !path.exists() {
        eprintln!("SKIPPED: the GenoM3 corpus is not at {UAVATT} (a clean clone)");
        return None;
    }
    let include = [PathBuf::from("../tests/fixtures/genom3/include")];
    let wcet = Path::new("../tests/fixtures/genom3/wcet/uavatt.wcet");
    Some(check_genom3(
        path,
        &include,
        Some(wcet),
        &CheckOptions::new(),
    ))
}

/// Renders the DOT text with Graphviz, when it is installed, and checks
/// that the result is XML.
pub fn graphviz_accepts(text: &str, path: &Path) {
    let Ok(mut child) = Command::new("dot")
        .arg("-Tsvg")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
    else {
        return; // Graphviz is not installed: nothing to compare with.
    };
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(text.as_bytes())
        .expect("write to dot");
    let out = child.wait_with_output().expect("dot runs");
    assert!(
        out.status.success(),
        "{}: dot failed: {}",
        path.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    let svg = String::from_utf8(out.stdout).expect("UTF-8");
    let options = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..roxmltree::ParsingOptions::default()
    };
    roxmltree::Document::parse_with_options(&svg, options).expect("Graphviz's SVG is XML");
}

/// Checks that the JSON Schema committed at `path` is `generated` (or
/// writes it there with `UPDATE_SCHEMA=1`); `test` and `types` name the
/// test binary and the file of the Rust types, for the message.
pub fn schema_is_up_to_date(path: &str, generated: &str, test: &str, types: &str) {
    if std::env::var_os("UPDATE_SCHEMA").is_some() {
        std::fs::create_dir_all("schema").expect("create schema/");
        std::fs::write(path, generated).expect("write the schema");
        return;
    }
    let committed = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        committed == generated,
        "export/{path} is out of date with the Rust types of export/src/{types}; \
         regenerate it with `UPDATE_SCHEMA=1 cargo test -p genom-export --test {test}` and commit it"
    );
}

/// A validator of the JSON Schema committed at `path`, itself checked
/// against the meta-schema.
pub fn validator(path: &str) -> jsonschema::Validator {
    let text = std::fs::read_to_string(path).expect("committed schema is readable");
    let schema: serde_json::Value = serde_json::from_str(&text).expect("schema is JSON");
    jsonschema::meta::validate(&schema).expect("schema is a valid JSON Schema");
    jsonschema::options()
        .should_validate_formats(true)
        .build(&schema)
        .expect("schema compiles")
}

/// The file stem of `path` (snapshot names).
pub fn stem(path: &Path) -> String {
    path.file_stem()
        .expect("file stem")
        .to_string_lossy()
        .into_owned()
}

/// The `config` export of a checked file with the verification record the
/// CLI builds (its response times included; a fixed tool version, so
/// snapshots do not change with releases), exported even when unverified
/// (as `--allow-unverified` does).
pub fn export_config_as_cli(result: &CheckResult) -> String {
    let component = result.component.as_ref().expect("a component");
    let verification = Verification {
        response_times: result.response_times.clone(),
        ..Verification::of(
            Some(component),
            &result.diagnostics,
            result.statistics.as_ref(),
            "0.0.0-test",
        )
    };
    let input = ExportInput {
        component,
        sources: &result.sources,
        verification: &verification,
    };
    let exported = genom_export::export(Format::Config, &input).expect("config export succeeds");
    assert!(
        exported.extra.is_empty(),
        "the config export has no companion file"
    );
    exported.main
}
