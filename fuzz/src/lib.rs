//! Support shared by the fuzz targets: the in-memory files an input may
//! include, and the invariants every result must keep (each label inside a
//! loaded file, both renderers total).

use genom_model::{Diagnostic, SourceMap, Span, Statistics};
use gen_frontend::MemoryLoader;
use genom_render::{FileReport, human, json};

/// The path the fuzzed text is checked as.
pub const PATH: &str = "fuzz.gen";

/// Files an input may `include` (their names are in `gen.dict`): a valid
/// IDL file, a file including itself, a file with a syntax error.
pub fn loader() -> MemoryLoader {
    MemoryLoader::new()
        .with(
            "types.idl",
            "typedef struct pos { double x; double y; } pos;\nconst long N = 3;\n",
        )
        .with("self.gen", "include \"self.gen\"\n")
        .with("bad.idl", "typedef struct { double x; \n")
}

/// Whether `span` lies within one loaded file (end included).
pub fn inside_a_file(sources: &SourceMap, span: Span) -> bool {
    sources.files().any(|(id, f)| {
        let whole = sources.file_span(id);
        f.base <= span.start && span.start <= span.end && span.end <= whole.end
    })
}

/// Panics when a label of a diagnostic points outside every file.
pub fn assert_spans(sources: &SourceMap, diagnostics: &[Diagnostic]) {
    for d in diagnostics {
        for label in &d.labels {
            assert!(
                inside_a_file(sources, label.span),
                "{:?} label {:?} points outside every file: {:?}",
                d.code,
                label.span,
                d.message
            );
        }
    }
}

/// Renders the report in both formats (they must not panic) and returns
/// the total length, so that the work is not optimised away.
pub fn render(
    sources: &SourceMap,
    diagnostics: &[Diagnostic],
    statistics: Option<&Statistics>,
) -> usize {
    let report = FileReport {
        path: PATH,
        sources,
        diagnostics,
        statistics,
        dialect: genom_model::Dialect::Gen,
        pragmas: &[],
        response_times: &[],
    };
    let text = human::render_diagnostics(&report, human::HumanOptions::default());
    let summary = human::render_summary(PATH, report.counts());
    let doc = json::render(&[report]);
    text.len() + summary.len() + doc.len()
}
