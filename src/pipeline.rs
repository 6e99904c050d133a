//! Runs the stages of a check in order (text → AST → model → verdicts): the
//! front-end of the file's dialect lowers the text into the model, the
//! checker checks it.

use std::path::Path;
use std::time::Instant;

use genom_model::Dialect;
use genom_parser::{FsLoader, LoadError, Loader};

pub use genom_checker::CheckOptions;

use crate::types::{CheckResult, InputError, Inputs, STDIN_NAME, display, is_stdin};

/// Checks the file at `path` in the dialect `inputs` says or its syntax
/// shows. Fails only when a file cannot be read at all.
pub fn check_path(
    path: &Path,
    inputs: &Inputs,
    options: &CheckOptions,
) -> Result<CheckResult, InputError> {
    let read = if is_stdin(path) {
        genom_model::loader::read_bounded(std::io::stdin().lock())
    } else {
        FsLoader.load(path)
    };
    let text = read.map_err(|error| InputError::Read {
        path: display(path),
        error,
    })?;
    let path = if is_stdin(path) {
        Path::new(STDIN_NAME)
    } else {
        path
    };
    check_text(path, text, inputs, options)
}

/// Checks `text` as the content of the file at `path` (which need not
/// exist, or may hold older text: an editor's unsaved buffer); its includes
/// are read from disk next to `path`. Fails only when the WCET file cannot
/// be read, or is given for a LANGUAGE.md file.
pub fn check_text(
    path: &Path,
    text: String,
    inputs: &Inputs,
    options: &CheckOptions,
) -> Result<CheckResult, InputError> {
    let dialect = inputs.dialect.unwrap_or_else(|| detect(&text));
    match dialect {
        Dialect::Gen if inputs.wcet_file.is_some() => Err(InputError::WcetNeedsGenom3 {
            path: display(path),
        }),
        Dialect::Gen => Ok(check_source(path, text, &FsLoader, options)),
        Dialect::Genom3 => crate::genom3::check(path, text, inputs, options),
    }
}

/// The dialect a text is written in, by its syntax: GenoM3 when it has a
/// GenoM3-only construct, else LANGUAGE.md.
pub fn detect(text: &str) -> Dialect {
    if genom_genom3::looks_like_genom3(text) {
        Dialect::Genom3
    } else {
        Dialect::Gen
    }
}

/// Checks the LANGUAGE.md file at `path`. Fails only when that file cannot
/// be read.
pub fn check_file(
    path: &Path,
    loader: &dyn Loader,
    options: &CheckOptions,
) -> Result<CheckResult, LoadError> {
    let text = loader.load(path)?;
    Ok(check_source(path, text, loader, options))
}

/// Checks already-loaded LANGUAGE.md text; includes are read through
/// `loader`.
pub fn check_source(
    path: &Path,
    text: String,
    loader: &dyn Loader,
    options: &CheckOptions,
) -> CheckResult {
    let started = Instant::now();
    let front = genom_parser::lower_until(path, text, loader, options.watch(started));
    let verdicts = genom_checker::verify(
        front.model,
        front.has_component,
        front.diagnostics,
        options,
        started,
    );
    CheckResult {
        dialect: Dialect::Gen,
        sources: front.sources,
        diagnostics: verdicts.diagnostics,
        component: verdicts.component,
        statistics: verdicts.statistics,
        pragmas: Vec::new(),
        response_times: verdicts.response_times,
    }
}
