//! IDL lowering: named types (modules give qualified names `m::T`; types
//! declared in a component or interface are scoped in it), constants with
//! their evaluated values, enumerators, exceptions; type expressions to
//! [`Ty`]; constant expression evaluation with IDL's operators.

use std::collections::BTreeMap;

use genom_model::component::genom3::Exception;
use genom_model::component::types::TypeTable;
use genom_model::component::{Constant, Field, Named, Ty, TypeDef, TypeId, TypeKind, Value};
use genom_model::kinds::BaseType;
use genom_model::{Code, Diagnostic, Span};

use super::closest_hint;

use crate::ast::{Declarator, Expr, ExprKind, IdlDef, Member, TypeSpec};
use crate::diagnostics;

/// The IDL tables built while lowering.
#[derive(Debug, Default)]
pub(crate) struct Types {
    /// Named types, in definition order.
    pub defs: genom_model::component::IdVec<TypeId, TypeDef>,
    /// Qualified name → type.
    pub by_name: BTreeMap<String, TypeId>,
    /// Qualified name → constant value.
    pub consts: BTreeMap<String, Value>,
    /// Constants in definition order.
    pub constants: Vec<Constant>,
    /// Qualified enumerator name → (enum type, enumerator).
    pub enumerators: BTreeMap<String, (TypeId, String)>,
    /// Exceptions by qualified name.
    pub exceptions: BTreeMap<String, Exception>,
    /// Diagnostics.
    pub diagnostics: Vec<Diagnostic>,
}

/// `scope::name` (or `name` at the top level).
pub(crate) fn qualify(scope: &[String], name: &str) -> String {
    if scope.is_empty() {
        name.to_owned()
    } else {
        format!("{}::{name}", scope.join("::"))
    }
}

/// The candidates a scoped name can mean from `scope`, innermost first.
pub(crate) fn candidates(scope: &[String], name: &str) -> Vec<String> {
    if let Some(abs) = name.strip_prefix("::") {
        return vec![abs.to_owned()];
    }
    (0..=scope.len())
        .rev()
        .map(|n| qualify(&scope[..n], name))
        .collect()
}

impl Types {
    /// Registers every definition of `defs` in `scope`.
    pub(crate) fn definitions(&mut self, defs: &[IdlDef], scope: &[String]) {
        for d in defs {
            self.definition(d, scope);
        }
    }

    /// Registers one definition.
    pub(crate) fn definition(&mut self, def: &IdlDef, scope: &[String]) {
        match def {
            IdlDef::Module(name, inner) => {
                let mut s = scope.to_vec();
                s.push(name.name.clone());
                self.definitions(inner, &s);
            }
            IdlDef::Const(ty, name, value) => {
                let ty = self.ty(ty, scope);
                let value = match self.eval(value, scope).and_then(|v| self.fits(&ty, v)) {
                    Ok(v) => Some(v),
                    Err(why) => {
                        self.diagnostics
                            .push(diagnostics::bad_constant(value.span, &why));
                        None
                    }
                };
                let qualified = qualify(scope, &name.name);
                if let Some(v) = &value {
                    self.consts.insert(qualified.clone(), v.clone());
                }
                self.constants.push(Constant {
                    name: qualified,
                    ty,
                    value,
                    span: name.span,
                });
            }
            IdlDef::Typedef(ty, decls) => {
                let base = self.ty(ty, scope);
                for d in decls {
                    let ty = self.array(base.clone(), d, scope);
                    self.define(scope, &d.name.name, d.name.span, TypeKind::Alias(ty));
                }
            }
            IdlDef::Native(name) => {
                self.define(scope, &name.name, name.span, TypeKind::Alias(Ty::Error));
            }
            IdlDef::Exception(items) => {
                for (name, members) in items {
                    let fields = self.fields(members, scope);
                    let qualified = qualify(scope, &name.name);
                    // An exception is also a type (a struct of its members).
                    self.define(
                        scope,
                        &name.name,
                        name.span,
                        TypeKind::Struct(fields.clone()),
                    );
                    self.exceptions
                        .entry(qualified.clone())
                        .or_insert(Exception {
                            name: Named {
                                name: qualified,
                                span: name.span,
                            },
                            fields,
                        });
                }
            }
            IdlDef::Type(spec) => {
                self.ty(spec, scope);
            }
            IdlDef::Forward(name) => {
                let q = qualify(scope, &name.name);
                if !self.by_name.contains_key(&q) {
                    self.define(scope, &name.name, name.span, TypeKind::Struct(Vec::new()));
                }
            }
        }
    }

