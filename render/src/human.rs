//! Human output: miette graphical reports with source snippets, labels and
//! help, a numbered trace for behavioural verdicts, and a one-line summary.
//! File names, messages and labels never reach the terminal raw: their
//! control characters are shown escaped (`\u{1b}`), see [`escaped`].

use std::borrow::Cow;
use std::fmt::{self, Write as _};

use miette::{
    GraphicalReportHandler, GraphicalTheme, LabeledSpan, MietteError, MietteSpanContents,
    SourceCode, SourceSpan, SpanContents,
};

use genom_model::diagnostic::{Counts, Diagnostic, Severity};
pub use genom_model::duration::format_ns;
use genom_model::span::{FileId, SourceMap, Span};
use genom_model::trace::{Event, Trace};

use crate::{FileReport, escaped, escaped_keeping_lines};

/// How to draw reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HumanOptions {
    /// ANSI colours.
    pub color: bool,
    /// Line width for wrapping.
    pub width: usize,
}

impl Default for HumanOptions {
    fn default() -> Self {
        Self {
            color: false,
            width: 100,
        }
    }
}

/// Renders every diagnostic of a file (not the summary).
pub fn render_diagnostics(report: &FileReport<'_>, options: HumanOptions) -> String {
    let mut out = String::new();
    for d in report.diagnostics {
        out.push_str(&render_diagnostic(report.sources, d, options));
    }
    out
}

/// Renders an advice in one line, as the default human report shows it
/// (`--verbose` shows it in full): `☞ CODE: message (file:line:column)`.
pub fn render_advice_line(sources: &SourceMap, d: &Diagnostic, options: HumanOptions) -> String {
    let at = crate::json::location(sources, d.span());
    let place = if at.file.is_empty() {
        String::new()
    } else {
        format!(" ({}:{}:{})", escaped(&at.file), at.line, at.column)
    };
    let (on, off) = if options.color {
        ("\u{1b}[36m", "\u{1b}[0m")
    } else {
        ("", "")
    };
    format!("{on}☞ {}{off}: {}{place}\n", d.code, escaped(&d.message))
}

/// Renders one diagnostic as a graphical report followed by its trace.
pub fn render_diagnostic(sources: &SourceMap, d: &Diagnostic, options: HumanOptions) -> String {
    let theme = if options.color {
        GraphicalTheme::unicode()
    } else {
        GraphicalTheme::unicode_nocolor()
    };
    let handler = GraphicalReportHandler::new_themed(theme)
        .with_width(options.width)
        .with_links(false);
    let adapter = Report::new(sources, d);
    let mut out = String::new();
    if handler.render_report(&mut out, &adapter).is_err() {
        let _ = writeln!(out, "{}: {}", d.code, d.message);
    }
    if let Some(trace) = &d.trace {
        out.push_str(&render_trace(sources, trace));
    }
    out.push('\n');
    out
}

/// The one-line summary: `pilot.gen: 0 errors, 0 warnings, 1 advice` (the
/// name's control characters escaped).
pub fn render_summary(path: &str, counts: Counts) -> String {
    format!("{}: {}", escaped(path), counts_text(counts))
}

/// `1 error, 2 warnings, 0 advice`.
fn counts_text(counts: Counts) -> String {
    format!(
        "{} {}, {} {}, {} advice",
        counts.errors,
        plural(counts.errors, "error"),
        counts.warnings,
        plural(counts.warnings, "warning"),
        counts.advice
    )
}

/// The grand total over the files of one run, as ruff prints it:
/// `Found 1 error, 2 warnings, 0 advice in 3 files.`
pub fn render_total(counts: Counts, files: usize) -> String {
    format!(
        "Found {} in {files} {}.",
        counts_text(counts),
        plural(files, "file")
    )
}

fn plural(n: usize, word: &str) -> String {
    if n == 1 {
        word.to_owned()
    } else {
        format!("{word}s")
    }
}

