//! The in-process preprocessor (no external `cpp`). It reads one file's
//! directive lines, keeps the file's byte offsets unchanged by blanking
//! directive lines and inactive conditional regions with spaces, and
//! reports what the loader must do: includes to follow (in order, with
//! their offset) and pragmas to record.
//!
//! Supported: `#include "…"`/`<…>`, `#define NAME [value]` (object-like
//! macros are expanded in the code when the value is not longer than the
//! name, padded with spaces so offsets stay exact), `#undef`, `#ifdef`, `#ifndef`,
//! `#if [!]defined(X)` / `#if 0|1`, `#elif`, `#else`, `#endif`,
//! `#pragma require|provides|masquerade`. Other directives (and `#line`
//! markers) are ignored with an advice.

use std::collections::{BTreeMap, BTreeSet};

use genom_model::{Diagnostic, Span};

use crate::diagnostics;

pub use genom_model::Pragma;

/// An `#include` line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Include {
    /// The path as written.
    pub path: String,
    /// `<…>` (else `"…"`).
    pub angled: bool,
    /// The directive line (global span).
    pub span: Span,
}

/// The result of scanning one file.
#[derive(Debug, Default)]
pub(crate) struct Scanned {
    /// The text with directive lines and inactive regions blanked.
    pub text: String,
    /// Includes in source order.
    pub includes: Vec<Include>,
    /// Pragmas in source order.
    pub pragmas: Vec<Pragma>,
    /// Advice and errors from directives.
    pub diagnostics: Vec<Diagnostic>,
}

/// A `#define`d macro.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Macro {
    /// Its replacement text (trimmed, may be empty).
    pub value: String,
    /// `#define F(x) ...` (never expanded).
    pub function_like: bool,
}

/// The macro table, shared across the files of one load.
pub(crate) type Macros = BTreeMap<String, Macro>;

/// One open conditional: is this branch active, has a branch been taken,
/// was the enclosing region active.
struct Cond {
    active: bool,
    taken: bool,
    parent: bool,
    span: Span,
}

/// Scans `text` (the file's global offset is `base`). `defines` is shared
/// across files, as a C preprocessor's macro table is; `on_include` is
/// called at each active `#include` in order, so that an included file's
/// guards are defined before the rest of this file is scanned.
pub(crate) fn scan(
    text: &str,
    base: u32,
    defines: &mut Macros,
    on_include: &mut dyn FnMut(&Include, &mut Macros),
) -> Scanned {
    let mut out = Scanned::default();
    let mut blanked = String::with_capacity(text.len());
    let mut stack: Vec<Cond> = Vec::new();
    let mut offset = 0usize;
    let mut in_comment = false;
    let mut warned = BTreeSet::new();
    for line in text.split_inclusive('\n') {
        let start = offset;
        offset += line.len();
        let span = Span::new(
            base + u32::try_from(start).unwrap_or(u32::MAX),
            base + u32::try_from(start + line.trim_end().len()).unwrap_or(u32::MAX),
        );
        let active = stack.last().is_none_or(|c| c.active);
        let trimmed = line.trim_start();
        let is_directive = !in_comment && trimmed.starts_with('#');
        let was_in_comment = in_comment;
        in_comment = update_comment_state(line, in_comment);
        if !is_directive {
            if active {
                blanked.push_str(&expand(
                    line,
                    was_in_comment,
                    defines,
                    span,
                    &mut warned,
                    &mut out.diagnostics,
                ));
            } else {
                blanked.push_str(&blank(line));
            }
            continue;
        }
        blanked.push_str(&blank(line));
        let body = strip_comments(trimmed[1..].trim());
        let (word, rest) = split_word(&body);
        match word {
            "ifdef" | "ifndef" => {
                let defined = defines.contains_key(first_word(rest));
                let cond = (word == "ifdef") == defined;
                stack.push(Cond {
                    active: active && cond,
                    taken: cond,
                    parent: active,
                    span,
                });
            }
            "if" => {
                let cond = eval_condition(rest, defines);
                stack.push(Cond {
                    active: active && cond,
                    taken: cond,
                    parent: active,
                    span,
                });
            }
            "elif" | "else" => match stack.last_mut() {
                Some(c) => {
                    let cond = word == "else" || eval_condition(rest, defines);
                    c.active = c.parent && !c.taken && cond;
                    c.taken |= cond;
                }
                None => out
                    .diagnostics
                    .push(diagnostics::unbalanced_directive(span, word)),
            },
            "endif" => {
                if stack.pop().is_none() {
                    out.diagnostics
                        .push(diagnostics::unbalanced_directive(span, word));
                }
            }
            _ if !active => {}
            "define" => {
                let name = first_word(rest).to_owned();
                let after = &rest.trim_start()[name.len()..];
                let function_like = after.starts_with('(');
                if function_like {
                    out.diagnostics.push(diagnostics::macro_not_expanded(
                        span,
                        &name,
                        "function-like macros are not expanded",
                    ));
                }
                let value = after.trim().to_owned();
                defines.insert(
                    name,
                    Macro {
                        value,
                        function_like,
                    },
                );
            }
            "undef" => {
                defines.remove(first_word(rest));
            }
            "include" => match parse_include(rest) {
                Some((path, angled)) => {
                    let inc = Include { path, angled, span };
                    on_include(&inc, defines);
                    out.includes.push(inc);
                }
                None => out.diagnostics.push(diagnostics::bad_include(span)),
            },
            "pragma" => {
                let (kind, args) = split_word(rest);
                let kind = match kind {
                    "requires" => "require",
                    "provide" => "provides",
                    k => k,
                };
                if !matches!(kind, "require" | "provides" | "masquerade") {
                    out.diagnostics.push(diagnostics::ignored_directive(
                        span,
                        &format!("pragma {kind}"),
                    ));
                }
                out.pragmas.push(Pragma {
                    kind: kind.to_owned(),
                    args: args.trim().to_owned(),
                    span,
                });
            }
            "" => {}
            other => out
                .diagnostics
                .push(diagnostics::ignored_directive(span, other)),
        }
    }
    for c in stack {
        out.diagnostics
            .push(diagnostics::unterminated_conditional(c.span));
    }
    out.text = blanked;
    out
}