    /// Defines (or completes a forward declaration of) `scope::name`.
    fn define(&mut self, scope: &[String], name: &str, span: Span, kind: TypeKind) -> TypeId {
        let qualified = qualify(scope, name);
        if let Some(&id) = self.by_name.get(&qualified) {
            if let Some(def) = self.defs.get_mut(id) {
                let forward = matches!(&def.kind, TypeKind::Struct(f) if f.is_empty());
                if forward {
                    def.kind = kind;
                    def.span = span;
                }
            }
            return id;
        }
        let id = self.defs.push(TypeDef {
            name: qualified.clone(),
            span,
            kind,
        });
        self.by_name.insert(qualified, id);
        id
    }

    /// Fields of a member list.
    pub(crate) fn fields(&mut self, members: &[Member], scope: &[String]) -> Vec<Field> {
        let mut out = Vec::new();
        for m in members {
            let base = self.ty(&m.ty, scope);
            for d in &m.decls {
                if let Some(first) = out.iter().find(|f: &&Field| f.name == d.name.name) {
                    self.diagnostics.push(diagnostics::duplicate(
                        "member",
                        &d.name.name,
                        d.name.span,
                        first.span,
                    ));
                    continue;
                }
                out.push(Field {
                    name: d.name.name.clone(),
                    ty: self.array(base.clone(), d, scope),
                    span: d.name.span,
                    default: None,
                    doc: None,
                });
            }
        }
        out
    }

    /// `T` with the declarator's array sizes.
    pub(crate) fn array(&mut self, base: Ty, d: &Declarator, scope: &[String]) -> Ty {
        let mut ty = base;
        for dim in d.dims.iter().rev() {
            let len = self.positive(dim, scope).unwrap_or(0);
            ty = Ty::Array {
                elem: Box::new(ty),
                len,
            };
        }
        ty
    }

    /// A non-negative integer constant, diagnosed when it is not one.
    pub(crate) fn positive(&mut self, e: &Expr, scope: &[String]) -> Option<u64> {
        match self.eval(e, scope) {
            Ok(Value::Int(v)) if v >= 0 => {
                let n = u64::try_from(v).ok();
                if n.is_none() {
                    self.diagnostics.push(diagnostics::bad_constant(
                        e.span,
                        &format!("{v} is too large for a size"),
                    ));
                }
                n
            }
            Ok(_) => {
                self.diagnostics.push(diagnostics::bad_constant(
                    e.span,
                    "expected a non-negative integer",
                ));
                None
            }
            Err(why) => {
                self.diagnostics
                    .push(diagnostics::bad_constant(e.span, &why));
                None
            }
        }
    }

    /// The named type a scoped name means from `scope`.
    pub(crate) fn lookup(&self, scope: &[String], name: &str) -> Option<TypeId> {
        candidates(scope, name)
            .iter()
            .find_map(|c| self.by_name.get(c).copied())
    }

