//! What a check takes and gives: the inputs of a file, why it could not
//! be read, the result, and how a path is shown. Both the pipeline and the
//! GenoM3 check use them.

use std::path::{Path, PathBuf};

use genom_model::component::Component;
use genom_model::{
    Diagnostic, Dialect, Pragma, ResponseTime, SourceMap, Statistics, sort_diagnostics,
};
use genom_parser::LoadError;

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

impl CheckResult {
    /// The report of this result for rendering, under the path as given.
    pub fn report<'a>(&'a self, path: &'a str) -> genom_render::FileReport<'a> {
        genom_render::FileReport {
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