/// Renders a trace as numbered steps with the source line of each; a timed
/// trace also gets a timeline per thread.
pub fn render_trace(sources: &SourceMap, trace: &Trace) -> String {
    let mut out = String::from("  trace:\n");
    out.push_str(&aside_note(trace).unwrap_or_default());
    for (i, step) in trace.steps.iter().enumerate() {
        if step.aside {
            continue;
        }
        if trace.loop_start == Some(i) {
            out.push_str("      -- the following steps repeat forever --\n");
        }
        let time = step
            .time_ns
            .map(|t| format!("[{}] ", format_instant(t)))
            .unwrap_or_default();
        let place = step.span.map(|s| location(sources, s)).unwrap_or_default();
        let text = escaped(&step.text);
        let _ = writeln!(out, "  {:>4}. {time}{text}{place}", i + 1);
    }
    if trace.steps.iter().any(|s| s.time_ns.is_some()) {
        out.push_str(&render_timeline(trace));
    }
    out
}

/// The line saying which threads' steps a trace leaves out
/// ([`genom_model::trace::TraceStep::aside`]), if any.
fn aside_note(trace: &Trace) -> Option<String> {
    let shown: Vec<String> = trace
        .aside_threads()
        .iter()
        .map(|t| format!("`{t}`"))
        .collect();
    if shown.is_empty() {
        return None;
    }
    let s = if shown.len() == 1 { "" } else { "s" };
    Some(format!(
        "        (the steps of task{s} {}, which play no part in this finding, are left out; `--format json` lists every step)\n",
        shown.join(", ")
    ))
}

/// One line per thread: its wake-ups (`|`) and codel executions with their
/// start and end instants; the control thread's requests.
pub fn render_timeline(trace: &Trace) -> String {
    let mut threads: Vec<(String, Vec<String>)> = Vec::new();
    let mut open: Vec<(String, String, u64)> = Vec::new();
    for step in &trace.steps {
        let (Some(thread), Some(t)) = (&step.thread, step.time_ns) else {
            continue;
        };
        if step.aside {
            continue;
        }
        let item = match step.event {
            Event::WakeUp => Some(format!("|{}", format_instant(t))),
            Event::CodelStart => {
                open.push((thread.clone(), step.codel.clone().unwrap_or_default(), t));
                None
            }
            Event::CodelEnd => {
                let at = open
                    .iter()
                    .rposition(|(th, c, _)| th == thread && Some(c) == step.codel.as_ref());
                let start = at.map_or(t, |k| open.remove(k).2);
                let who = format!(
                    "{}::{}",
                    step.service.clone().unwrap_or_default(),
                    step.codel.clone().unwrap_or_default()
                );
                let outcome = step
                    .outcome
                    .as_ref()
                    .map(|o| format!("→{o}"))
                    .unwrap_or_default();
                Some(format!(
                    "{who}[{}–{}]{outcome}",
                    format_instant(start),
                    format_instant(t)
                ))
            }
            Event::Request | Event::Reject | Event::Acknowledge => {
                let what = match step.event {
                    Event::Request => "request",
                    Event::Reject => "reject",
                    _ => "ack",
                };
                Some(format!(
                    "{what} {}@{}",
                    step.service.clone().unwrap_or_default(),
                    format_instant(t)
                ))
            }
            _ => None,
        };
        let Some(item) = item else { continue };
        match threads.iter_mut().find(|(name, _)| name == thread) {
            Some((_, items)) => items.push(item),
            None => threads.push((thread.clone(), vec![item])),
        }
    }
    for (thread, _, start) in open {
        let item = format!("(running since {})", format_instant(start));
        if let Some((_, items)) = threads.iter_mut().find(|(name, _)| *name == thread) {
            items.push(item);
        }
    }
    if threads.is_empty() {
        // A timed trace whose steps name no thread (a chain's timeline
        // across components) has no per-thread line to draw.
        return String::new();
    }
    let width = threads
        .iter()
        .map(|(n, _)| n.chars().count())
        .max()
        .unwrap_or(0);
    let mut out = String::from("  timeline:\n");
    for (name, items) in threads {
        let _ = writeln!(out, "    {name:<width$}  {}", items.join("  "));
    }
    out
}

