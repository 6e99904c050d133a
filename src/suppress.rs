//! What a project silences or promotes: the levels of `genom-check.toml`
//! (`allow`, `warn`, `deny` per code) and inline allows in the source, a
//! comment `// genom-check: allow(missing-wcet, unpaused-loop)` (or
//! `/* ... */`) on the line before an item or at the end of its first
//! line. An inline allow covers that item: from its first line to its
//! closing brace (or its `;` when it has no braces), so a diagnostic whose
//! primary label falls inside it is not reported.
//!
//! `incomplete` cannot be allowed: it says that a verdict is missing, and
//! hiding it would let a check pass unverified.

use std::collections::BTreeMap;

use genom_check::CheckResult;
use genom_model::span::SourceFile;
use genom_model::{Code, Severity};

use crate::config::{Level, allowable, code_named};

/// The marker of an inline allow.
const MARKER: &str = "genom-check: allow(";

/// An inline allow: the codes and the global byte range it covers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Allow {
    codes: Vec<Code>,
    start: u32,
    end: u32,
}

/// Applies `levels` and the inline allows of the result's sources to its
/// diagnostics. Err: the problems of inline allows (`path:line: message`).
pub fn apply(result: &mut CheckResult, levels: &BTreeMap<Code, Level>) -> Result<(), String> {
    let mut allows = Vec::new();
    for (_, file) in result.sources.files() {
        allows.extend(inline_allows(file)?);
    }
    result.diagnostics.retain_mut(|d| {
        let at = d.span().start;
        let inline = allows
            .iter()
            .any(|a| a.codes.contains(&d.code) && (a.start..a.end).contains(&at));
        match levels.get(&d.code) {
            _ if inline => false,
            Some(Level::Allow) => false,
            Some(Level::Warn) => {
                d.severity = Severity::Warning;
                true
            }
            Some(Level::Deny) => {
                d.severity = Severity::Error;
                true
            }
            None => true,
        }
    });
    Ok(())
}

/// The inline allows of one source file.
pub fn inline_allows(file: &SourceFile) -> Result<Vec<Allow>, String> {
    let text = file.text.as_str();
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(found) = text[from..].find(MARKER) {
        let at = from + found;
        from = at + MARKER.len();
        let line_no = text[..at].matches('\n').count() + 1;
        let where_ = format!("{}:{line_no}", file.path.display());
        if !in_comment(text, at) {
            continue;
        }
        let close = text[from..]
            .find(')')
            .ok_or_else(|| format!("{where_}: `{MARKER}` has no closing `)`"))?;
        let mut codes = Vec::new();
        for name in text[from..from + close].split(',').map(str::trim) {
            let code = code_named(name)
                .ok_or_else(|| format!("{where_}: unknown code `{name}` in `{MARKER}...)`"))?;
            if !allowable(code) {
                return Err(format!(
                    "{where_}: `{name}` cannot be allowed (a verdict is missing)"
                ));
            }
            codes.push(code);
        }
        let Some((start, end)) = item_after(text, at) else {
            return Err(format!("{where_}: no item follows this allow"));
        };
        out.push(Allow {
            codes,
            start: file.base + to_u32(start),
            end: file.base + to_u32(end),
        });
    }
    Ok(out)
}

