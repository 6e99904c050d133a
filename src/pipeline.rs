//! Runs the stages of a check in order (text → AST → model → verdicts): the
//! front-end lowers the text into the model, the checker checks it.

use std::path::Path;
use std::time::Instant;

use genom_model::component::Component;
use genom_model::{Diagnostic, SourceMap, Statistics};
use genom_parser::{Ast, LoadError, Loader};

pub use genom_checker::CheckOptions;

/// Everything a check found about one file.
#[derive(Debug, Clone)]
pub struct CheckResult {
    /// The checked file and its includes.
    pub sources: SourceMap,
    /// The syntax trees.
    pub ast: Ast,
    /// All diagnostics, sorted by file and position.
    pub diagnostics: Vec<Diagnostic>,
    /// The resolved component, when the file parsed completely and has a
    /// `component` item.
    pub component: Option<Component>,
    /// Exploration figures, when the engines ran.
    pub statistics: Option<Statistics>,
}

/// Checks the file at `path`. Fails only when that file cannot be read.
pub fn check_file(
    path: &Path,
    loader: &dyn Loader,
    options: &CheckOptions,
) -> Result<CheckResult, LoadError> {
    let text = loader.load(path)?;
    Ok(check_source(path, text, loader, options))
}

/// Checks already-loaded text; includes are read through `loader`.
pub fn check_source(
    path: &Path,
    text: String,
    loader: &dyn Loader,
    options: &CheckOptions,
) -> CheckResult {
    let started = Instant::now();
    let front = genom_parser::lower(path, text, loader);
    let verdicts = genom_checker::verify(
        front.model,
        front.has_component,
        front.diagnostics,
        options,
        started,
    );
    CheckResult {
        sources: front.sources,
        ast: front.ast,
        diagnostics: verdicts.diagnostics,
        component: verdicts.component,
        statistics: verdicts.statistics,
    }
}
