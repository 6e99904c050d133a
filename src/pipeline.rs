//! Runs the stages of a check in order (text → AST → model → verdicts): the
//! front-end of the file's dialect lowers the text into the model, the
//! checker checks it.

use std::path::{Path, PathBuf};
use std::time::Instant;

use genom_model::component::Component;
use genom_model::{
    Diagnostic, Dialect, Pragma, ResponseTime, SourceMap, Statistics, sort_diagnostics,
};
use genom_parser::{FsLoader, LoadError, Loader};

pub use genom_checker::CheckOptions;
/// A path as shown to people (forward slashes).
/// How a path given by the user is shown: `/`-separated, and `-` (standard
/// input) as `<stdin>`.
pub fn display(path: &Path) -> String {
    if is_stdin(path) {
        STDIN_NAME.to_owned()
    } else {
        genom_model::span::display_path(path)
    }
}

/// The name the text read from standard input is checked under (its
/// includes are searched from the current folder).
pub const STDIN_NAME: &str = "<stdin>";

/// Whether `path` is `-`: standard input.
pub fn is_stdin(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// Everything a check found about one file.
#[derive(Debug, Clone)]
pub struct CheckResult {
    /// The language the file was read as.
    pub dialect: Dialect,
    /// The checked file and its includes.
    pub sources: SourceMap,
    /// All diagnostics, sorted by file and position.
    pub diagnostics: Vec<Diagnostic>,
    /// The resolved component, when the file parsed completely and has a
    /// `component` item.
    pub component: Option<Component>,
    /// Exploration figures, when the engines ran.
    pub statistics: Option<Statistics>,
    /// The `#pragma` lines of a GenoM3 file, in preprocessor order.
    pub pragmas: Vec<Pragma>,
    /// Worst-case response times by service name, when an engine computed
    /// them (LANGUAGE.md components with timing).
    pub response_times: Vec<ResponseTime>,
}

/// How to read a file: its dialect and, for GenoM3, where its includes and
/// WCETs are.
#[derive(Debug, Clone, Default)]
pub struct Inputs {
    /// The dialect; `None` recognises it by its syntax.
    pub dialect: Option<Dialect>,
    /// GenoM3 include folders (`-I`), searched in order after the including
    /// file's folder and before `GENOM_INCLUDE_PATH`.
    pub include_dirs: Vec<PathBuf>,
    /// A GenoM3 WCET side file (`--wcet`).
    pub wcet_file: Option<PathBuf>,
}

/// Why a file was not checked at all.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum InputError {
    /// The file (or the WCET file) cannot be read.
    #[error("cannot read `{path}`: {error}")]
    Read {
        /// The path as given.
        path: String,
        /// Why.
        error: LoadError,
    },
    /// `--wcet` on a file that is not GenoM3.
    #[error(
        "`--wcet` gives the WCETs of a GenoM3 component, and `{path}` was read as LANGUAGE.md, whose codels carry their own `wcet:`"
    )]
    WcetNeedsGenom3 {
        /// The checked file.
        path: String,
    },
}

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

impl CheckResult {
    /// The report of this result for rendering, under the path as given.
    pub fn report<'a>(&'a self, path: &'a str) -> genom_model::render::FileReport<'a> {
        genom_model::render::FileReport {
            path,
            sources: &self.sources,
            diagnostics: &self.diagnostics,
            statistics: self.statistics.as_ref(),
            dialect: self.dialect,
            pragmas: &self.pragmas,
            response_times: &self.response_times,
        }
    }

    /// Adds diagnostics, keeping them sorted.
    pub(crate) fn extend(&mut self, more: impl IntoIterator<Item = Diagnostic>) {
        self.diagnostics.extend(more);
        sort_diagnostics(&mut self.diagnostics);
    }
}
