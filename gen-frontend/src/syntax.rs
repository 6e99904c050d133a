//! Syntax errors in words: turns a pest error into a `syntax` diagnostic that
//! says what was expected and what was found, at the exact position; finds
//! where to resume after an error; and rejects pathological nesting before
//! the recursive-descent parser sees it.

use genom_model::{Diagnostic, Span};
use pest::error::{Error, ErrorVariant, InputLocation};

use crate::build::to_u32;
use crate::diagnostics;
use crate::grammar::Rule;

/// Deepest bracket nesting accepted. Real components nest fewer than ten
/// levels; the limit keeps the recursive parser far from stack exhaustion.
pub const MAX_NESTING: usize = 64;

/// Words for what a rule stands for, used after "expected".
pub fn describe(rule: Rule) -> &'static str {
    use Rule::*;
    match rule {
        EOI => "end of file",
        next_item | item => "a top-level item",
        next_idl_item | idl_item | idl_def => "an IDL definition",
        ident | scoped_name | declarator | attr_name | word => "a name",
        number => "a number",
        integer => "an integer",
        duration => "a duration such as `10ms`",
        size => "a size such as `64k`",
        string | string_content => "a string",
        boolean => "`true` or `false`",
        quote => "`\"`",
        semi => "`;`",
        colon => "`:`",
        assign => "`:=`",
        comma => "`,`",
        dot => "`.`",
        lbrace | field_block => "`{`",
        rbrace => "`}`",
        lparen => "`(`",
        rparen => "`)`",
        lbracket | array_dim => "`[`",
        rbracket => "`]`",
        langle => "`<`",
        rangle => "`>`",
        equals => "`=`",
        plus => "`+`",
        minus => "`-`",
        star => "`*`",
        slash => "`/`",
        percent => "`%`",
        kw_component | component => "`component`",
        kw_include | hash_include | include => "`include`",
        kw_ids | ids_block => "`ids`",
        kw_export | export_block => "`export`",
        kw_import | import_block => "`import`",
        kw_thread | thread => "`thread`",
        kw_service | service => "`service`",
        kw_init | kw_auto | service_kind => "`init` or `auto`",
        kw_codel => "`codel`",
        kw_start => "`start`",
        kw_control => "`control`",
        kw_exec => "`exec`",
        kw_inter => "`inter`",
        kw_typedef | typedef_def => "`typedef`",
        kw_struct | struct_def | struct_type => "`struct`",
        kw_enum | enum_def | enum_type => "`enum`",
        kw_const | const_def => "`const`",
        kw_module | module_def => "`module`",
        kw_string | string_type => "`string`",
        kw_sequence | sequence_type => "`sequence`",
        type_spec | base_type => "a type",
        const_expr | const_term | const_factor => "a constant expression",
        struct_body | enum_body => "`{`",
        struct_member => "a struct member such as `double x;`",
        angle_path | angle_content => "a path",
        value | composite | value_list => "a value",
        field_values | field_value | field_init => "a field initialiser such as `name := value`",
        member => "a member such as `double x;`",
        codel | named_codel | unnamed_codel => "a codel",
        attribute | attr_string | attr_duration | attr_size | attr_integer | attr_credentials
        | attr_call | attr_params | attr_typed | attr_datarefs | attr_idents | attr_ident
        | attr_word | attr_unknown => "an attribute",
        name_string | name_duration | name_size | name_integer | name_credentials | name_call
        | name_params | name_typed | name_datarefs | name_idents | name_ident | name_word => {
            "an attribute name"
        }
        unknown_value => "a value",
        call => "a codel call such as `f(a, b)`",
        argument | data_ref => "a data reference",
        param => "a parameter",
        typed_param | typed_name => "a type and a name",
        WHITESPACE | COMMENT => "a blank",
        ident_start | ident_char | name_char | hex_digits | decimal_digits | exponent
        | time_unit | blanks | word_long | word_short | known_name => "a name",
    }
}

/// Joins alternatives: "A", "A or B", "A, B or C".
fn join_alternatives(items: &[&str]) -> String {
    match items {
        [] => "something else".to_owned(),
        [one] => (*one).to_owned(),
        [init @ .., last] => format!("{} or {last}", init.join(", ")),
    }
}