/// An instant: whole units when exact (`12ms`), else milliseconds with
/// decimals (`1000.000217ms`).
pub fn format_instant(ns: u64) -> String {
    if ns == 0 || ns % 1_000 == 0 {
        return format_ns(ns);
    }
    let ms = ns / 1_000_000;
    let frac = format!("{:06}", ns % 1_000_000);
    format!("{ms}.{}ms", frac.trim_end_matches('0'))
}

fn location(sources: &SourceMap, span: Span) -> String {
    let Some(loc) = sources.locate(span) else {
        return String::new();
    };
    let Some(file) = sources.file(loc.file) else {
        return String::new();
    };
    let (line, _) = file.line_col(loc.offset);
    format!("  ({}:{line})", escaped(&file.display_path()))
}

/// Adapts a diagnostic to miette: labels in the primary file are shown in
/// the main snippet; labels in other files become related reports.
struct Report<'a> {
    diagnostic: &'a Diagnostic,
    /// For a related report: its own message (the label's text).
    related_message: Option<String>,
    source: Option<FileSource<'a>>,
    labels: Vec<LabeledSpan>,
    related: Vec<Report<'a>>,
}

impl<'a> Report<'a> {
    fn new(sources: &'a SourceMap, d: &'a Diagnostic) -> Self {
        let primary = sources.locate(d.span()).map(|l| l.file);
        let mut labels = Vec::new();
        let mut related = Vec::new();
        for label in &d.labels {
            let Some(loc) = sources.locate(label.span) else {
                continue;
            };
            if Some(loc.file) == primary {
                labels.push(labeled(
                    &label.message,
                    loc.offset,
                    loc.length,
                    labels.is_empty(),
                ));
            } else {
                related.push(Report::related(sources, d, loc.file, &label.message, loc));
            }
        }
        let spans: Vec<(usize, usize)> = labels.iter().map(|l| (l.offset(), l.len())).collect();
        let source = primary.and_then(|f| FileSource::around(sources, f, &spans));
        if let Some((_, lines)) = &source {
            labels = labels.iter().filter_map(|l| lines.relabel(l)).collect();
        }
        let mut source = source.map(|(s, _)| s);
        if let (Some(s), Some(first)) = (source.as_mut(), labels.first()) {
            if let Some(window) = s.cut_long_line(first.offset(), first.len()) {
                labels = labels.iter().filter_map(|l| window.relabel(l)).collect();
            }
        }
        Report {
            diagnostic: d,
            related_message: None,
            source,
            labels,
            related,
        }
    }

    fn related(
        sources: &'a SourceMap,
        d: &'a Diagnostic,
        file: FileId,
        message: &str,
        loc: genom_model::span::Located,
    ) -> Self {
        let text = if message.is_empty() {
            "related location"
        } else {
            message
        };
        let span = (loc.offset as usize, loc.length as usize);
        let (source, lines) = match FileSource::around(sources, file, &[span]) {
            Some((s, w)) => (Some(s), Some(w)),
            None => (None, None),
        };
        let label = labeled("", loc.offset, loc.length, true);
        let labels = match lines {
            Some(w) => w.relabel(&label).into_iter().collect(),
            None => vec![label],
        };
        Report {
            diagnostic: d,
            related_message: Some(text.to_owned()),
            source,
            labels,
            related: Vec::new(),
        }
    }
}

fn labeled(message: &str, offset: u32, length: u32, primary: bool) -> LabeledSpan {
    let text = (!message.is_empty()).then(|| escaped_keeping_lines(message).into_owned());
    let span = SourceSpan::new((offset as usize).into(), length as usize);
    if primary {
        LabeledSpan::new_primary_with_span(text, span)
    } else {
        LabeledSpan::new_with_span(text, span)
    }
}

impl fmt::Debug for Report<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Report")
            .field("code", &self.diagnostic.code)
            .finish()
    }
}