    /// A type expression (constructed types are defined on the way).
    pub(crate) fn ty(&mut self, spec: &TypeSpec, scope: &[String]) -> Ty {
        match spec {
            TypeSpec::Base(name, _) => base(name).map_or(Ty::Error, Ty::base),
            TypeSpec::Named(name) => match self.lookup(scope, &name.name) {
                Some(id) => Ty::Named { id },
                None => {
                    let hint = closest_hint(&name.name, self.by_name.keys());
                    self.diagnostics.push(diagnostics::unknown(
                        Code::UnknownType,
                        "type",
                        &name.name,
                        name.span,
                        hint.as_deref(),
                    ));
                    Ty::Error
                }
            },
            TypeSpec::Sequence(elem, bound, _) => {
                let elem = self.ty(elem, scope);
                let bound = bound.as_ref().and_then(|b| self.positive(b, scope));
                Ty::Sequence {
                    elem: Box::new(elem),
                    bound,
                }
            }
            TypeSpec::Optional(elem, _) => Ty::Sequence {
                elem: Box::new(self.ty(elem, scope)),
                bound: Some(1),
            },
            TypeSpec::String(bound, _) => Ty::String {
                bound: bound.as_ref().and_then(|b| self.positive(b, scope)),
            },
            TypeSpec::Fixed(_) => Ty::base(BaseType::Double),
            TypeSpec::Struct(name, members) => {
                let id = self.define(scope, &name.name, name.span, TypeKind::Struct(Vec::new()));
                let mut inner = scope.to_vec();
                inner.push(name.name.clone());
                let fields = self.fields(members, &inner);
                if let Some(def) = self.defs.get_mut(id) {
                    def.kind = TypeKind::Struct(fields);
                }
                Ty::Named { id }
            }
            TypeSpec::Union(name, switch, cases) => {
                self.ty(switch, scope);
                for label in cases.iter().flat_map(|(labels, _)| labels.iter().flatten()) {
                    if let Err(why) = self.eval(label, scope) {
                        self.diagnostics
                            .push(diagnostics::bad_constant(label.span, &why));
                    }
                }
                let mut inner = scope.to_vec();
                inner.push(name.name.clone());
                let members: Vec<Member> = cases.iter().map(|(_, m)| m.clone()).collect();
                let fields = self.fields(&members, &inner);
                Ty::Named {
                    id: self.define(scope, &name.name, name.span, TypeKind::Struct(fields)),
                }
            }
            TypeSpec::Enum(name, values) => {
                let list: Vec<(String, Span)> =
                    values.iter().map(|v| (v.name.clone(), v.span)).collect();
                let id = self.define(scope, &name.name, name.span, TypeKind::Enum(list));
                for v in values {
                    self.enumerators
                        .insert(qualify(scope, &v.name), (id, v.name.clone()));
                }
                Ty::Named { id }
            }
        }
    }

    /// Evaluates a constant expression.
    pub(crate) fn eval(&self, e: &Expr, scope: &[String]) -> Result<Value, String> {
        Ok(match &e.kind {
            ExprKind::Int(v) => Value::Int(*v),
            ExprKind::TooComplex => {
                return Err(
                    "the expression has more than 4096 terms or 256 nested parentheses".to_owned(),
                );
            }
            ExprKind::OutOfRange(t) => {
                return Err(format!(
                    "`{t}` is out of the range of every IDL number type"
                ));
            }
            ExprKind::Float(v) => Value::Float(*v),
            ExprKind::Bool(v) => Value::Bool(*v),
            ExprKind::Char(c) => Value::Str(c.to_string()),
            ExprKind::Str(s) => Value::Str(s.clone()),
            ExprKind::Name(n) => {
                let cands = candidates(scope, n);
                if let Some(v) = cands.iter().find_map(|c| self.consts.get(c)) {
                    v.clone()
                } else if let Some((_, v)) = cands.iter().find_map(|c| self.enumerators.get(c)) {
                    Value::Enum(v.clone())
                } else {
                    let hint = closest_hint(n, self.consts.keys());
                    return Err(match hint {
                        Some(h) => format!("unknown constant `{n}` (did you mean `{h}`?)"),
                        None => format!("unknown constant `{n}`"),
                    });
                }
            }
            ExprKind::Unary(op, inner) => match (op, self.eval(inner, scope)?) {
                ('-', Value::Int(v)) => Value::Int(v.checked_neg().ok_or("`-` overflows")?),
                ('-', Value::Float(v)) => Value::Float(-v),
                ('+', v @ (Value::Int(_) | Value::Float(_))) => v,
                ('~', Value::Int(v)) => Value::Int(!v),
                _ => return Err(format!("`{op}` needs a number")),
            },
            ExprKind::Binary(op, a, b) => binary(op, self.eval(a, scope)?, self.eval(b, scope)?)?,
        })
    }
}

