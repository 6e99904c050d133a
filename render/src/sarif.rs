//! SARIF 2.1.0 output (`--format sarif`): one run of the `genom-check`
//! tool over every checked file, for code-scanning services (GitHub code
//! scanning uploads it). Each diagnostic is a `result` with its rule (the
//! diagnostic's code, described by its `explain` text), level (`error`,
//! `warning`, `note` for advice), primary location, secondary labels as
//! `relatedLocations`, and its counterexample or witness trace as a
//! `codeFlow` (one `threadFlow`, a location per step). Columns count
//! Unicode code points, as the human and JSON reports do. A file's `uri` is
//! its path as a URI reference: bytes outside RFC 3986's path characters
//! (spaces, `%`, `#`, `?`, `:`, control characters, non-ASCII) are
//! percent-encoded, so no name breaks or redirects the link.

use std::collections::BTreeMap;

use percent_encoding::{AsciiSet, CONTROLS, utf8_percent_encode};
use serde_json::{Value, json};

use genom_model::diagnostic::{Code, Diagnostic, Severity};
use genom_model::span::{SourceMap, Span};
use genom_model::trace::Trace;

use crate::FileReport;
use crate::json::region;

/// The SARIF version written.
pub const SARIF_VERSION: &str = "2.1.0";

/// The schema the document declares.
pub const SARIF_SCHEMA: &str = "https://json.schemastore.org/sarif-2.1.0.json";

/// Renders every report as one SARIF log; `explain` gives the long text of
/// a code (the rules' help), `version` the tool's version.
pub fn render(
    reports: &[FileReport<'_>],
    explain: &dyn Fn(Code) -> String,
    version: &str,
) -> String {
    let mut codes: BTreeMap<&'static str, Code> = BTreeMap::new();
    for d in reports.iter().flat_map(|r| r.diagnostics) {
        codes.insert(d.code.as_str(), d.code);
    }
    let index: BTreeMap<&str, usize> = codes.keys().enumerate().map(|(i, c)| (*c, i)).collect();
    let rules: Vec<Value> = codes.values().map(|&c| rule(c, &explain(c))).collect();
    let results: Vec<Value> = reports
        .iter()
        .flat_map(|r| r.diagnostics.iter().map(move |d| (r.sources, d)))
        .map(|(sources, d)| result(sources, d, index.get(d.code.as_str()).copied()))
        .collect();
    let mut run = json!({
        "tool": { "driver": {
            "name": "genom-check",
            "version": version,
            "rules": rules,
        }},
        "columnKind": "unicodeCodePoints",
        "results": results,
    });
    let notes: Vec<Value> = reports.iter().flat_map(assumption_notes).collect();
    if !notes.is_empty() {
        run["invocations"] = json!([{
            "executionSuccessful": true,
            "toolExecutionNotifications": notes,
        }]);
    }
    let log = json!({
        "$schema": SARIF_SCHEMA,
        "version": SARIF_VERSION,
        "runs": [run],
    });
    serde_json::to_string_pretty(&log).unwrap_or_default() + "\n"
}

/// One `note` notification per assumption the file's verdicts rest on
/// (a WCET file, an instance bound), located at the file.
fn assumption_notes(r: &FileReport<'_>) -> Vec<Value> {
    let all = r.statistics.map_or(&[][..], |s| &s.assumptions[..]);
    all.iter()
        .map(|a| {
            json!({
                "level": "note",
                "descriptor": { "id": format!("assumption/{}", a.kind) },
                "message": { "text": format!("{}: the verdicts assume {}", r.path, a.text) },
                "locations": [{ "physicalLocation": { "artifactLocation": { "uri": uri(r.path) } } }],
            })
        })
        .collect()
}

fn level(severity: Severity) -> &'static str {
    match severity {
        Severity::Error => "error",
        Severity::Warning => "warning",
        Severity::Advice => "note",
    }
}

fn rule(code: Code, help: &str) -> Value {
    json!({
        "id": code.as_str(),
        "shortDescription": { "text": code.meaning() },
        "help": { "text": help, "markdown": help },
        "defaultConfiguration": { "level": level(code.severity()) },
    })
}