impl fmt::Display for Report<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let message = self
            .related_message
            .as_deref()
            .unwrap_or(&self.diagnostic.message);
        f.write_str(&escaped_keeping_lines(message))
    }
}

impl std::error::Error for Report<'_> {}

impl miette::Diagnostic for Report<'_> {
    fn code<'b>(&'b self) -> Option<Box<dyn fmt::Display + 'b>> {
        if self.related_message.is_some() {
            return None;
        }
        Some(Box::new(self.diagnostic.code.as_str()))
    }

    fn severity(&self) -> Option<miette::Severity> {
        if self.related_message.is_some() {
            return Some(miette::Severity::Advice);
        }
        Some(match self.diagnostic.severity {
            Severity::Error => miette::Severity::Error,
            Severity::Warning => miette::Severity::Warning,
            Severity::Advice => miette::Severity::Advice,
        })
    }

    fn help<'b>(&'b self) -> Option<Box<dyn fmt::Display + 'b>> {
        if self.related_message.is_some() {
            return None;
        }
        self.diagnostic
            .help
            .as_deref()
            .map(|h| Box::new(escaped_keeping_lines(h)) as Box<dyn fmt::Display>)
    }

    fn source_code(&self) -> Option<&dyn SourceCode> {
        self.source.as_ref().map(|s| s as &dyn SourceCode)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        Some(Box::new(self.labels.iter().cloned()))
    }

    fn related<'b>(&'b self) -> Option<Box<dyn Iterator<Item = &'b dyn miette::Diagnostic> + 'b>> {
        if self.related.is_empty() {
            return None;
        }
        Some(Box::new(
            self.related.iter().map(|r| r as &dyn miette::Diagnostic),
        ))
    }
}

/// One file's text, named (control characters in the name escaped), as a
/// miette source; ASCII control characters
/// other than tabs and line ends are shown as `?` (same byte length, so
/// spans stay exact) rather than written raw to the terminal.
struct FileSource<'a> {
    name: String,
    text: Cow<'a, str>,
    /// When the text is a window cut out of one long line: the lines and
    /// columns (characters) before it, added to what miette reads.
    before: Option<(usize, usize)>,
}

/// Lines longer than this (bytes) are shown as a window around the label:
/// the renderer cannot draw labels past column 65 535, and a huge line
/// echoed whole is no help.
const LONG_LINE: usize = 1_000;

/// Bytes of context each side of a label in a window.
const WINDOW_CONTEXT: usize = 80;

/// Bytes of a label shown at most in a window.
const WINDOW_LABEL: usize = 200;

/// The part of a long line a report shows: bytes `start..end` of the file,
/// behind an ellipsis.
struct Window {
    start: usize,
    end: usize,
    /// Bytes of the ellipsis in front of the window (0 at the line's start).
    lead: usize,
}

impl Window {
    /// `l` moved into the window, or `None` when it lies outside.
    fn relabel(&self, l: &LabeledSpan) -> Option<LabeledSpan> {
        let (at, len) = (l.offset(), l.len());
        if at < self.start || at > self.end {
            return None;
        }
        let len = len.min(self.end - at);
        let span = SourceSpan::new((at - self.start + self.lead).into(), len);
        Some(if l.primary() {
            LabeledSpan::new_primary_with_span(l.label().map(str::to_owned), span)
        } else {
            LabeledSpan::new_with_span(l.label().map(str::to_owned), span)
        })
    }
}

/// Lines of context kept each side of the labels (miette shows one).
const CONTEXT_LINES: usize = 2;

/// Files larger than this (bytes) are cut to the lines around a report's
/// labels before miette reads them, so that rendering many diagnostics
/// of a large file stays linear (20 000 of them took 41 s, now 1.3 s).
const LARGE_FILE: usize = 1 << 16;