fn binary(op: &str, a: Value, b: Value) -> Result<Value, String> {
    match (a, b) {
        (Value::Int(x), Value::Int(y)) => {
            let v = match op {
                "+" => x.checked_add(y),
                "-" => x.checked_sub(y),
                "*" => x.checked_mul(y),
                "/" => x.checked_div(y),
                "%" => x.checked_rem(y),
                "|" => Some(x | y),
                "^" => Some(x ^ y),
                "&" => Some(x & y),
                "<<" => u32::try_from(y).ok().and_then(|s| x.checked_shl(s)),
                _ => u32::try_from(y).ok().and_then(|s| x.checked_shr(s)),
            };
            v.map(Value::Int)
                .ok_or_else(|| format!("`{op}` overflows or divides by zero"))
        }
        (x, y) => {
            let (Some(x), Some(y)) = (as_f64(&x), as_f64(&y)) else {
                return Err(format!("`{op}` needs numbers"));
            };
            Ok(Value::Float(match op {
                "+" => x + y,
                "-" => x - y,
                "*" => x * y,
                "/" => x / y,
                _ => return Err(format!("`{op}` needs integers")),
            }))
            .and_then(|v| match v {
                Value::Float(f) if !f.is_finite() => Err(format!(
                    "`{op}` gives a number out of the range of `double`"
                )),
                v => Ok(v),
            })
        }
    }
}

impl Types {
    /// `v` as a value of `ty`, or why it is not one: an integer within its
    /// type's range, a finite number for `float`/`double` (`float`: within
    /// `f32`), a boolean, a one-character `char`, a string. Integers widen
    /// to floating types; other types are not checked here.
    pub(crate) fn fits(&self, ty: &Ty, v: Value) -> Result<Value, String> {
        let resolved = self.defs.resolve(ty);
        let Ty::Base { base } = resolved.clone() else {
            return match (resolved, &v) {
                (Ty::String { .. }, Value::Str(_)) => Ok(v),
                (Ty::String { .. }, _) => Err("expected a string".to_owned()),
                _ => Ok(v),
            };
        };
        let name = base.idl();
        match (&v, base.integer_range()) {
            (Value::Int(i), Some((min, max))) if *i < min || *i > max => Err(format!(
                "{i} is out of the range of `{name}` ({min} to {max})"
            )),
            (Value::Int(_), Some(_)) => Ok(v),
            (_, Some(_)) => Err(format!("expected an integer for `{name}`")),
            (Value::Int(_) | Value::Float(_), None) if base.is_float() => {
                let f = as_f64(&v).unwrap_or(f64::INFINITY);
                let fits =
                    f.is_finite() && (base != BaseType::Float || f.abs() <= f64::from(f32::MAX));
                if fits {
                    Ok(v)
                } else {
                    Err(format!("{f} is out of the range of `{name}`"))
                }
            }
            (_, None) if base.is_float() => Err(format!("expected a number for `{name}`")),
            (Value::Bool(_), None) if base == BaseType::Boolean => Ok(v),
            (_, None) if base == BaseType::Boolean => Err("expected TRUE or FALSE".to_owned()),
            (Value::Str(s), None) if s.chars().count() == 1 => Ok(v),
            (_, None) => Err(format!("expected one character for `{name}`")),
        }
    }
}

/// A numeric value as `f64`.
pub(crate) fn as_f64(v: &Value) -> Option<f64> {
    match v {
        #[allow(clippy::cast_precision_loss)]
        Value::Int(i) => Some(*i as f64),
        Value::Float(f) => Some(*f),
        _ => None,
    }
}

/// The base type of an IDL spelling.
fn base(name: &str) -> Option<BaseType> {
    Some(match name {
        "double" => BaseType::Double,
        "float" => BaseType::Float,
        "short" => BaseType::Short,
        "long" => BaseType::Long,
        "long long" => BaseType::LongLong,
        "unsigned short" => BaseType::UShort,
        "unsigned long" => BaseType::ULong,
        "unsigned long long" => BaseType::ULongLong,
        "char" | "wchar" => BaseType::Char,
        "boolean" => BaseType::Boolean,
        "octet" => BaseType::Octet,
        _ => return None,
    })
}
