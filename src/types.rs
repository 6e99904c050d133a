//! What a check takes and gives: the inputs of a file, why it could not
//! be read, the result (the checker's [`genom_checker::Checked`]), and how
//! a path is shown.

use std::path::PathBuf;

use gen_frontend::LoadError;
use genom_model::component::Component;
use genom_model::{Diagnostic, Dialect, Pragma, ResponseTime, SourceMap, Statistics};

pub use genom_model::loader::{STDIN_NAME, display, is_stdin};

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

impl From<genom_checker::Checked> for CheckResult {
    fn from(c: genom_checker::Checked) -> Self {
        CheckResult {
            dialect: c.dialect,
            sources: c.sources,
            diagnostics: c.diagnostics,
            component: c.component,
            statistics: c.statistics,
            pragmas: c.pragmas,
            response_times: c.response_times,
        }
    }
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
}