impl<'a> FileSource<'a> {
    /// The lines of `file` around the labels at `spans` (local offset and
    /// length), with [`CONTEXT_LINES`] each side, and the window that moves
    /// the labels into them: rendering one diagnostic costs the lines it
    /// shows, not the file (many diagnostics on a large file stay linear).
    fn around(
        sources: &'a SourceMap,
        file: FileId,
        spans: &[(usize, usize)],
    ) -> Option<(Self, Window)> {
        let f = sources.file(file)?;
        let lo = spans.iter().map(|s| s.0).min().unwrap_or(0);
        let hi = spans.iter().map(|s| s.0 + s.1).max().unwrap_or(0);
        let local = |at: usize| u32::try_from(at.min(f.text.len())).unwrap_or(u32::MAX);
        let (first, _) = f.line_col(local(lo));
        let (last, _) = f.line_col(local(hi));
        // A file of ordinary size is shown whole, as miette lays it out.
        let small = f.text.len() <= LARGE_FILE;
        let from = if small {
            1
        } else {
            first.saturating_sub(CONTEXT_LINES).max(1)
        };
        let start = f.line_start(from).unwrap_or(0);
        let end = match f.line_start(last + CONTEXT_LINES + 1) {
            Some(end) if !small => end,
            _ => f.text.len(),
        };
        let text = f.text.get(start..end).unwrap_or("");
        let source = FileSource {
            name: escaped(&f.display_path()).into_owned(),
            text: printable(text),
            before: Some((from - 1, 0)),
        };
        Some((
            source,
            Window {
                start,
                end,
                lead: 0,
            },
        ))
    }

    /// When the line of the label at `at` (`len` bytes) is longer than
    /// [`LONG_LINE`], keeps only a window of it around the label.
    fn cut_long_line(&mut self, at: usize, len: usize) -> Option<Window> {
        let text = self.text.as_ref();
        let at = at.min(text.len());
        let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
        let line_end = text[at..].find('\n').map_or(text.len(), |i| at + i);
        // miette shows a line of context each side: those count too.
        let before = text[..line_start.saturating_sub(1)]
            .rfind('\n')
            .map_or(0, |i| i + 1);
        let after = text[line_end..]
            .get(1..)
            .and_then(|t| t.find('\n'))
            .map_or(text.len(), |i| line_end + 1 + i);
        if line_end - line_start <= LONG_LINE
            && line_start.saturating_sub(before) <= LONG_LINE
            && after.saturating_sub(line_end) <= LONG_LINE
        {
            return None;
        }
        let floor = |mut i: usize| {
            while !text.is_char_boundary(i) {
                i -= 1;
            }
            i
        };
        let start = floor(at.saturating_sub(WINDOW_CONTEXT).max(line_start));
        let end = floor((at + len.min(WINDOW_LABEL) + WINDOW_CONTEXT).min(line_end));
        let lines = self.before.map_or(0, |b| b.0) + text[..line_start].matches('\n').count();
        let columns = text[line_start..start].chars().count();
        let lead = if start > line_start { "…" } else { "" };
        let tail = if end < line_end { "…" } else { "" };
        let shown = format!("{lead}{}{tail}", &text[start..end]);
        self.text = Cow::Owned(shown);
        // The ellipsis takes the column before the window.
        self.before = Some((lines, columns.saturating_sub(usize::from(!lead.is_empty()))));
        Some(Window {
            start,
            end,
            lead: lead.len(),
        })
    }
}

/// `text` with ASCII control characters other than `\t`, `\n` and `\r`
/// replaced by `?`.
fn printable(text: &str) -> Cow<'_, str> {
    let hidden = |c: char| c.is_ascii_control() && !matches!(c, '\t' | '\n' | '\r');
    if text.contains(hidden) {
        Cow::Owned(
            text.chars()
                .map(|c| if hidden(c) { '?' } else { c })
                .collect(),
        )
    } else {
        Cow::Borrowed(text)
    }
}