/// Expands object-like macros in one line of code, keeping every offset:
/// a macro whose value is not longer than its name is replaced by the
/// value padded with spaces; a longer one is left alone with an advice
/// (once per macro and file). Comments and strings are left alone.
fn expand(
    line: &str,
    mut in_comment: bool,
    defines: &Macros,
    span: Span,
    warned: &mut BTreeSet<String>,
    diags: &mut Vec<Diagnostic>,
) -> String {
    if defines.is_empty() {
        return line.to_owned();
    }
    let bytes = line.as_bytes();
    let mut out = String::with_capacity(line.len());
    let mut i = 0;
    let mut in_string = false;
    while i < bytes.len() {
        let rest = &line[i..];
        if in_comment {
            if rest.starts_with("*/") {
                in_comment = false;
                out.push_str("*/");
                i += 2;
            } else {
                let c = rest.chars().next().unwrap_or(' ');
                out.push(c);
                i += c.len_utf8();
            }
            continue;
        }
        if in_string {
            let c = rest.chars().next().unwrap_or(' ');
            if c == '\\' {
                out.push_str(rest.get(..2).unwrap_or(rest));
                i += rest.get(..2).map_or(rest.len(), str::len);
                continue;
            }
            in_string = c != '"';
            out.push(c);
            i += c.len_utf8();
            continue;
        }
        if rest.starts_with("//") {
            out.push_str(rest);
            break;
        }
        if rest.starts_with("/*") {
            in_comment = true;
            out.push_str("/*");
            i += 2;
            continue;
        }
        let c = rest.chars().next().unwrap_or(' ');
        if c == '"' {
            in_string = true;
            out.push(c);
            i += 1;
            continue;
        }
        if c.is_ascii_alphabetic() || c == '_' {
            let len = rest
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(rest.len());
            let word = &rest[..len];
            match defines.get(word) {
                Some(m) if !m.function_like && m.value.len() <= len => {
                    out.push_str(&m.value);
                    out.push_str(&" ".repeat(len - m.value.len()));
                }
                Some(m) if !m.function_like => {
                    if warned.insert(word.to_owned()) {
                        diags.push(diagnostics::macro_not_expanded(
                            span,
                            word,
                            "its value is longer than its name, so expanding it would move positions",
                        ));
                    }
                    out.push_str(word);
                }
                _ => out.push_str(word),
            }
            i += len;
            continue;
        }
        out.push(c);
        i += c.len_utf8();
    }
    out
}

/// Spaces for every byte of `line`, keeping its line ending (offsets and
/// line numbers are unchanged).
fn blank(line: &str) -> String {
    line.chars()
        .map(|c| {
            if c == '\n' || c == '\r' {
                c.to_string()
            } else {
                " ".repeat(c.len_utf8())
            }
        })
        .collect()
}

/// Whether a `/* … */` comment is still open after `line`.
fn update_comment_state(line: &str, mut open: bool) -> bool {
    let bytes = line.as_bytes();
    let mut i = 0;
    while i + 1 < bytes.len() {
        match (open, bytes[i], bytes[i + 1]) {
            (false, b'/', b'/') => return false,
            (false, b'/', b'*') => {
                open = true;
                i += 1;
            }
            (true, b'*', b'/') => {
                open = false;
                i += 1;
            }
            _ => {}
        }
        i += 1;
    }
    open
}

