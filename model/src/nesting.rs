//! The nesting guard both front-ends run before their recursive-descent
//! parsers: finds the first bracket nested deeper than a limit, in one pass
//! over the text, so that no parser, builder, lowering or renderer ever
//! recurses deeper than the limit (the stack stays small, whatever
//! `--max-memory` says, and a 100 000-level input costs a linear scan).
//!
//! Comments, strings and character literals are skipped. A `<` opens a
//! level only after `sequence`, `string` or `fixed` (a template-like type),
//! and a `>` closes only such a level, so shift and comparison operators
//! (`1 >> 2`, `a > b`) neither open nor hide levels. A run of `-` (unary
//! minus, `- - - 1`) nests like brackets.

use crate::{Code, Diagnostic, Span};

/// `syntax`: brackets nested beyond the supported depth.
pub fn too_deep(span: Span, limit: usize) -> Diagnostic {
    Diagnostic::new(
        Code::Syntax,
        format!("nesting deeper than {limit} levels"),
        span,
        "this bracket is nested too deeply",
    )
    .with_help("no component needs this much nesting; is a closing bracket missing?")
}

/// What opened a level.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Open {
    /// `{`, `(` or `[`.
    Bracket,
    /// `<` after a template-like type keyword.
    Angle,
}

/// The byte offset of the first bracket (or `-` of a run) nested deeper
/// than `limit` in `text`, if any.
pub fn excessive_nesting(text: &str, limit: usize) -> Option<usize> {
    let bytes = text.as_bytes();
    let mut open: Vec<Open> = Vec::new();
    // The previous token was `sequence`, `string` or `fixed`.
    let mut after_type_keyword = false;
    // Consecutive `-` tokens.
    let mut minus_run = 0usize;
    let mut i = 0;
    while i < bytes.len() {
        if let Some(after) = skip_trivia(text, i) {
            if matches!(bytes[i], b'"' | b'\'') {
                after_type_keyword = false;
                minus_run = 0;
            }
            i = after;
            continue;
        }
        match bytes[i] {
            b' ' | b'\t' | b'\r' | b'\n' => {
                i += 1;
                continue;
            }
            b if b.is_ascii_alphabetic() || b == b'_' => {
                let len = bytes[i..]
                    .iter()
                    .take_while(|b| b.is_ascii_alphanumeric() || **b == b'_')
                    .count();
                after_type_keyword = matches!(&text[i..i + len], "sequence" | "string" | "fixed");
                minus_run = 0;
                i += len;
                continue;
            }
            b'-' => {
                minus_run += 1;
                after_type_keyword = false;
                if open.len() + minus_run > limit {
                    return Some(i);
                }
                i += 1;
                continue;
            }
            b'{' | b'(' | b'[' => open.push(Open::Bracket),
            b'<' if after_type_keyword => open.push(Open::Angle),
            b'}' | b')' | b']' => {
                // Closes the innermost bracket (and any `<` left open in it).
                while open.pop() == Some(Open::Angle) {}
            }
            b'>' if open.last() == Some(&Open::Angle) => {
                open.pop();
            }
            _ => {}
        }
        after_type_keyword = false;
        minus_run = 0;
        if open.len() > limit {
            return Some(i);
        }
        i += 1;
    }
    None
}

/// When a comment, string or character literal starts at byte `i` of
/// `text`: the offset just after it (a line comment ends before its line
/// end; an unterminated one ends the text). Both front-ends' scans skip
/// what this skips.
pub fn skip_trivia(text: &str, i: usize) -> Option<usize> {
    let bytes = text.as_bytes();
    match (bytes.get(i)?, bytes.get(i + 1)) {
        (b'/', Some(b'*')) => Some(
            text.get(i + 2..)?
                .find("*/")
                .map_or(bytes.len(), |j| i + 2 + j + 2),
        ),
        (b'/', Some(b'/')) => Some(text.get(i..)?.find('\n').map_or(bytes.len(), |j| i + j)),
        (&quote @ (b'"' | b'\''), _) => Some(skip_quoted(bytes, i + 1, quote)),
        _ => None,
    }
}

/// The offset just past the literal opened before `i` by `quote` (at the
/// closing quote, a line end, or the end of the text).
fn skip_quoted(bytes: &[u8], mut i: usize, quote: u8) -> usize {
    while i < bytes.len() {
        match bytes[i] {
            b'\\' => i += 2,
            b'\n' => return i + 1,
            b if b == quote => return i + 1,
            _ => i += 1,
        }
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_first_bracket_past_the_limit() {
        let deep = "{".repeat(5);
        assert_eq!(excessive_nesting(&deep, 4), Some(4));
        assert_eq!(excessive_nesting(&deep, 5), None);
        assert_eq!(excessive_nesting("({[(", 3), Some(3));
    }

    #[test]
    fn ignores_comments_strings_and_characters() {
        let deep = "{".repeat(10);
        let hidden = format!("/* {deep} */ \"{deep}\" '{{' // {deep}\n x");
        assert_eq!(excessive_nesting(&hidden, 2), None);
    }

    #[test]
    fn angles_nest_only_after_a_template_keyword() {
        assert_eq!(excessive_nesting("a < b < c < d", 1), None);
        assert_eq!(excessive_nesting("sequence<sequence<long> >", 1), Some(17));
        assert_eq!(excessive_nesting("sequence<sequence<long>>", 2), None);
    }

    #[test]
    fn shifts_cannot_hide_levels() {
        // Each `>>` would have closed two levels with a plain counter.
        let text = format!("{}1 >> 1 >> 1 >> 1{}", "(".repeat(3), "(".repeat(3));
        assert_eq!(
            excessive_nesting(&text, 5),
            Some(text.rfind('(').unwrap_or(0))
        );
        assert_eq!(excessive_nesting("((1)) > ((1))", 2), None);
    }

    #[test]
    fn the_dialect_shapes() {
        let limit = 64;
        let seq = "sequence<".repeat(limit + 1);
        assert!(excessive_nesting(&seq, limit).is_some());
        assert_eq!(excessive_nesting("credentials: a < b < c < d;", 1), None);
        let commented = "sequence /* c */ <".repeat(limit + 1);
        assert!(excessive_nesting(&commented, limit).is_some());
        let minus = format!("const long N = {}1;", "- ".repeat(limit + 1));
        assert!(excessive_nesting(&minus, limit).is_some());
        let text = "thread t { max-time: -1s; } const long x = 1 - -2;";
        assert_eq!(excessive_nesting(text, 2), None);
        assert_eq!(excessive_nesting("typedef mystring<", 0), None);
    }

    #[test]
    fn a_run_of_minus_signs_nests() {
        assert_eq!(excessive_nesting("- - - 1", 2), Some(4));
        assert_eq!(excessive_nesting("a - b - c - d", 1), None);
    }

    #[test]
    fn a_closing_bracket_closes_open_angles_inside_it() {
        // A stray `<` inside parentheses does not stay open after them.
        assert_eq!(excessive_nesting("(sequence<) (sequence<)", 2), None);
    }
}