/// Converts a pest error on `text` (which starts at global offset `base`).
/// Returns the diagnostic and the local offset of the error.
pub fn convert(error: &Error<Rule>, text: &str, base: u32) -> (Diagnostic, usize) {
    let pos = match error.location {
        InputLocation::Pos(p) => p,
        InputLocation::Span((p, _)) => p,
    };
    let pos = pos.min(text.len());
    let rest = &text[pos..];
    let at = |local: usize| base + to_u32(local);
    if rest.starts_with("/*") && !rest.contains("*/") {
        return (
            diagnostics::unterminated_comment(Span::new(at(pos), at(pos + 2))),
            pos,
        );
    }
    let token_len = token_length(rest);
    // pest's stack guard stopped the parser: nesting that
    // `excessive_nesting` cannot see (`- - - 1`, `sequence/**/<`).
    if let ErrorVariant::CustomError { .. } = &error.variant {
        return (
            genom_model::nesting::too_deep(Span::new(at(pos), at(pos + token_len)), MAX_NESTING),
            pos,
        );
    }
    let expected = expected_words(error);
    let found = match rest.chars().next() {
        None => "end of file".to_owned(),
        Some('\n' | '\r') => "end of line".to_owned(),
        Some(_) => genom_model::diagnostic::quote(&rest[..token_len]),
    };
    // A missing terminator belongs after the previous token, not on the
    // next line (as rustc reports it).
    let previous = previous_token_end(text, pos);
    let after_previous =
        rest.is_empty() || (expected.contains(&"`;`") && text[previous..pos].contains('\n'));
    let span = if after_previous {
        Span::new(at(previous), at(previous))
    } else {
        Span::new(at(pos), at(pos + token_len))
    };
    let mut d = diagnostics::syntax(span, &join_alternatives(&expected), &found);
    if let Some(help) = spaced_duration(&expected, rest, token_len) {
        d = d.with_help(help);
    }
    if rest.is_empty() {
        if let Some(open) = unclosed_brace(text) {
            d = d.with_label(
                Span::new(at(open), at(open + 1)),
                "this `{` is never closed",
            );
        }
    }
    (d, pos)
}

/// When a duration was expected and the text is a number, blanks, then a
/// unit (`10 ms`): the help says to write them together.
fn spaced_duration(expected: &[&str], rest: &str, token_len: usize) -> Option<String> {
    if !expected.contains(&describe(Rule::duration)) {
        return None;
    }
    let number = rest.get(..token_len)?;
    let after = rest.get(token_len..)?;
    let unit: String = after
        .trim_start_matches([' ', '\t'])
        .chars()
        .take_while(char::is_ascii_alphabetic)
        .collect();
    let spaced = after.starts_with([' ', '\t']);
    let is_unit = crate::literal::unit_ns(&unit).is_some();
    let is_number = number.chars().all(|c| c.is_ascii_digit() || c == '.');
    (spaced && is_unit && is_number)
        .then(|| format!("write the number and its unit together: `{number}{unit}`"))
}

fn expected_words(error: &Error<Rule>) -> Vec<&'static str> {
    let mut expected: Vec<&str> = Vec::new();
    if let ErrorVariant::ParsingError { positives, .. } = &error.variant {
        for &r in positives {
            let d = describe(r);
            if !expected.contains(&d) {
                expected.push(d);
            }
        }
    }
    expected
}

/// The offset just after the last non-blank character before `pos`.
fn previous_token_end(text: &str, pos: usize) -> usize {
    text[..pos].trim_end().len()
}

/// The offset of the innermost `{` left open at the end of `text`,
/// skipping comments and strings.
fn unclosed_brace(text: &str) -> Option<usize> {
    let bytes = text.as_bytes();
    let mut open = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if let Some(after) = genom_model::nesting::skip_trivia(text, i) {
            i = after;
            continue;
        }
        match bytes[i] {
            b'{' => open.push(i),
            b'}' => {
                open.pop();
            }
            _ => {}
        }
        i += 1;
    }
    open.pop()
}

