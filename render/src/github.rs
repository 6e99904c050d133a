//! GitHub Actions output (`--format github`): one workflow command per
//! diagnostic, which GitHub shows as an annotation on the line of the pull
//! request (`::error file=F,line=L,col=C,endLine=L2,endColumn=C2,title=CODE::MESSAGE`).
//! Errors are `error`, warnings `warning`, advice `notice`; the message
//! carries the help and the steps of the trace on further lines (encoded,
//! as the workflow-command syntax asks). The location is the primary
//! label's, in the file it points into (an included file too). A file's
//! summary line follows its annotations, and the grand total ends the
//! output.
//!
//! Nothing from outside can forge a command: file names and messages are
//! encoded inside annotations, and a summary line (which names the file and
//! may name the WCET file) is kept a plain log line, see [`plain`].

use std::fmt::Write as _;

use genom_model::diagnostic::{Counts, Diagnostic, Severity};
use genom_model::span::SourceMap;

use crate::json::{location, region};
use crate::{FileReport, escaped, escaped_keeping_lines};

/// Renders the annotations of every report and, given `summaries` (one per
/// report), each file's summary line and the grand total.
pub fn render(reports: &[FileReport<'_>], summaries: Option<&[String]>) -> String {
    let mut out = String::new();
    let mut total = Counts::default();
    for (i, report) in reports.iter().enumerate() {
        for d in report.diagnostics {
            out.push_str(&annotation(report.sources, d));
            out.push('\n');
        }
        if let Some(line) = summaries.and_then(|s| s.get(i)) {
            out.push_str(&plain(line));
            out.push('\n');
        }
        total.merge(report.counts());
    }
    if summaries.is_some() {
        out.push_str(&crate::human::render_total(total, reports.len()));
        out.push('\n');
    }
    out
}

/// The workflow command of one diagnostic.
pub fn annotation(sources: &SourceMap, d: &Diagnostic) -> String {
    let command = match d.severity {
        Severity::Error => "error",
        Severity::Warning => "warning",
        Severity::Advice => "notice",
    };
    let (start, end) = region(sources, d.span());
    let mut props = format!(
        "file={},line={},col={}",
        property(&start.file),
        start.line,
        start.column
    );
    if let Some((line, column)) = end {
        let _ = write!(props, ",endLine={line},endColumn={column}");
    }
    let _ = write!(props, ",title={}", property(d.code.as_str()));
    let text = message(sources, d);
    format!(
        "::{command} {props}::{}",
        data(&escaped_keeping_lines(&text))
    )
}

/// The text of the annotation: the message, the help, the trace's steps.
fn message(sources: &SourceMap, d: &Diagnostic) -> String {
    let mut text = d.message.clone();
    if let Some(help) = &d.help {
        let _ = write!(text, "\nhelp: {help}");
    }
    if let Some(trace) = &d.trace {
        text.push_str("\ntrace:");
        for (i, step) in trace.steps.iter().enumerate() {
            let at = step.span.map(|s| location(sources, s));
            let at = at.map_or(String::new(), |l| format!(" ({}:{})", l.file, l.line));
            let _ = write!(text, "\n  {}. {}{at}", i + 1, step.text);
        }
    }
    text
}

/// A line that is not a workflow command and cannot become one, whatever
/// names it holds: control characters escaped as the human format shows
/// them (so no line end splits it), and the two ways the runner recognises
/// a command defused: `::` at the start (after spaces) and `##[` anywhere
/// (the older syntax) get their `:` or `[` encoded (`%3A`, `%5B`).
pub fn plain(line: &str) -> String {
    let line = escaped(line).replace("##[", "##%5B");
    let body = line.trim_start();
    if body.starts_with("::") {
        let indent = &line[..line.len() - body.len()];
        return format!("{indent}%3A{}", &body[1..]);
    }
    line
}

/// Encodes a command's data (the message) as the runner decodes it.
fn data(text: &str) -> String {
    text.replace('%', "%25")
        .replace('\r', "%0D")
        .replace('\n', "%0A")
}

/// Encodes a property value (file, title): data encoding plus `:` and `,`.
fn property(text: &str) -> String {
    data(text).replace(':', "%3A").replace(',', "%2C")
}

#[cfg(test)]
mod tests {
    use super::*;
    use genom_model::Code;
    use genom_model::span::Span;

    fn sources() -> SourceMap {
        let mut s = SourceMap::new();
        s.add("a,b.gen", "component c {\n  x: y;\n}\n".to_owned());
        s
    }

    #[test]
    fn an_annotation_points_at_the_primary_label_and_encodes_its_text() {
        let s = sources();
        let d = Diagnostic::new(
            Code::UnknownData,
            "unknown `y`: 100%",
            Span::new(19, 20),
            "here",
        )
        .with_help("declare it\nfirst");
        assert_eq!(
            annotation(&s, &d),
            "::error file=a%2Cb.gen,line=2,col=6,endLine=2,endColumn=7,title=unknown-data::\
             unknown `y`: 100%25%0Ahelp: declare it%0Afirst"
        );
    }

    #[test]
    fn advice_is_a_notice_and_the_total_ends_the_output() {
        let s = sources();
        let d = Diagnostic::new(Code::UnknownData, "m", Span::new(0, 9), "l");
        let advice = Diagnostic {
            severity: Severity::Advice,
            ..d.clone()
        };
        let diagnostics = [d, advice];
        let report = FileReport {
            path: "a.gen",
            sources: &s,
            diagnostics: &diagnostics,
            statistics: None,
            dialect: genom_model::Dialect::Gen,
            pragmas: &[],
            response_times: &[],
        };
        let summary = ["a.gen: 1 error, 0 warnings, 1 advice".to_owned()];
        let out = render(&[report], Some(&summary));
        let lines: Vec<&str> = out.lines().collect();
        assert!(
            lines[0].starts_with("::error file=a%2Cb.gen,line=1,col=1,"),
            "{out}"
        );
        assert!(lines[1].starts_with("::notice "), "{out}");
        assert_eq!(lines[2], "a.gen: 1 error, 0 warnings, 1 advice");
        assert_eq!(lines[3], "Found 1 error, 0 warnings, 1 advice in 1 file.");
    }

    #[test]
    fn a_summary_line_cannot_become_a_workflow_command() {
        assert_eq!(plain("a.gen: 0 errors"), "a.gen: 0 errors");
        let forged = "a\n::error file=evil.gen,line=1::x\n.gen: 0 errors";
        assert_eq!(
            plain(forged),
            "a\\n::error file=evil.gen,line=1::x\\n.gen: 0 errors"
        );
        assert_eq!(
            plain("  ::error file=e.gen::x.gen: 0 errors"),
            "  %3A:error file=e.gen::x.gen: 0 errors"
        );
        assert_eq!(
            plain("w##[error]x.gen: 1 error"),
            "w##%5Berror]x.gen: 1 error"
        );
        assert_eq!(plain("\r::warning::x"), "\\r::warning::x");
    }
}
