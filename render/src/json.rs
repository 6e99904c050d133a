//! Machine output: one versioned JSON document for a whole run
//! (`--format json`). The format is documented in `docs/json-format.md`;
//! bump [`FORMAT_VERSION`] on any incompatible change.

use serde::Serialize;

use genom_model::diagnostic::{Counts, Diagnostic};
use genom_model::response::JsonResponseTime;
use genom_model::span::{SourceMap, Span};
use genom_model::stats::{Assumption, Statistics};
use genom_model::trace::{Trace, TraceStep};

use crate::FileReport;

/// Version of the JSON document format.
pub const FORMAT_VERSION: u32 = 1;

/// The whole document.
#[derive(Debug, Serialize)]
pub struct JsonDocument {
    /// Format version.
    pub version: u32,
    /// One entry per checked file, in command-line order.
    pub files: Vec<JsonFile>,
    /// The files that could not be read at all, in command-line order.
    pub unread: Vec<JsonUnread>,
    /// Totals over all files.
    pub summary: JsonSummary,
}

/// One checked file.
#[derive(Debug, Serialize)]
pub struct JsonFile {
    /// The path as given.
    pub path: String,
    /// The language it was read as: `gen` (LANGUAGE.md) or `genom3`.
    pub dialect: &'static str,
    /// Its diagnostics, sorted.
    pub diagnostics: Vec<JsonDiagnostic>,
    /// Exploration figures, or null when the engines did not run.
    pub statistics: Option<Statistics>,
    /// Its `#pragma` lines (GenoM3), in preprocessor order.
    pub pragmas: Vec<JsonPragma>,
    /// Worst-case response times by service name (empty when not
    /// computed: no timing, or the engines did not run).
    pub response_times: Vec<JsonResponseTime>,
    /// What the verdicts rest on besides the component (a WCET file, an
    /// instance bound); empty when they rest on nothing else.
    pub assumptions: Vec<Assumption>,
}

/// A `#pragma` line.
#[derive(Debug, Serialize)]
pub struct JsonPragma {
    /// `require`, `provides`, `masquerade` or another word.
    pub kind: String,
    /// The rest of the line.
    pub args: String,
    /// Where.
    #[serde(flatten)]
    pub location: JsonLocation,
}

/// A file that could not be read (exit status 2).
#[derive(Debug, Clone, Serialize)]
pub struct JsonUnread {
    /// The path as given.
    pub path: String,
    /// Why, e.g. ``cannot read `x.gen`: no such file``.
    pub error: String,
}

/// Totals.
#[derive(Debug, Serialize)]
pub struct JsonSummary {
    /// Number of errors.
    pub errors: usize,
    /// Number of warnings.
    pub warnings: usize,
    /// Number of advice.
    pub advice: usize,
    /// Number of files that could not be read.
    pub unread: usize,
    /// States explored over all files.
    pub states: u64,
    /// Transitions fired over all files.
    pub transitions: u64,
    /// Wall-clock time over all files, in milliseconds.
    pub time_ms: f64,
}

/// A location: file, 1-based line and column, byte span in that file.
#[derive(Debug, Serialize)]
pub struct JsonLocation {
    /// The file the span is in.
    pub file: String,
    /// 1-based line.
    pub line: usize,
    /// 1-based column, in characters.
    pub column: usize,
    /// Byte offset and length within that file.
    pub span: JsonSpan,
}

/// Byte offset and length within a file.
#[derive(Debug, Serialize)]
pub struct JsonSpan {
    /// Byte offset from the start of the file.
    pub offset: u32,
    /// Length in bytes.
    pub length: u32,
}

/// One diagnostic.
#[derive(Debug, Serialize)]
pub struct JsonDiagnostic {
    /// Stable code.
    pub code: &'static str,
    /// `error`, `warning` or `advice`.
    pub severity: &'static str,
    /// Message.
    pub message: String,
    /// Primary location.
    #[serde(flatten)]
    pub location: JsonLocation,
    /// All labels, the primary first.
    pub labels: Vec<JsonLabel>,
    /// Help, or null.
    pub help: Option<String>,
    /// Trace steps, or null.
    pub trace: Option<Vec<JsonStep>>,
}