/// Length in bytes of the token at the start of `rest`: a word, a string
/// start, or one character.
fn token_length(rest: &str) -> usize {
    let word = rest
        .bytes()
        .take_while(|b| b.is_ascii_alphanumeric() || *b == b'_')
        .count();
    if word > 0 {
        return word;
    }
    rest.chars().next().map_or(0, char::len_utf8)
}

/// Top-level keywords a line may start with for parsing to resume there.
const RESUME_WORDS: &[&str] = &[
    "component",
    "include",
    "#include",
    "ids",
    "export",
    "import",
    "thread",
    "service",
    "init",
    "auto",
    "typedef",
    "struct",
    "enum",
    "const",
    "module",
];

/// The byte offset, after `from`, of the next line that looks like the start
/// of a top-level item and is indented no deeper than `indent` (the column
/// of the item that failed), if any. The indentation rule keeps an indented
/// `const` or `struct` inside a broken item from being taken for a new item.
pub fn resume_point(text: &str, from: usize, indent: usize) -> Option<usize> {
    let mut offset = text.get(from..)?.find('\n').map(|i| from + i + 1)?;
    while offset < text.len() {
        let line_end = text[offset..].find('\n').map_or(text.len(), |i| offset + i);
        let line = &text[offset..line_end];
        let depth = line.len() - line.trim_start().len();
        if depth <= indent && starts_item(line) {
            return Some(offset);
        }
        offset = line_end + 1;
    }
    None
}

/// The column (in bytes from the line start) of the first token at or after
/// `pos`, skipping blanks and comments.
pub fn item_indent(text: &str, pos: usize) -> usize {
    let mut i = pos;
    loop {
        let rest = &text[i..];
        let trimmed = rest.trim_start();
        i += rest.len() - trimmed.len();
        if trimmed.starts_with("//") {
            i = text[i..].find('\n').map_or(text.len(), |j| i + j);
        } else if trimmed.starts_with("/*") {
            i = text[i + 2..]
                .find("*/")
                .map_or(text.len(), |j| i + 2 + j + 2);
        } else {
            break;
        }
    }
    let line_start = text[..i].rfind('\n').map_or(0, |j| j + 1);
    i - line_start
}

fn starts_item(line: &str) -> bool {
    let trimmed = line.trim_start();
    let word_len = trimmed
        .bytes()
        .take_while(|b| b.is_ascii_alphanumeric() || *b == b'_' || *b == b'#')
        .count();
    let (word, after) = trimmed.split_at(word_len);
    if !RESUME_WORDS.contains(&word) {
        return false;
    }
    let next = after.trim_start().chars().next();
    match word {
        "include" | "#include" => matches!(next, Some('"' | '<')),
        _ => {
            after.starts_with([' ', '\t'])
                && next.is_some_and(|c| c.is_ascii_alphabetic() || c == '_' || c == ':')
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alternatives_read_as_a_sentence() {
        assert_eq!(join_alternatives(&["`;`"]), "`;`");
        assert_eq!(join_alternatives(&["`;`", "`,`"]), "`;` or `,`");
        assert_eq!(join_alternatives(&["a", "b", "c"]), "a, b or c");
    }

    #[test]
    fn finds_the_unclosed_brace() {
        let text = "service a {\n  start codel { exec: f(\"}\"); } /* } */\n";
        assert_eq!(unclosed_brace(text), Some(10));
        assert_eq!(unclosed_brace("a { b { } }"), None);
    }

    #[test]
    fn resumes_at_the_next_item_line() {
        let text = "service a {\n  thread: x;\n  oops\n}\nservice b {}\n";
        let from = text.find("oops").unwrap();
        assert_eq!(resume_point(text, from, 0), text.find("service b"));
        // An indented keyword inside a broken item is not a new item.
        let nested = "service a {\n  exec: f(\n    const x);\n}\nconst long N = 1;\n";
        assert_eq!(resume_point(nested, 12, 0), nested.find("const long"));
        assert_eq!(item_indent("  /* c */ // d\n   service", 0), 3);
        // `thread:` and `export:` inside a service are attributes, not items.
        assert!(!starts_item("  thread: motionTask;"));
        assert!(!starts_item("  export: T x;"));
        assert!(starts_item("init service setup {"));
        assert!(starts_item("#include \"a.idl\""));
    }
}