fn to_u32(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

/// Whether byte `at` is inside a `//` or `/* */` comment that starts on its
/// line.
fn in_comment(text: &str, at: usize) -> bool {
    let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    let before = &text[line_start..at];
    before.contains("//") || before.contains("/*")
}

/// The item an allow at `at` covers: the code before the comment on its
/// line if any, else the next line with code; up to the brace closing its
/// first `{`, or its first `;` when that comes before any brace.
fn item_after(text: &str, at: usize) -> Option<(usize, usize)> {
    let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    let comment = text[line_start..at]
        .find("//")
        .into_iter()
        .chain(text[line_start..at].find("/*"))
        .min()
        .unwrap_or(at - line_start);
    let start = if text[line_start..line_start + comment].trim().is_empty() {
        next_code_line(text, at)?
    } else {
        line_start
    };
    Some((start, item_end(text, start)?))
}

/// The start of the first line after `at`'s line that holds code.
fn next_code_line(text: &str, at: usize) -> Option<usize> {
    let mut pos = text[at..].find('\n')? + at + 1;
    loop {
        let end = text[pos..].find('\n').map_or(text.len(), |i| pos + i);
        let line = text[pos..end].trim();
        if !(line.is_empty()
            || line.starts_with("//")
            || line.starts_with("/*")
            || line.starts_with('*'))
        {
            return Some(pos);
        }
        if end >= text.len() {
            return None;
        }
        pos = end + 1;
    }
}

/// Where the item starting at `start` ends (one past its last byte),
/// skipping comments and strings.
fn item_end(text: &str, start: usize) -> Option<usize> {
    let b = text.as_bytes();
    let (mut i, mut depth, mut braced) = (start, 0usize, false);
    while i < b.len() {
        match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => {
                i = text[i..].find('\n').map_or(b.len(), |k| i + k);
                continue;
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                i = text[i + 2..].find("*/").map_or(b.len(), |k| i + 2 + k + 2);
                continue;
            }
            b'"' => {
                i = text[i + 1..].find('"').map_or(b.len(), |k| i + 1 + k + 1);
                continue;
            }
            b'{' => {
                depth += 1;
                braced = true;
            }
            b'}' => {
                depth = depth.saturating_sub(1);
                if depth == 0 && braced {
                    return Some(i + 1);
                }
            }
            b';' if depth == 0 && !braced => return Some(i + 1),
            _ => {}
        }
        i += 1;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spans(text: &str) -> Vec<(String, Vec<&'static str>)> {
        let mut map = genom_model::SourceMap::new();
        let id = map.add("x.gen", text.to_owned());
        let file = map.file(id).expect("the file");
        inline_allows(file)
            .expect("valid allows")
            .into_iter()
            .map(|a| {
                let s = text[a.start as usize..a.end as usize].to_owned();
                (s, a.codes.iter().map(|c| c.as_str()).collect())
            })
            .collect()
    }

    #[test]
    fn an_allow_before_an_item_covers_it_to_its_closing_brace() {
        let text =
            "// genom-check: allow(missing-wcet)\nservice S {\n  a { b; }\n}\nservice T { }\n";
        assert_eq!(
            spans(text),
            vec![(
                "service S {\n  a { b; }\n}".to_owned(),
                vec!["missing-wcet"]
            )]
        );
    }

    #[test]
    fn an_allow_at_the_end_of_a_line_covers_the_item_of_that_line() {
        let text = "  codel<start> f() yield ether; /* genom-check: allow(unpaused-loop, livelock) */\n  codel<x> g();\n";
        assert_eq!(
            spans(text),
            vec![(
                "  codel<start> f() yield ether;".to_owned(),
                vec!["unpaused-loop", "livelock"]
            )]
        );
    }

    #[test]
    fn braces_in_comments_and_strings_do_not_count() {
        let text = "// genom-check: allow(no-termination)\nservice S { // }\n doc \"}\"; }\nrest";
        assert_eq!(spans(text)[0].0, "service S { // }\n doc \"}\"; }");
    }

    #[test]
    fn unknown_codes_and_incomplete_are_refused() {
        let mut map = genom_model::SourceMap::new();
        let a = map.add(
            "a.gen",
            "// genom-check: allow(missing-wcett)\nx;".to_owned(),
        );
        let b = map.add("b.gen", "// genom-check: allow(incomplete)\nx;".to_owned());
        let err = inline_allows(map.file(a).expect("a")).expect_err("unknown");
        assert!(
            err.starts_with("a.gen:1: unknown code `missing-wcett`"),
            "{err}"
        );
        let err = inline_allows(map.file(b).expect("b")).expect_err("incomplete");
        assert!(err.contains("cannot be allowed"), "{err}");
    }

    #[test]
    fn the_marker_outside_a_comment_is_ignored() {
        assert!(spans("doc \"genom-check: allow(x)\";\n").is_empty());
    }
}
