//! Typed values: defaults and initialisers checked against their declared
//! types (numbers and ranges, booleans, strings and bounds, enum values,
//! struct initialisers by field, arrays and sequences), giving model values.

use crate::ast::{self, FieldInit};
use genom_model::Span;
use genom_model::component::types::TypeTable as _;
use genom_model::component::{Ty, Value};
use genom_model::diagnostic::closest;
use genom_model::kinds::BaseType;

use super::Resolver;
use super::idl::describe_value;
use super::scope::Symbol;
use crate::checks::{duplicate_definition, type_mismatch};

impl Resolver {
    /// Checks a written value against `ty`; `None` when it does not fit
    /// (diagnosed) or the type is unknown.
    pub(super) fn value(&mut self, v: &ast::Value, ty: &Ty, scope: &[String]) -> Option<Value> {
        if matches!(self.c.types.resolve(ty), Ty::Error) {
            return None;
        }
        match v {
            ast::Value::Fields(fields, span) => self.struct_value(fields, *span, ty, scope),
            // `{}` initialises a struct with no field, as well as an empty list.
            ast::Value::List(items, _) if items.is_empty() && self.c.types.fields(ty).is_some() => {
                Some(Value::Struct(Vec::new()))
            }
            ast::Value::List(items, span) => self.list_value(items, *span, ty, scope),
            ast::Value::Name(name) => self.name_value(name, ty, scope),
            ast::Value::Number(n) => self.fit_number(n, ty),
            ast::Value::Str(s) => self.fit(Value::Str(s.value.clone()), ty, s.span),
            ast::Value::Bool(b, span) => self.fit(Value::Bool(*b), ty, *span),
        }
    }

    fn struct_value(
        &mut self,
        fields: &[FieldInit],
        span: Span,
        ty: &Ty,
        scope: &[String],
    ) -> Option<Value> {
        let Some(declared) = self.c.types.fields(ty).map(<[_]>::to_vec) else {
            let expected = self.show(ty);
            self.report(type_mismatch::value_mismatch(
                span,
                &expected,
                "a struct initialiser",
            ));
            return None;
        };
        let mut out: Vec<(String, Value)> = Vec::new();
        let mut seen: Vec<&FieldInit> = Vec::new();
        for init in fields {
            if let Some(first) = seen.iter().find(|f| f.name.name == init.name.name) {
                let d = duplicate_definition::duplicate(
                    "field initialiser",
                    &init.name.name,
                    init.name.span,
                    first.name.span,
                );
                self.report(d);
                continue;
            }
            seen.push(init);
            let Some(field) = declared.iter().find(|f| f.name == init.name.name) else {
                let names = declared.iter().map(|f| f.name.as_str());
                let help = closest(&init.name.name, names).map(|c| format!("did you mean `{c}`?"));
                let shown = self.show(ty);
                self.report(type_mismatch::no_such_field(
                    init.name.span,
                    &init.name.name,
                    &shown,
                    help,
                ));
                continue;
            };
            if let Some(v) = self.value(&init.value, &field.ty, scope) {
                out.push((field.name.clone(), v));
            }
        }
        Some(Value::Struct(out))
    }

    fn list_value(
        &mut self,
        items: &[ast::Value],
        span: Span,
        ty: &Ty,
        scope: &[String],
    ) -> Option<Value> {
        let (elem, bound) = match self.c.types.resolve(ty) {
            Ty::Array { elem, len } => ((**elem).clone(), Some(*len)),
            Ty::Sequence { elem, bound } => ((**elem).clone(), *bound),
            _ => {
                let expected = self.show(ty);
                self.report(type_mismatch::value_mismatch(
                    span,
                    &expected,
                    "a list of values",
                ));
                return None;
            }
        };
        if let Some(max) = bound.filter(|&m| items.len() as u64 > m) {
            let shown = self.show(ty);
            let d = type_mismatch::too_long(span, &shown, items.len(), max, "elements");
            self.report(d);
        }
        let values: Vec<Value> = items
            .iter()
            .filter_map(|i| self.value(i, &elem, scope))
            .collect();
        Some(Value::List(values))
    }

    /// A name as a value: an enumerator of the expected enum, or a constant.
    fn name_value(&mut self, name: &ast::ScopedName, ty: &Ty, scope: &[String]) -> Option<Value> {
        if let Some((enum_id, values)) = self.c.types.enumerators(ty) {
            let values: Vec<String> = values.iter().map(|(v, _)| v.clone()).collect();
            let found = self.scopes.lookup(scope, name).map(|(_, s)| s);
            // An unqualified name is looked up in the enum it initialises
            // first, even when another enum in scope has a value of that name.
            let unqualified = !name.absolute && name.parts.len() == 1;
            let ok = (unqualified && values.iter().any(|v| v == name.last()))
                || found == Some(Symbol::Enumerator(enum_id));
            if ok {
                return Some(Value::Enum(name.last().to_owned()));
            }
            if !matches!(found, Some(Symbol::Const(_))) {
                let shown = self.show(ty);
                let list: Vec<&str> = values.iter().map(String::as_str).collect();
                self.report(type_mismatch::not_an_enumerator(
                    name.span,
                    &name.to_string(),
                    &shown,
                    &list,
                ));
                return None;
            }
        }
        let v = self.name_constant(name, scope)?;
        self.fit(v, ty, name.span)
    }

