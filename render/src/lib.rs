//! `genom-render`: where a [`Diagnostic`] becomes text. It owns every
//! report format of `--format`: graphical reports with miette ([`human`]),
//! the versioned JSON document ([`json`]), GitHub Actions annotations
//! ([`github`]) and SARIF 2.1.0 ([`sarif`]), and the escaping of names and
//! messages from outside ([`escaped`]). Rendering returns strings; only the
//! binary prints.
//!
//! It depends on `genom-model` alone (the diagnostics, spans, traces and
//! statistics it renders) and must not depend on the front-ends, the
//! checker, the engines or the exports: they do not render, so a change
//! here rebuilds only the binary (and the tests that read reports).
//! Durations are written by [`genom_model::duration::format_ns`], which
//! the engines' messages share; [`human::format_ns`] re-exports it.
//!
//! [`Diagnostic`]: genom_model::Diagnostic

pub mod github;
pub mod human;
pub mod json;
pub mod sarif;

use std::borrow::Cow;

use genom_model::diagnostic::{Counts, Diagnostic};
use genom_model::dialect::{Dialect, Pragma};
use genom_model::response::ResponseTime;
use genom_model::span::SourceMap;
use genom_model::stats::Statistics;

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

/// `text` as it may be written to a terminal or a log on one line: control
/// characters (C0, DEL, C1) and the bidirectional-text controls, which
/// would move the cursor, change colours, start a line or reorder what
/// follows, are shown as Rust escapes (`\n`, `\u{1b}`, `\u{202e}`), as
/// [`quote`](genom_model::diagnostic::quote) shows them in messages. For names
/// (files) that come from outside.
pub fn escaped(text: &str) -> Cow<'_, str> {
    escape(text, false)
}

/// [`escaped`], keeping line ends and tabs: for messages, help and trace
/// text, which may span lines.
pub fn escaped_keeping_lines(text: &str) -> Cow<'_, str> {
    escape(text, true)
}

fn escape(text: &str, keep_lines: bool) -> Cow<'_, str> {
    let hidden = |c: char| {
        (c.is_control() && !(keep_lines && matches!(c, '\n' | '\t'))) || is_bidi_control(c)
    };
    if !text.contains(hidden) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if is_bidi_control(c) {
            out.extend(c.escape_unicode());
        } else if hidden(c) {
            out.extend(c.escape_debug());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

/// The Unicode controls that reorder bidirectional text (marks, embeddings,
/// overrides, isolates).
fn is_bidi_control(c: char) -> bool {
    matches!(c, '\u{061c}' | '\u{200e}' | '\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_escaped_on_one_line_and_messages_keep_their_lines() {
        assert_eq!(escaped("pilot.gen"), "pilot.gen");
        assert!(matches!(escaped("pilot.gen"), Cow::Borrowed(_)));
        assert_eq!(
            escaped("a\n::error x\u{1b}[31m\r\t\u{7f}\u{9b}.gen"),
            "a\\n::error x\\u{1b}[31m\\r\\t\\u{7f}\\u{9b}.gen"
        );
        assert_eq!(escaped("abc\u{202e}gen.exe"), "abc\\u{202e}gen.exe");
        assert_eq!(
            escaped_keeping_lines("line 1\n\tline 2\u{1b}"),
            "line 1\n\tline 2\\u{1b}"
        );
        assert_eq!(escaped("é 世界"), "é 世界");
    }
}