/// Removes `/* … */` and `// …` comments from a directive's body.
fn strip_comments(s: &str) -> String {
    let mut out = String::new();
    let mut rest = s;
    loop {
        let block = rest.find("/*");
        let line = rest.find("//");
        match (block, line) {
            (Some(b), l) if l.is_none_or(|l| b < l) => {
                out.push_str(&rest[..b]);
                match rest[b + 2..].find("*/") {
                    Some(e) => rest = &rest[b + 2 + e + 2..],
                    None => break,
                }
            }
            (_, Some(l)) => {
                out.push_str(&rest[..l]);
                break;
            }
            _ => {
                out.push_str(rest);
                break;
            }
        }
    }
    out.trim().to_owned()
}

fn split_word(s: &str) -> (&str, &str) {
    let s = s.trim_start();
    let end = s
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    (&s[..end], &s[end..])
}

fn first_word(s: &str) -> &str {
    split_word(s).0
}

/// `"path"` or `<path>`.
fn parse_include(rest: &str) -> Option<(String, bool)> {
    let rest = rest.trim();
    let (close, angled) = match rest.chars().next()? {
        '"' => ('"', false),
        '<' => ('>', true),
        _ => return None,
    };
    let end = rest[1..].find(close)?;
    Some((rest[1..1 + end].to_owned(), angled))
}

/// Evaluates the simple `#if` conditions: `defined(X)`, `defined X`,
/// `!defined(X)`, integers, joined by `&&` / `||` (`&&` binding tighter).
/// Linear in the length of the condition, without recursion: a hostile
/// `#if !!!…!1` or a long chain of `||` costs one pass.
fn eval_condition(expr: &str, defines: &Macros) -> bool {
    expr.split("||")
        .any(|alt| alt.split("&&").all(|term| eval_term(term, defines)))
}

/// One term of a condition: `!` any number of times, then `defined X`,
/// an integer or a macro name, possibly in parentheses.
fn eval_term(term: &str, defines: &Macros) -> bool {
    let mut expr = term.trim();
    let mut negate = false;
    while let Some(rest) = expr.strip_prefix('!') {
        negate = !negate;
        expr = rest.trim_start();
    }
    let value = if let Some(e) = expr.strip_prefix("defined") {
        let name = e
            .trim()
            .trim_start_matches('(')
            .trim_end_matches(')')
            .trim();
        defines.contains_key(name)
    } else {
        let inner = expr.trim_start_matches('(').trim_end_matches(')').trim();
        match inner.parse::<i64>() {
            Ok(v) => v != 0,
            Err(_) => defines
                .get(inner)
                .is_some_and(|m| m.value.parse::<i64>().is_ok_and(|v| v != 0)),
        }
    };
    value != negate
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(text: &str) -> Scanned {
        let mut defines = Macros::new();
        scan(text, 0, &mut defines, &mut |_, _| {})
    }

    #[test]
    fn blanks_directives_and_keeps_offsets() {
        let s = run("#pragma require \"a\"\nstruct a { long b; };\n");
        assert_eq!(
            s.text.len(),
            "#pragma require \"a\"\nstruct a { long b; };\n".len()
        );
        assert!(s.text.starts_with("                   \nstruct"));
        assert_eq!(s.pragmas[0].kind, "require");
        assert_eq!(s.pragmas[0].args, "\"a\"");
    }

    #[test]
    fn guards_hide_the_second_inclusion() {
        let text = "#ifndef G\n#define G\nx\n#endif\n";
        let mut defines = Macros::new();
        let first = scan(text, 0, &mut defines, &mut |_, _| {});
        let second = scan(text, 0, &mut defines, &mut |_, _| {});
        assert!(first.text.contains('x'));
        assert!(!second.text.contains('x'));
    }

    #[test]
    fn else_elif_and_defined() {
        let s = run("#define A\n#if defined(B)\nb\n#elif defined A\na\n#else\nc\n#endif\n");
        assert!(s.text.contains('a') && !s.text.contains('b') && !s.text.contains('c'));
    }

    #[test]
    fn short_object_like_macros_are_expanded_in_place() {
        let s = run(
            "#define EMPTY\n#define N 4\n#define LONG_VALUE_X 1234567890123456\nlong EMPTY a[N]; /* N */ \"N\" LONG_VALUE_X\n",
        );
        let last = s.text.lines().last().unwrap_or("");
        assert_eq!(last, "long       a[4]; /* N */ \"N\" LONG_VALUE_X");
        assert_eq!(s.diagnostics.len(), 1, "{:?}", s.diagnostics);
    }

    #[test]
    fn unknown_directives_give_advice() {
        let s = run("#line 3\n#warning x\n");
        assert_eq!(s.diagnostics.len(), 2);
    }

    #[test]
    fn includes_in_order() {
        let s = run("#include \"a.idl\"\n#include <b/c.gen>\n");
        let paths: Vec<_> = s
            .includes
            .iter()
            .map(|i| (i.path.as_str(), i.angled))
            .collect();
        assert_eq!(paths, vec![("a.idl", false), ("b/c.gen", true)]);
    }
}
