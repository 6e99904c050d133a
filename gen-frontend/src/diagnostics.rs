//! The parser's diagnostics, one small named constructor each: `syntax`,
//! `include-not-found`, `include-cycle`, and the `invalid-attribute` cases
//! visible without context (unknown attribute names, literals that are not
//! whole nanoseconds or overflow).

pub use genom_model::diagnostic::closest;
use genom_model::limits::Limit;
use genom_model::{Code, Diagnostic, Span};

use crate::ast::Ident;
use crate::literal::LiteralError;

/// Every attribute name the language knows, for suggestions.
pub const ATTRIBUTE_NAMES: &[&str] = &[
    "category",
    "lang",
    "version",
    "doc",
    "credentials",
    "priority",
    "period",
    "stack",
    "start",
    "stop",
    "thread",
    "report",
    "max-time",
    "credential",
    "stops",
    "delays",
    "forbids",
    "input",
    "output",
    "import",
    "export",
    "exec",
    "update",
    "on-inter",
    "next",
];

/// `syntax`: the text does not parse.
pub fn syntax(span: Span, expected: &str, found: &str) -> Diagnostic {
    Diagnostic::new(
        Code::Syntax,
        format!("expected {expected}, found {found}"),
        span,
        format!("expected {expected}"),
    )
}

/// `syntax`: a block comment that never ends.
pub fn unterminated_comment(span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::Syntax,
        "unterminated block comment",
        span,
        "this `/*` has no closing `*/`",
    )
    .with_help("close the comment with `*/`; block comments do not nest")
}

/// `syntax`: recovery gave up after too many errors in one file.
pub fn too_many_errors(span: Span, count: usize) -> Diagnostic {
    Diagnostic::new(
        Code::Syntax,
        format!("too many syntax errors ({count}); the rest of the file was not parsed"),
        span,
        "parsing stopped here",
    )
}

/// `incomplete`: a limit passed while parsing; the rest was not read.
pub fn limit_reached(at: Span, limit: Limit) -> Diagnostic {
    genom_model::limits::parsing_stopped(at, limit)
}

/// `syntax`: a constant expression with more operators than the parser
/// builds (its tree would be as deep as it is long).
pub fn expression_too_long(span: Span, limit: usize) -> Diagnostic {
    Diagnostic::new(
        Code::Syntax,
        format!("constant expression with more than {limit} operators"),
        span,
        "expression too long",
    )
    .with_help("split it into several named constants")
}

/// `include-not-found`: an included file that cannot be read.
pub fn include_not_found(span: Span, path: &str, reason: &str) -> Diagnostic {
    Diagnostic::new(
        Code::IncludeNotFound,
        format!("cannot include `{path}`: {reason}"),
        span,
        "included here",
    )
    .with_help("include paths are resolved relative to the directory of the including file")
}

/// `include-cycle`: a file that includes itself through `chain`.
pub fn include_cycle(span: Span, path: &str, chain: &[String]) -> Diagnostic {
    Diagnostic::new(
        Code::IncludeCycle,
        format!("`{path}` includes itself: {}", chain.join(" -> ")),
        span,
        "this include closes the cycle",
    )
    .with_help("remove one of the includes; each file needs to be included only once")
}

/// `invalid-attribute`: an attribute name the language does not know.
pub fn unknown_attribute(name: &Ident) -> Diagnostic {
    let help = closest(&name.name, ATTRIBUTE_NAMES.iter().copied())
        .map(|c| format!("did you mean `{c}`?"));
    Diagnostic::new(
        Code::InvalidAttribute,
        format!("unknown attribute `{}`", name.name),
        name.span,
        "unknown attribute",
    )
    .with_optional_help(help)
}

/// `invalid-attribute`: a duration that is not whole nanoseconds or overflows.
pub fn bad_duration(span: Span, text: &str, error: LiteralError) -> Diagnostic {
    match error {
        LiteralError::NotWholeNs => Diagnostic::new(
            Code::InvalidAttribute,
            format!("duration `{text}` is not a whole number of nanoseconds"),
            span,
            "not a whole number of nanoseconds",
        )
        .with_help("durations are integers of nanoseconds internally; use a smaller unit or round"),
        LiteralError::Overflow | LiteralError::Malformed => literal_overflow(span, text),
    }
}

/// `invalid-attribute`: a duration longer than genom-check reads.
pub fn duration_too_long(span: Span, text: &str) -> Diagnostic {
    Diagnostic::new(
        Code::InvalidAttribute,
        genom_model::limits::duration_too_long(text),
        span,
        "duration out of range",
    )
    .with_help("periods, delays and max-times are at most a day: the timed engines' arithmetic must stay exact")
}

/// `invalid-attribute`: a literal too large to represent.
pub fn literal_overflow(span: Span, text: &str) -> Diagnostic {
    Diagnostic::new(
        Code::InvalidAttribute,
        format!("`{text}` is too large"),
        span,
        "value out of range",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggests_close_attribute_names() {
        assert_eq!(
            closest("perod", ATTRIBUTE_NAMES.iter().copied()),
            Some("period")
        );
        assert_eq!(
            closest("maxtime", ATTRIBUTE_NAMES.iter().copied()),
            Some("max-time")
        );
        assert_eq!(closest("zzzzzz", ATTRIBUTE_NAMES.iter().copied()), None);
    }
}

/// Long explanations of the parser's codes, for `genom-check explain`.
pub mod explain {
    /// `syntax`
    pub const SYNTAX: &str = r#"The file does not follow the grammar of the description language. The
message says what the parser expected at that position and what it found
instead; the label points at the exact token.

Why it matters: nothing else can be checked in a file that does not parse,
so semantic checks are skipped until every syntax error is fixed. Parsing
resumes at the next line that starts a top-level item, so one run reports
the syntax errors of every item.

Example:

```
thread motionTask { period: 10; }    // expected a duration such as `10ms`
component pilot { lang: C }          // expected `;`, found `}`
```

Inside braces every attribute ends with `;`; durations need a unit (`ns`,
`us`, `ms`, `s`, `min`)."#;

    /// `include-not-found`
    pub const INCLUDE_NOT_FOUND: &str = r#"An `include "file"` (or `#include`) names a file that cannot be read: it does
not exist, is a directory, or is not UTF-8 text.

Why it matters: the types the component uses are defined in its IDL
includes; without them nothing can be resolved, so semantic checks are
skipped.

Paths are resolved relative to the directory of the including file, not the
current directory:

```
// specs/pilot.gen
include "demoStruct.idl"     // reads specs/demoStruct.idl
```"#;

    /// `include-cycle`
    pub const INCLUDE_CYCLE: &str = r#"A file includes itself, directly or through other files. The message shows
the chain of includes and the label points at the include that closes it.

Why it matters: a cycle has no meaning (there is no order in which the files
can be read). A file included twice through different paths without a cycle
(a diamond) is fine: it is read once.

Example:

```
// a.idl
include "b.idl";
// b.idl
include "a.idl";   // include-cycle: `a.idl` includes itself: a.idl -> b.idl -> a.idl
```"#;
}
