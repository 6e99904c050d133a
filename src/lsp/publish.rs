//! genom-check's diagnostics as protocol diagnostics, grouped by the file
//! they are located in: the checked document, or one of its includes.

use std::collections::BTreeMap;
use std::path::Path;

use genom_check::CheckResult;
use genom_model::{Diagnostic, Severity, SourceMap, Span};
use lsp_types::{
    CodeDescription, DiagnosticRelatedInformation, DiagnosticSeverity, Location, NumberOrString,
    Range, Uri,
};

use super::position;

/// What the server needs to place diagnostics.
pub struct Target<'a> {
    /// The checked document's URI: diagnostics without a location go there.
    pub document: &'a Uri,
    /// The path the document was checked under.
    pub path: &'a Path,
    /// The documentation URI of a code: this template with `{code}`
    /// replaced (from the client's `initializationOptions.codeUrl`).
    pub code_url: Option<&'a str>,
}

/// The diagnostics of `result` by file URI (as a string, for a stable
/// order), the document's always present (possibly empty).
pub fn by_file(
    result: &CheckResult,
    target: &Target<'_>,
) -> BTreeMap<String, (Uri, Vec<lsp_types::Diagnostic>)> {
    let mut out = BTreeMap::new();
    out.insert(
        target.document.as_str().to_owned(),
        (target.document.clone(), Vec::new()),
    );
    for d in &result.diagnostics {
        let (uri, range) = d
            .labels
            .first()
            .and_then(|l| target.place(&result.sources, l.span))
            .unwrap_or_else(|| (target.document.clone(), Range::default()));
        let converted = convert(d, &result.sources, range, target);
        out.entry(uri.as_str().to_owned())
            .or_insert_with(|| (uri, Vec::new()))
            .1
            .push(converted);
    }
    if let Some(note) = assumptions(result, target) {
        out.entry(target.document.as_str().to_owned())
            .or_insert_with(|| (target.document.clone(), Vec::new()))
            .1
            .push(note);
    }
    out
}

/// What the verdicts rest on (a WCET file, an instance bound), as an
/// information at the component's name.
fn assumptions(result: &CheckResult, target: &Target<'_>) -> Option<lsp_types::Diagnostic> {
    let assumed = result.statistics.as_ref()?.assumed()?;
    let c = result.component.as_ref()?;
    let (_, range) = target.place(&result.sources, c.name.span)?;
    Some(lsp_types::Diagnostic {
        range,
        severity: Some(DiagnosticSeverity::INFORMATION),
        source: Some("genom-check".to_owned()),
        message: format!("the verdicts assume {assumed}"),
        ..lsp_types::Diagnostic::default()
    })
}

impl Target<'_> {
    /// The file URI and range of a global span: the document's own URI
    /// for its text, a `file://` URI for an include.
    pub fn place(&self, sources: &SourceMap, span: Span) -> Option<(Uri, Range)> {
        let located = sources.locate(span)?;
        let file = sources.file(located.file)?;
        let uri = if file.path == self.path {
            self.document.clone()
        } else {
            position::uri_of(&file.path)?
        };
        let range = position::range(&file.text, located.offset as usize, located.length as usize);
        Some((uri, range))
    }
}

fn convert(
    d: &Diagnostic,
    sources: &SourceMap,
    range: Range,
    target: &Target<'_>,
) -> lsp_types::Diagnostic {
    let code = d.code.as_str();
    let code_description = target
        .code_url
        .and_then(|t| t.replace("{code}", code).parse::<Uri>().ok())
        .map(|href| CodeDescription { href });
    lsp_types::Diagnostic {
        range,
        severity: Some(severity(d.severity)),
        code: Some(NumberOrString::String(code.to_owned())),
        code_description,
        source: Some("genom-check".to_owned()),
        message: message(d),
        related_information: Some(related(d, sources, target)).filter(|r| !r.is_empty()),
        tags: None,
        data: None,
    }
}

fn severity(s: Severity) -> DiagnosticSeverity {
    match s {
        Severity::Error => DiagnosticSeverity::ERROR,
        Severity::Warning => DiagnosticSeverity::WARNING,
        Severity::Advice => DiagnosticSeverity::INFORMATION,
    }
}

/// The message, its primary label when it says more, and its help.
fn message(d: &Diagnostic) -> String {
    let mut text = d.message.clone();
    if let Some(label) = d.labels.first() {
        if !label.message.is_empty() && label.message != d.message {
            text.push('\n');
            text.push_str(&label.message);
        }
    }
    if let Some(help) = &d.help {
        text.push_str("\nhelp: ");
        text.push_str(help);
    }
    text
}

/// The secondary labels, then the trace steps that have a place.
fn related(
    d: &Diagnostic,
    sources: &SourceMap,
    target: &Target<'_>,
) -> Vec<DiagnosticRelatedInformation> {
    let labels = d.labels.iter().skip(1).map(|l| {
        let text = if l.message.is_empty() {
            "related".to_owned()
        } else {
            l.message.clone()
        };
        (l.span, text)
    });
    let steps = d.trace.iter().flat_map(|t| {
        t.steps.iter().enumerate().filter_map(|(i, s)| {
            let span = s.span?;
            Some((span, format!("trace step {}: {}", i + 1, s.text)))
        })
    });
    labels
        .chain(steps)
        .filter_map(|(span, message)| {
            let (uri, range) = target.place(sources, span)?;
            Some(DiagnosticRelatedInformation {
                location: Location::new(uri, range),
                message,
            })
        })
        .collect()
}