/// A labelled span.
#[derive(Debug, Serialize)]
pub struct JsonLabel {
    /// The label text.
    pub message: String,
    /// Where.
    #[serde(flatten)]
    pub location: JsonLocation,
}

/// One trace step.
#[derive(Debug, Serialize)]
pub struct JsonStep {
    /// 1-based step number.
    pub step: usize,
    /// Event kind (`request`, `codel-end`, ...).
    pub event: &'static str,
    /// Time in nanoseconds since component start, or null when untimed.
    pub time_ns: Option<u64>,
    /// Thread, or null.
    pub thread: Option<String>,
    /// Service, or null.
    pub service: Option<String>,
    /// Codel, or null.
    pub codel: Option<String>,
    /// Outcome, reject reason or reply, or null.
    pub outcome: Option<String>,
    /// Whether this step starts the cycle that repeats forever.
    pub loop_start: bool,
    /// Whether this step is one of a thread that plays no part in the
    /// finding (`TraceStep::aside`; left out of human output).
    pub aside: bool,
    /// Description.
    pub text: String,
    /// Source location, or null.
    pub location: Option<JsonLocation>,
}

/// Builds the document for a run.
pub fn document(reports: &[FileReport<'_>]) -> JsonDocument {
    document_with_unread(reports, &[])
}

/// Builds the document for a run in which the `unread` files could not be
/// read.
pub fn document_with_unread(reports: &[FileReport<'_>], unread: &[JsonUnread]) -> JsonDocument {
    let mut counts = Counts::default();
    let mut summary = JsonSummary {
        errors: 0,
        warnings: 0,
        advice: 0,
        unread: unread.len(),
        states: 0,
        transitions: 0,
        time_ms: 0.0,
    };
    let files = reports
        .iter()
        .map(|r| {
            counts.merge(r.counts());
            if let Some(s) = r.statistics {
                summary.states += s.states;
                summary.transitions += s.transitions;
                summary.time_ms += s.time_ms;
            }
            JsonFile {
                path: r.path.to_owned(),
                dialect: r.dialect.as_str(),
                pragmas: r
                    .pragmas
                    .iter()
                    .map(|p| JsonPragma {
                        kind: p.kind.clone(),
                        args: p.args.clone(),
                        location: location(r.sources, p.span),
                    })
                    .collect(),
                diagnostics: r
                    .diagnostics
                    .iter()
                    .map(|d| diagnostic(r.sources, d))
                    .collect(),
                statistics: r.statistics.cloned(),
                response_times: r
                    .response_times
                    .iter()
                    .map(JsonResponseTime::from)
                    .collect(),
                assumptions: r
                    .statistics
                    .map(|s| s.assumptions.clone())
                    .unwrap_or_default(),
            }
        })
        .collect();
    summary.errors = counts.errors;
    summary.warnings = counts.warnings;
    summary.advice = counts.advice;
    JsonDocument {
        version: FORMAT_VERSION,
        files,
        unread: unread.to_vec(),
        summary,
    }
}

/// Renders the document as pretty JSON text.
pub fn render(reports: &[FileReport<'_>]) -> String {
    render_with_unread(reports, &[])
}

/// Renders the document of a run in which the `unread` files could not be
/// read.
pub fn render_with_unread(reports: &[FileReport<'_>], unread: &[JsonUnread]) -> String {
    serde_json::to_string_pretty(&document_with_unread(reports, unread))
        .unwrap_or_else(|e| format!("{{\"error\":\"{e}\"}}"))
}

/// Converts one diagnostic.
pub fn diagnostic(sources: &SourceMap, d: &Diagnostic) -> JsonDiagnostic {
    JsonDiagnostic {
        code: d.code.as_str(),
        severity: d.severity.as_str(),
        message: d.message.clone(),
        location: location(sources, d.span()),
        labels: d
            .labels
            .iter()
            .map(|l| JsonLabel {
                message: l.message.clone(),
                location: location(sources, l.span),
            })
            .collect(),
        help: d.help.clone(),
        trace: d.trace.as_ref().map(|t| trace(sources, t)),
    }
}

fn trace(sources: &SourceMap, t: &Trace) -> Vec<JsonStep> {
    t.steps
        .iter()
        .enumerate()
        .map(|(i, s)| step(sources, i, s, t.loop_start == Some(i)))
        .collect()
}

fn step(sources: &SourceMap, i: usize, s: &TraceStep, loop_start: bool) -> JsonStep {
    JsonStep {
        step: i + 1,
        event: s.event.as_str(),
        time_ns: s.time_ns,
        thread: s.thread.clone(),
        service: s.service.clone(),
        codel: s.codel.clone(),
        outcome: s.outcome.clone(),
        loop_start,
        aside: s.aside,
        text: s.text.clone(),
        location: s.span.map(|sp| location(sources, sp)),
    }
}

/// The start of `span` resolved as [`location`], and its end as 1-based
/// line and column (the column after the last character) when the span
/// ends in the same file, for formats that give regions (GitHub, SARIF).
pub fn region(sources: &SourceMap, span: Span) -> (JsonLocation, Option<(usize, usize)>) {
    let start = location(sources, span);
    let end = location(sources, Span::point(span.end.max(span.start)));
    let same_file = end.file == start.file && end.line >= start.line;
    let end = same_file.then_some((end.line, end.column));
    (start, end)
}

/// Resolves a global span to file, line, column and local span.
pub fn location(sources: &SourceMap, span: Span) -> JsonLocation {
    let located = sources.locate(span);
    let file = located.and_then(|l| sources.file(l.file));
    match (located, file) {
        (Some(l), Some(f)) => {
            let (line, column) = f.line_col(l.offset);
            JsonLocation {
                file: f.display_path(),
                line,
                column,
                span: JsonSpan {
                    offset: l.offset,
                    length: l.length,
                },
            }
        }
        _ => JsonLocation {
            file: String::new(),
            line: 1,
            column: 1,
            span: JsonSpan {
                offset: 0,
                length: 0,
            },
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use genom_model::diagnostic::Code;

    #[test]
    fn document_has_the_documented_shape() {
        let mut map = SourceMap::new();
        map.add("specs/x.gen", "component x {}\nfoo\n".into());
        let d = Diagnostic::new(Code::Syntax, "expected item", Span::new(15, 18), "here");
        let diags = [d];
        let report = FileReport {
            path: "specs/x.gen",
            sources: &map,
            diagnostics: &diags,
            statistics: None,
            dialect: genom_model::dialect::Dialect::Gen,
            pragmas: &[],
            response_times: &[],
        };
        let v: serde_json::Value = serde_json::from_str(&render(&[report])).unwrap();
        assert_eq!(v["version"], 1);
        let d = &v["files"][0]["diagnostics"][0];
        assert_eq!(d["code"], "syntax");
        assert_eq!(d["severity"], "error");
        assert_eq!(d["file"], "specs/x.gen");
        assert_eq!(
            (d["line"].as_u64(), d["column"].as_u64()),
            (Some(2), Some(1))
        );
        assert_eq!(d["span"]["offset"], 15);
        assert_eq!(d["span"]["length"], 3);
        assert_eq!(d["labels"][0]["message"], "here");
        assert_eq!(d["labels"][0]["line"], 2);
        assert!(d["help"].is_null());
        assert!(d["trace"].is_null());
        assert_eq!(v["summary"]["errors"], 1);
        assert_eq!(v["summary"]["warnings"], 0);
    }
}
