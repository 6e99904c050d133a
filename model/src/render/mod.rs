//! Rendering of diagnostics, the one place where a [`Diagnostic`] becomes
//! text: graphical reports with miette ([`human`]), the versioned JSON
//! document ([`json`]), GitHub Actions annotations ([`github`]) and SARIF
//! 2.1.0 ([`sarif`]). Rendering returns strings; only the binary prints.
//!
//! [`Diagnostic`]: crate::Diagnostic

pub mod github;
pub mod human;
pub mod json;
pub mod sarif;

use crate::diagnostic::{Counts, Diagnostic};
use crate::dialect::{Dialect, Pragma};
use crate::response::ResponseTime;
use crate::span::SourceMap;
use crate::stats::Statistics;

/// Everything known about one checked file, ready to render.
#[derive(Debug, Clone, Copy)]
pub struct FileReport<'a> {
    /// The path as the user gave it.
    pub path: &'a str,
    /// The checked file and every file it includes.
    pub sources: &'a SourceMap,
    /// Sorted diagnostics.
    pub diagnostics: &'a [Diagnostic],
    /// Exploration figures, when the behavioural engines ran.
    pub statistics: Option<&'a Statistics>,
    /// The language the file was read as.
    pub dialect: Dialect,
    /// Its `#pragma` lines (GenoM3), in preprocessor order.
    pub pragmas: &'a [Pragma],
    /// Worst-case response times, by service name (empty when not
    /// computed).
    pub response_times: &'a [ResponseTime],
}

impl FileReport<'_> {
    /// Counts of this file's diagnostics by severity.
    pub fn counts(&self) -> Counts {
        Counts::of(self.diagnostics)
    }
}
