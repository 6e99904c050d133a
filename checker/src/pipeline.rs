//! Runs the stages of a check in order (text → AST → model → verdicts) and
//! gathers their diagnostics and statistics.

use std::path::Path;
use std::time::Instant;

use genom_model::component::Component;
use genom_model::{Diagnostic, FileId, SourceMap, Span, Statistics, sort_diagnostics};
use genom_parser::{Ast, LoadError, Loader};

/// Options of a check, built with consuming setters.
#[derive(Debug, Clone, Default)]
pub struct CheckOptions {
    _private: (),
}

impl CheckOptions {
    /// The defaults: every check, no limits beyond the built-in ones.
    pub fn new() -> Self {
        Self::default()
    }
}

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
    let _ = options;
    let parsed = genom_parser::parse_source(path, text, loader);
    let mut diagnostics = parsed.diagnostics.clone();
    let mut component = None;
    if parsed.is_complete() {
        let start = parsed
            .sources
            .file(FileId(0))
            .map_or(Span::default(), |f| Span::point(f.base));
        let resolved = crate::resolve::resolve(&parsed.ast, start);
        diagnostics.extend(resolved.diagnostics);
        diagnostics.extend(crate::checks::run(&resolved.component));
        component = resolved.has_component.then_some(resolved.component);
    }
    sort_diagnostics(&mut diagnostics);
    let _elapsed = started.elapsed();
    CheckResult {
        sources: parsed.sources,
        ast: parsed.ast,
        diagnostics,
        component,
        statistics: None,
    }
}
