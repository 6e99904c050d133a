//! Shared helpers of the construct tests: parsing a snippet without any
//! diagnostic, the text a span covers, and accessors for the AST's items,
//! attributes and values.

use gen_frontend::ast::*;
use gen_frontend::{ParserReturn, parse_str};
use genom_model::Span;

// ---------------------------------------------------------------- helpers

/// Parses `text` as `t.gen` and requires no diagnostic at all.
pub(crate) fn parse_clean(text: &str) -> ParserReturn {
    let r = parse_str("t.gen", text);
    assert!(
        r.diagnostics.is_empty(),
        "unexpected diagnostics: {:#?}",
        r.diagnostics
    );
    r
}

/// The text a span covers.
pub(crate) fn at(r: &ParserReturn, span: Span) -> &str {
    r.sources.slice(span)
}

pub(crate) fn items(r: &ParserReturn) -> Vec<&Item> {
    r.ast.items().collect()
}

pub(crate) fn component(r: &ParserReturn) -> &Component {
    r.ast
        .items()
        .find_map(|i| match i {
            Item::Component(c) => Some(c),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no component in {:#?}", r.ast))
}

pub(crate) fn services(r: &ParserReturn) -> Vec<&Service> {
    r.ast
        .items()
        .filter_map(|i| match i {
            Item::Service(s) => Some(s),
            _ => None,
        })
        .collect()
}

pub(crate) fn service(r: &ParserReturn) -> &Service {
    let all = services(r);
    assert_eq!(all.len(), 1, "expected one service");
    all[0]
}

pub(crate) fn threads(r: &ParserReturn) -> Vec<&Thread> {
    r.ast
        .items()
        .filter_map(|i| match i {
            Item::Thread(t) => Some(t),
            _ => None,
        })
        .collect()
}

pub(crate) fn data_blocks(r: &ParserReturn) -> Vec<&DataBlock> {
    r.ast
        .items()
        .filter_map(|i| match i {
            Item::Data(d) => Some(d),
            _ => None,
        })
        .collect()
}

pub(crate) fn typedefs(r: &ParserReturn) -> Vec<&Typedef> {
    r.ast
        .items()
        .filter_map(|i| match i {
            Item::Typedef(t) => Some(t),
            _ => None,
        })
        .collect()
}

pub(crate) fn attr<'a>(attributes: &'a [Attribute], name: &str) -> &'a Attribute {
    attributes
        .iter()
        .find(|a| a.name.name == name)
        .unwrap_or_else(|| panic!("no attribute `{name}` in {attributes:#?}"))
}

pub(crate) fn ident_names(idents: &[Ident]) -> Vec<&str> {
    idents.iter().map(|i| i.name.as_str()).collect()
}

pub(crate) fn int(v: &Value) -> i128 {
    match v {
        Value::Number(NumberLit {
            value: Number::Int(n),
            ..
        }) => *n,
        other => panic!("not an integer: {other:?}"),
    }
}

pub(crate) fn float(v: &Value) -> f64 {
    match v {
        Value::Number(NumberLit {
            value: Number::Float(x),
            ..
        }) => *x,
        other => panic!("not a decimal: {other:?}"),
    }
}

pub(crate) fn const_int(e: &ConstExpr) -> i128 {
    match e {
        ConstExpr::Number(NumberLit {
            value: Number::Int(n),
            ..
        }) => *n,
        other => panic!("not an integer: {other:?}"),
    }
}

pub(crate) fn duration_ns(a: &Attribute) -> Option<i64> {
    match &a.value {
        AttrValue::Duration(d) => d.ns,
        other => panic!("not a duration: {other:?}"),
    }
}

pub(crate) fn base(t: &TypeSpec) -> BaseType {
    match t {
        TypeSpec::Base(b, _) => *b,
        other => panic!("not a base type: {other:?}"),
    }
}

pub(crate) fn named(t: &TypeSpec) -> &ScopedName {
    match t {
        TypeSpec::Named(n) => n,
        other => panic!("not a named type: {other:?}"),
    }
}

pub(crate) fn path_text(d: &DataRef) -> String {
    d.to_string()
}