fn result(sources: &SourceMap, d: &Diagnostic, rule_index: Option<usize>) -> Value {
    let mut text = d.message.clone();
    if let Some(help) = &d.help {
        text.push_str("\nhelp: ");
        text.push_str(help);
    }
    let mut r = json!({
        "ruleId": d.code.as_str(),
        "level": level(d.severity),
        "message": { "text": text },
        "locations": [ { "physicalLocation": physical(sources, d.span()) } ],
    });
    if let Some(i) = rule_index {
        r["ruleIndex"] = json!(i);
    }
    let related: Vec<Value> = d
        .labels
        .iter()
        .skip(1)
        .enumerate()
        .map(|(i, l)| {
            json!({
                "id": i,
                "physicalLocation": physical(sources, l.span),
                "message": { "text": if l.message.is_empty() { d.message.as_str() } else { l.message.as_str() } },
            })
        })
        .collect();
    if !related.is_empty() {
        r["relatedLocations"] = Value::Array(related);
    }
    if let Some(trace) = &d.trace {
        r["codeFlows"] = json!([code_flow(sources, trace)]);
    }
    r
}

fn code_flow(sources: &SourceMap, trace: &Trace) -> Value {
    let steps: Vec<Value> = trace
        .steps
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let mut location = json!({ "message": { "text": s.text } });
            if let Some(span) = s.span {
                location["physicalLocation"] = physical(sources, span);
            }
            json!({ "location": location, "executionOrder": i + 1 })
        })
        .collect();
    json!({ "threadFlows": [ { "locations": steps } ] })
}

/// A file and the region of `span` in it (1-based lines and columns, the
/// end column exclusive).
fn physical(sources: &SourceMap, span: Span) -> Value {
    let (start, end) = region(sources, span);
    let mut region = json!({ "startLine": start.line, "startColumn": start.column });
    if let Some((line, column)) = end {
        region["endLine"] = json!(line);
        region["endColumn"] = json!(column);
    }
    json!({
        "artifactLocation": { "uri": uri(&start.file) },
        "region": region,
    })
}

/// The bytes of a path that a URI reference's path cannot hold as they are
/// (`:` too: in a relative reference's first segment it would read as a
/// scheme). Non-ASCII bytes are always encoded.
const NOT_IN_PATH: &AsciiSet = &CONTROLS
    .add(b' ')
    .add(b'"')
    .add(b'#')
    .add(b'%')
    .add(b':')
    .add(b'<')
    .add(b'>')
    .add(b'?')
    .add(b'[')
    .add(b'\\')
    .add(b']')
    .add(b'^')
    .add(b'`')
    .add(b'{')
    .add(b'|')
    .add(b'}');

/// A file's path as a URI reference.
fn uri(path: &str) -> String {
    utf8_percent_encode(path, NOT_IN_PATH).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_uri_encodes_what_a_path_reference_cannot_hold() {
        assert_eq!(uri("specs/pilot.gen"), "specs/pilot.gen");
        assert_eq!(
            uri("a b/100%#1?:\n\u{1b}é.gen"),
            "a%20b/100%25%231%3F%3A%0A%1B%C3%A9.gen"
        );
    }

    #[test]
    fn a_result_has_its_rule_level_region_and_related_locations() {
        let mut s = SourceMap::new();
        s.add("a.gen", "component c {\n  x: y;\n}\n".to_owned());
        let d = Diagnostic::new(Code::UnknownData, "unknown `y`", Span::new(19, 20), "here")
            .with_label(Span::new(0, 9), "in this component");
        let diagnostics = [d];
        let report = FileReport {
            path: "a.gen",
            sources: &s,
            diagnostics: &diagnostics,
            statistics: None,
            dialect: genom_model::Dialect::Gen,
            pragmas: &[],
            response_times: &[],
        };
        let text = render(&[report], &|c| format!("about {}", c.as_str()), "0.1.0");
        let log: Value = serde_json::from_str(&text).expect("JSON");
        assert_eq!(log["version"], "2.1.0");
        let run = &log["runs"][0];
        assert_eq!(run["tool"]["driver"]["rules"][0]["id"], "unknown-data");
        assert_eq!(
            run["tool"]["driver"]["rules"][0]["help"]["text"],
            "about unknown-data"
        );
        let r = &run["results"][0];
        assert_eq!(
            (r["ruleId"].as_str(), r["ruleIndex"].as_u64()),
            (Some("unknown-data"), Some(0))
        );
        assert_eq!(r["level"], "error");
        let region = &r["locations"][0]["physicalLocation"]["region"];
        assert_eq!(
            (region["startLine"].as_u64(), region["startColumn"].as_u64()),
            (Some(2), Some(6))
        );
        assert_eq!(
            (region["endLine"].as_u64(), region["endColumn"].as_u64()),
            (Some(2), Some(7))
        );
        assert_eq!(
            r["relatedLocations"][0]["message"]["text"],
            "in this component"
        );
        assert!(r.get("codeFlows").is_none());
    }
}