impl SourceCode for FileSource<'_> {
    fn read_span<'b>(
        &'b self,
        span: &SourceSpan,
        context_lines_before: usize,
        context_lines_after: usize,
    ) -> Result<Box<dyn SpanContents<'b> + 'b>, MietteError> {
        let inner =
            self.text
                .as_ref()
                .read_span(span, context_lines_before, context_lines_after)?;
        let (lines, columns) = self.before.unwrap_or((0, 0));
        Ok(Box::new(MietteSpanContents::new_named(
            self.name.clone(),
            inner.data(),
            *inner.span(),
            inner.line() + lines,
            inner.column() + columns,
            inner.line_count(),
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use genom_model::diagnostic::Code;

    #[test]
    fn summary_pluralises() {
        let c = Counts {
            errors: 1,
            warnings: 2,
            advice: 1,
        };
        assert_eq!(
            render_summary("pilot.gen", c),
            "pilot.gen: 1 error, 2 warnings, 1 advice"
        );
        assert_eq!(
            render_summary("a.gen", Counts::default()),
            "a.gen: 0 errors, 0 warnings, 0 advice"
        );
    }

    #[test]
    fn instants_keep_sub_microsecond_precision() {
        assert_eq!(format_instant(12_000_000), "12ms");
        assert_eq!(format_instant(1_000_000_217), "1000.000217ms");
        assert_eq!(format_instant(250), "0.00025ms");
    }

    #[test]
    fn durations_use_the_largest_exact_unit() {
        assert_eq!(format_ns(1_000_000_000), "1s");
        assert_eq!(format_ns(1_500_000_000), "1500ms");
        assert_eq!(format_ns(250_000), "250us");
        assert_eq!(format_ns(7), "7ns");
        assert_eq!(format_ns(120_000_000_000), "2min");
    }

    #[test]
    fn report_shows_code_snippet_label_and_help() {
        let mut map = SourceMap::new();
        map.add("x.gen", "component x {\n  lang C;\n}\n".into());
        let d = Diagnostic::new(
            Code::Syntax,
            "expected `:`",
            Span::new(21, 22),
            "expected `:` here",
        )
        .with_help("attributes are written `name: value;`");
        let text = render_diagnostic(&map, &d, HumanOptions::default());
        assert!(text.contains("syntax"), "{text}");
        assert!(text.contains("expected `:`"), "{text}");
        assert!(text.contains("x.gen:2:"), "{text}");
        assert!(text.contains("lang C;"), "{text}");
        assert!(text.contains("attributes are written"), "{text}");
    }

    #[test]
    fn labels_in_other_files_become_related_reports() {
        let mut map = SourceMap::new();
        map.add("a.gen", "include \"b.idl\";\n".into());
        let b = map.add("b.idl", "struct S { long x; };\n".into());
        let base = map.file(b).unwrap().base;
        let d = Diagnostic::new(
            Code::DuplicateDefinition,
            "`S` is defined twice",
            Span::new(0, 7),
            "here",
        )
        .with_label(Span::new(base + 7, base + 8), "first defined here");
        let text = render_diagnostic(&map, &d, HumanOptions::default());
        assert!(text.contains("a.gen:1:1"), "{text}");
        assert!(text.contains("b.idl:1:8"), "{text}");
        assert!(text.contains("first defined here"), "{text}");
    }

    #[test]
    fn control_characters_in_names_and_messages_are_shown_escaped() {
        let name = "a\n::error file=evil.gen,line=1::x\u{1b}[2J.gen";
        let summary = render_summary(name, Counts::default());
        assert_eq!(
            summary,
            "a\\n::error file=evil.gen,line=1::x\\u{1b}[2J.gen: 0 errors, 0 warnings, 0 advice"
        );
        let mut map = SourceMap::new();
        map.add(name, "component x {\n  lang C;\n}\n".into());
        let d = Diagnostic::new(
            Code::Syntax,
            "bad \u{1b}[31m",
            Span::new(21, 22),
            "here\u{7}",
        )
        .with_help("see \u{1b}]8;;x");
        let text = render_diagnostic(&map, &d, HumanOptions::default());
        assert!(
            !text.contains('\u{1b}') && !text.contains('\u{7}'),
            "{text:?}"
        );
        assert!(text.contains("x\\u{1b}[2J.gen:2:"), "{text}");
        assert!(text.contains("bad \\u{1b}[31m"), "{text}");
    }
}
