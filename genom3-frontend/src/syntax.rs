//! Syntax errors in words: turns a pest error into a `syntax` diagnostic
//! that says what was expected where, and finds where to resume after it.

use genom_model::{Diagnostic, Span};
use pest::error::{Error, ErrorVariant, InputLocation};

use crate::diagnostics;
use crate::grammar::Rule;

/// Words for what a rule stands for, used after "expected".
fn describe(rule: Rule) -> String {
    use Rule::*;
    let fixed = match rule {
        EOI => "end of file",
        next_statement | statement => "a `component`, `interface` or IDL definition",
        idl_statement | type_dcl => "an IDL definition",
        identifier | scoped_name | declarator => "a name",
        integer_lit => "an integer",
        float_lit => "a number",
        string_lit | strings | string_list => "a string",
        semi => "`;`",
        comma => "`,`",
        colon => "`:`",
        coloncolon => "`::`",
        lbrace | properties | body => "`{`",
        rbrace => "`}`",
        lparen => "`(`",
        rparen => "`)`",
        lbracket => "`[`",
        rbracket => "`]`",
        langle => "`<`",
        rangle => "`>`",
        equals => "`=`",
        dot => "`.`",
        export => "a component element (`ids`, `task`, `port`, a service or a property)",
        property => "a property",
        type_spec | base_type | template_type => "a type",
        const_expr | unary | primary | literal => "a constant expression",
        binop => "an operator",
        time_unit => "a time unit (`s`, `ms`, `us`)",
        size_unit => "a size unit (`k`, `M`)",
        param_dir => "`in`, `out` or `inout`",
        port_dir => "`in` or `out`",
        param_src => "`ids`, `local`, `port` or `remote`",
        codel_param | attribute_param | service_param => "a parameter",
        event | event_list => "a state name",
        member | member_list => "a member such as `double x;`",
        initializer | initializer_value | opt_initializer => "a value",
        fsm_codel => "`<`",
        codel_call => "a codel function",
        kw_yield => "`yield`",
        case_label | union_case => "`case` or `default`",
        _ => "",
    };
    if !fixed.is_empty() {
        return fixed.to_owned();
    }
    let name = format!("{rule:?}");
    match name
        .strip_prefix("kw_")
        .or_else(|| name.strip_prefix("prop_"))
    {
        Some(k) => format!(
            "`{}`",
            k.replace("real_time", "real-time").replace('_', "-")
        ),
        None => name.replace('_', " "),
    }
}

/// The `syntax` diagnostic for a pest error on text whose first byte is at
/// global offset `base` (`text` is the parsed slice).
pub(crate) fn error(err: &Error<Rule>, text: &str, base: u32) -> (Diagnostic, usize) {
    let pos = match err.location {
        InputLocation::Pos(p) => p,
        InputLocation::Span((s, _)) => s,
    };
    let expected = match &err.variant {
        ErrorVariant::ParsingError { positives, .. } => {
            let mut words: Vec<String> = positives.iter().map(|r| describe(*r)).collect();
            words.sort();
            words.dedup();
            words
        }
        ErrorVariant::CustomError { message } => vec![message.clone()],
    };
    let found = found_at(text, pos);
    if let ErrorVariant::CustomError { message } = &err.variant {
        let start = base + u32::try_from(pos).unwrap_or(u32::MAX);
        let span = Span::new(
            start,
            start + u32::try_from(token_len(text, pos)).unwrap_or(0),
        );
        return (
            diagnostics::syntax(
                span,
                format!("cannot parse: {message} (nesting too deep?)"),
                "here".to_owned(),
            ),
            pos,
        );
    }
    let message = match expected.as_slice() {
        [] => format!("unexpected {found}"),
        [one] => format!("expected {one}, found {found}"),
        many => {
            let (last, init) = many
                .split_last()
                .map_or((String::new(), &[][..]), |(l, i)| (l.clone(), i));
            format!("expected {} or {last}, found {found}", init.join(", "))
        }
    };
    // genom3 reads `>>` as the shift operator, also after a type
    // parameter (`sequence<sequence<long>>`): say how to write it.
    let closes_two =
        expected.iter().any(|w| w == "`>`") && text.get(pos..).is_some_and(|r| r.starts_with(">>"));
    if closes_two {
        let start = base + u32::try_from(pos).unwrap_or(u32::MAX);
        let span = Span::new(start, start + 2);
        return (
            diagnostics::syntax(
                span,
                "`>>` is the shift operator: two type parameters close with `> >`".to_owned(),
                "write `> >` here".to_owned(),
            ),
            pos,
        );
    }
    let start = base + u32::try_from(pos).unwrap_or(u32::MAX);
    let len = token_len(text, pos);
    let span = Span::new(start, start + u32::try_from(len).unwrap_or(0));
    (
        diagnostics::syntax(span, message, "unexpected here".to_owned()),
        pos,
    )
}

fn token_len(text: &str, pos: usize) -> usize {
    let rest = text.get(pos..).unwrap_or("");
    let Some(c) = rest.chars().next() else {
        return 0;
    };
    if c.is_ascii_alphanumeric() || c == '_' {
        rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(rest.len())
    } else {
        c.len_utf8()
    }
}

fn found_at(text: &str, pos: usize) -> String {
    let rest = text.get(pos..).unwrap_or("");
    match rest.get(..token_len(text, pos)) {
        None | Some("") => "end of file".to_owned(),
        Some(tok) => genom_model::diagnostic::quote(tok),
    }
}

/// Where to resume after an error at `pos` in `text`: the start of the next
/// line (after `pos`'s line) that begins a top-level statement.
pub(crate) fn resume_after(text: &str, pos: usize) -> usize {
    const STARTS: [&str; 10] = [
        "component",
        "interface",
        "module",
        "struct",
        "typedef",
        "const",
        "enum",
        "union",
        "exception",
        "native",
    ];
    let mut offset = text
        .get(pos..)
        .and_then(|r| r.find('\n'))
        .map_or(text.len(), |n| pos + n + 1);
    while offset < text.len() {
        let line = &text[offset..];
        if STARTS.iter().any(|s| {
            line.strip_prefix(s)
                .is_some_and(|r| r.starts_with(|c: char| c.is_whitespace() || c == '{'))
        }) {
            return offset;
        }
        offset = line.find('\n').map_or(text.len(), |n| offset + n + 1);
    }
    text.len()
}