    /// Checks a scalar value against a type (after aliases).
    pub(super) fn fit(&mut self, v: Value, ty: &Ty, span: Span) -> Option<Value> {
        let resolved = self.c.types.resolve(ty).clone();
        match (&v, &resolved) {
            (_, Ty::Error) => None,
            (Value::Int(i), Ty::Base { base }) if base.integer_range().is_some() => {
                self.in_range(*i, *base, span)
            }
            #[allow(clippy::cast_precision_loss)]
            (Value::Int(i), Ty::Base { base }) if base.is_float() => Some(Value::Float(*i as f64)),
            (Value::Float(f), Ty::Base { base }) if base.is_float() => {
                if !float_fits(*f, *base) {
                    let shown = describe_value(&v);
                    let d = type_mismatch::float_out_of_range(span, &shown, base.idl());
                    self.report(d);
                    return None;
                }
                Some(v)
            }
            (
                Value::Bool(_),
                Ty::Base {
                    base: BaseType::Boolean,
                },
            ) => Some(v),
            (
                Value::Str(s),
                Ty::Base {
                    base: BaseType::Char,
                },
            ) if s.chars().count() == 1 => Some(v),
            (Value::Str(s), Ty::String { bound }) => {
                if let Some(max) = bound.filter(|&m| s.chars().count() as u64 > m) {
                    let shown = self.show(ty);
                    let length = s.chars().count();
                    let d = type_mismatch::too_long(span, &shown, length, max, "characters");
                    self.report(d);
                }
                Some(v)
            }
            (Value::Enum(name), _) if self.is_enumerator_of(name, &resolved) => Some(v),
            _ => {
                let expected = self.show(ty);
                let found = format!("`{}`", describe_value(&v));
                self.report(type_mismatch::value_mismatch(span, &expected, &found));
                None
            }
        }
    }

    /// Checks a numeric literal against a type, quoting it as written when
    /// it is out of range (an integer too large even for `i128`, or a
    /// floating-point value its type cannot hold).
    fn fit_number(&mut self, n: &ast::NumberLit, ty: &Ty) -> Option<Value> {
        let raw = match n.value {
            ast::Number::Int(i) => Value::Int(i),
            ast::Number::Float(f) => Value::Float(f),
        };
        if let Ty::Base { base } = self.c.types.resolve(ty).clone() {
            let huge_integer = matches!(n.value, ast::Number::Float(_)) && is_integral(&n.text);
            if let (true, Some((min, max))) = (huge_integer, base.integer_range()) {
                let d = type_mismatch::out_of_range(n.span, &n.text, base.idl(), min, max);
                self.report(d);
                return None;
            }
            if base.is_float() && !float_fits(super::idl::as_float(&raw), base) {
                self.report(type_mismatch::float_out_of_range(
                    n.span,
                    &n.text,
                    base.idl(),
                ));
                return None;
            }
        }
        self.fit(raw, ty, n.span)
    }

    fn in_range(&mut self, i: i128, base: BaseType, span: Span) -> Option<Value> {
        let (min, max) = base.integer_range()?;
        if i < min || i > max {
            self.report(type_mismatch::out_of_range(
                span,
                &i.to_string(),
                base.idl(),
                min,
                max,
            ));
            return None;
        }
        Some(Value::Int(i))
    }

    fn is_enumerator_of(&self, name: &str, ty: &Ty) -> bool {
        self.c
            .types
            .enumerators(ty)
            .is_some_and(|(_, values)| values.iter().any(|(v, _)| v == name))
    }
}

/// Whether a numeric literal is written as an integer (decimal digits, or
/// hexadecimal), whatever its size.
fn is_integral(text: &str) -> bool {
    let body = text.strip_prefix('-').unwrap_or(text);
    body.starts_with("0x") || body.starts_with("0X") || !body.contains(['.', 'e', 'E'])
}

/// Whether a floating-point type holds `f`: finite, and for `float` within
/// the magnitude of `f32`.
fn float_fits(f: f64, base: BaseType) -> bool {
    match base {
        BaseType::Float => f.is_finite() && f.abs() <= f64::from(f32::MAX),
        _ => f.is_finite(),
    }
}
