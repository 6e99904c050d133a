//! IDL declarations: types (structs, enums, typedefs), enumerators and
//! constants of every file, by module scope; type expressions; constant
//! evaluation (lazy, so constants may refer to later ones).

use crate::Ast;
use crate::ast::{self, BinOp, ConstExpr, Item, StructMember, TypeSpec, TypedefTarget};
use genom_model::Span;
use genom_model::component::types::TypeTable as _;
use genom_model::component::{Constant, Field, Ty, TypeDef, TypeId, TypeKind, Value};

use super::Resolver;
use super::scope::{Symbol, qualify};
use crate::checks::{duplicate_definition, type_mismatch, unknown_name};

/// Evaluation state of one constant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum EvalState {
    Pending,
    Running,
    Done,
}

/// The AST of every constant and where it is declared, for lazy evaluation.
#[derive(Debug, Default)]
pub(super) struct Consts {
    defs: Vec<(ast::ConstDef, Vec<String>)>,
    state: Vec<EvalState>,
}

/// A type body to resolve once every name is declared.
enum Pending<'a> {
    Struct(TypeId, &'a [StructMember], Vec<String>),
    Alias(TypeId, &'a TypeSpec, &'a [ConstExpr], Vec<String>),
    AliasTo(TypeId, TypeId, &'a [ConstExpr], Vec<String>),
}

/// Declares every IDL name of every file, then resolves type bodies and
/// evaluates every constant.
pub(super) fn declare_all(r: &mut Resolver, ast: &Ast) {
    let mut pending = Vec::new();
    for item in ast.items() {
        declare(r, item, &[], &mut pending);
    }
    for p in pending {
        resolve_pending(r, p);
    }
    for index in 0..r.consts.defs.len() {
        r.const_value(index);
    }
}

fn declare<'a>(r: &mut Resolver, item: &'a Item, scope: &[String], pending: &mut Vec<Pending<'a>>) {
    match item {
        Item::Module(m) => {
            let mut inner = scope.to_vec();
            inner.push(m.name.name.clone());
            for i in &m.items {
                declare(r, i, &inner, pending);
            }
        }
        Item::Struct(s) => {
            if let Some(id) = r.declare_type(scope, &s.name, TypeKind::Struct(Vec::new())) {
                pending.push(Pending::Struct(id, &s.members, scope.to_vec()));
            }
        }
        Item::Enum(e) => {
            r.declare_enum(scope, &e.name, &e.enumerators);
        }
        Item::Typedef(t) => declare_typedef(r, t, scope, pending),
        Item::Const(c) => r.declare_const(scope, c),
        _ => {}
    }
}

fn declare_typedef<'a>(
    r: &mut Resolver,
    t: &'a ast::Typedef,
    scope: &[String],
    pending: &mut Vec<Pending<'a>>,
) {
    let Some(first) = t.declarators.first() else {
        return;
    };
    let inline = match &t.target {
        TypedefTarget::Struct(tag, members) => {
            let name = tag.as_ref().unwrap_or(&first.name);
            let id = r.declare_type(scope, name, TypeKind::Struct(Vec::new()));
            if let Some(id) = id {
                pending.push(Pending::Struct(id, members, scope.to_vec()));
            }
            Some((name.name.clone(), id))
        }
        TypedefTarget::Enum(tag, values) => {
            let name = tag.as_ref().unwrap_or(&first.name);
            Some((name.name.clone(), r.declare_enum(scope, name, values)))
        }
        TypedefTarget::Type(_) => None,
    };
    for d in &t.declarators {
        match (&inline, &t.target) {
            (Some((name, _)), _) if *name == d.name.name && d.dims.is_empty() => {}
            (Some((_, Some(target))), _) => {
                if let Some(id) = r.declare_type(scope, &d.name, TypeKind::Alias(Ty::Error)) {
                    pending.push(Pending::AliasTo(id, *target, &d.dims, scope.to_vec()));
                }
            }
            (None, TypedefTarget::Type(spec)) => {
                if let Some(id) = r.declare_type(scope, &d.name, TypeKind::Alias(Ty::Error)) {
                    pending.push(Pending::Alias(id, spec, &d.dims, scope.to_vec()));
                }
            }
            _ => {}
        }
    }
}

fn resolve_pending(r: &mut Resolver, p: Pending<'_>) {
    let (id, kind) = match p {
        Pending::Struct(id, members, scope) => {
            (id, TypeKind::Struct(r.struct_fields(members, &scope)))
        }
        Pending::Alias(id, spec, dims, scope) => {
            (id, TypeKind::Alias(r.ty_dims(spec, dims, &scope)))
        }
        Pending::AliasTo(id, target, dims, scope) => (
            id,
            TypeKind::Alias(r.wrap_dims(Ty::Named { id: target }, dims, &scope)),
        ),
    };
    if let Some(def) = r.c.types.get_mut(id) {
        def.kind = kind;
    }
}

impl Resolver {
    /// Declares a named type in `scope`; `None` (and a diagnostic) when the
    /// name is taken.
    fn declare_type(
        &mut self,
        scope: &[String],
        name: &ast::Ident,
        kind: TypeKind,
    ) -> Option<TypeId> {
        let qualified = qualify(scope, &name.name);
        let id = self.c.types.push(TypeDef {
            name: qualified.clone(),
            span: name.span,
            kind,
        });
        match self.scopes.declare(qualified, Symbol::Type(id), name.span) {
            Ok(()) => Some(id),
            Err(first) => {
                self.report(duplicate_definition::duplicate(
                    "type", &name.name, name.span, first,
                ));
                None
            }
        }
    }

    fn declare_enum(
        &mut self,
        scope: &[String],
        name: &ast::Ident,
        values: &[ast::Ident],
    ) -> Option<TypeId> {
        let list = values.iter().map(|v| (v.name.clone(), v.span)).collect();
        let id = self.declare_type(scope, name, TypeKind::Enum(list))?;
        for v in values {
            if let Err(first) =
                self.scopes
                    .declare(qualify(scope, &v.name), Symbol::Enumerator(id), v.span)
            {
                self.report(duplicate_definition::duplicate(
                    "enum value",
                    &v.name,
                    v.span,
                    first,
                ));
            }
        }
        Some(id)
    }

    fn declare_const(&mut self, scope: &[String], c: &ast::ConstDef) {
        let index = self.c.constants.len();
        let qualified = qualify(scope, &c.name.name);
        if let Err(first) =
            self.scopes
                .declare(qualified.clone(), Symbol::Const(index), c.name.span)
        {
            self.report(duplicate_definition::duplicate(
                "constant",
                &c.name.name,
                c.name.span,
                first,
            ));
            return;
        }
        self.c.constants.push(Constant {
            name: qualified,
            ty: Ty::Error,
            value: None,
            span: c.name.span,
        });
        self.consts.defs.push((c.clone(), scope.to_vec()));
        self.consts.state.push(EvalState::Pending);
    }

    fn struct_fields(&mut self, members: &[StructMember], scope: &[String]) -> Vec<Field> {
        let mut fields: Vec<Field> = Vec::new();
        for m in members {
            for d in &m.declarators {
                if let Some(prev) = fields.iter().find(|f| f.name == d.name.name) {
                    let first = prev.span;
                    self.report(duplicate_definition::duplicate(
                        "field",
                        &d.name.name,
                        d.name.span,
                        first,
                    ));
                    continue;
                }
                let ty = self.ty_dims(&m.ty, &d.dims, scope);
                fields.push(Field {
                    name: d.name.name.clone(),
                    ty,
                    span: d.name.span,
                    default: None,
                    doc: None,
                });
            }
        }
        fields
    }

    /// Resolves a type expression written in `scope`.
    pub(super) fn ty(&mut self, spec: &TypeSpec, scope: &[String]) -> Ty {
        match spec {
            TypeSpec::Base(b, _) => Ty::base(*b),
            TypeSpec::String(bound, _) => Ty::String {
                bound: bound.as_deref().and_then(|e| self.bound(e, scope)),
            },
            TypeSpec::Sequence(elem, bound, _) => Ty::Sequence {
                elem: Box::new(self.ty(elem, scope)),
                bound: bound.as_deref().and_then(|e| self.bound(e, scope)),
            },
            TypeSpec::Named(name) => match self.scopes.lookup(scope, name) {
                Some((_, Symbol::Type(id))) => Ty::Named { id },
                _ => {
                    let candidates = self.scopes.names(|s| matches!(s, Symbol::Type(_)));
                    let d = unknown_name::unknown_type(&name.to_string(), name.span, candidates);
                    self.report(d);
                    Ty::Error
                }
            },
        }
    }

    /// A type with array dimensions (`T name[2][3]`).
    pub(super) fn ty_dims(&mut self, spec: &TypeSpec, dims: &[ConstExpr], scope: &[String]) -> Ty {
        let base = self.ty(spec, scope);
        self.wrap_dims(base, dims, scope)
    }

    fn wrap_dims(&mut self, base: Ty, dims: &[ConstExpr], scope: &[String]) -> Ty {
        let mut ty = base;
        for d in dims.iter().rev() {
            ty = match self.bound(d, scope) {
                Some(len) => Ty::Array {
                    elem: Box::new(ty),
                    len,
                },
                None => Ty::Error,
            };
        }
        ty
    }

    /// An array or string/sequence bound: a positive integer constant.
    fn bound(&mut self, e: &ConstExpr, scope: &[String]) -> Option<u64> {
        match self.eval(e, scope) {
            Some(Value::Int(n)) if n > 0 => u64::try_from(n).ok(),
            Some(other) => {
                let found = format!("`{}`", describe_value(&other));
                self.report(type_mismatch::value_mismatch(
                    e.span(),
                    "positive integer constant",
                    &found,
                ));
                None
            }
            None => None,
        }
    }

    /// The value of constant `index`, evaluated on first use.
    pub(super) fn const_value(&mut self, index: usize) -> Option<Value> {
        match self.consts.state.get(index).copied()? {
            EvalState::Done => return self.c.constants.get(index)?.value.clone(),
            EvalState::Running => {
                let (def, _) = &self.consts.defs[index];
                let d = type_mismatch::value_mismatch(
                    def.name.span,
                    "constant",
                    "a constant defined in terms of itself",
                );
                self.report(d);
                return None;
            }
            EvalState::Pending => {}
        }
        self.consts.state[index] = EvalState::Running;
        let (def, scope) = self.consts.defs[index].clone();
        let ty = self.ty(&def.ty, &scope);
        let raw = self.eval(&def.value, &scope);
        let value = raw.and_then(|v| self.fit(v, &ty, def.value.span()));
        self.c.constants[index].ty = ty;
        self.c.constants[index].value = value.clone();
        self.consts.state[index] = EvalState::Done;
        value
    }

    /// Evaluates a constant expression.
    pub(super) fn eval(&mut self, e: &ConstExpr, scope: &[String]) -> Option<Value> {
        match e {
            ConstExpr::Number(n) => Some(number_value(&n.value)),
            ConstExpr::Str(s) => Some(Value::Str(s.value.clone())),
            ConstExpr::Bool(b, _) => Some(Value::Bool(*b)),
            ConstExpr::Name(name) => self.name_constant(name, scope),
            ConstExpr::Neg(inner, span) => {
                let v = self.eval(inner, scope)?;
                self.negate(v, *span)
            }
            ConstExpr::Binary(a, op, b, span) => {
                let (x, y) = (self.eval(a, scope)?, self.eval(b, scope)?);
                self.arith(&x, *op, &y, *span)
            }
        }
    }

    /// The value of a constant or enumerator name.
    pub(super) fn name_constant(
        &mut self,
        name: &ast::ScopedName,
        scope: &[String],
    ) -> Option<Value> {
        match self.scopes.lookup(scope, name) {
            Some((_, Symbol::Const(i))) => self.const_value(i),
            Some((_, Symbol::Enumerator(_))) => Some(Value::Enum(name.last().to_owned())),
            _ => {
                let candidates = self.scopes.names(|s| matches!(s, Symbol::Const(_)));
                self.report(unknown_name::unknown_data(
                    "constant",
                    &name.to_string(),
                    name.span,
                    candidates,
                ));
                None
            }
        }
    }

    fn negate(&mut self, v: Value, span: Span) -> Option<Value> {
        match v {
            Value::Int(i) => Some(Value::Int(-i)),
            Value::Float(f) => Some(Value::Float(-f)),
            other => {
                let found = format!("`{}`", describe_value(&other));
                self.report(type_mismatch::value_mismatch(span, "number", &found));
                None
            }
        }
    }

    fn arith(&mut self, x: &Value, op: BinOp, y: &Value, span: Span) -> Option<Value> {
        let result = match (x, y) {
            (Value::Int(a), Value::Int(b)) => int_op(*a, op, *b).map(Value::Int),
            (Value::Int(_) | Value::Float(_), Value::Int(_) | Value::Float(_)) => {
                float_op(as_float(x), op, as_float(y)).map(Value::Float)
            }
            _ => None,
        };
        if result.is_none() {
            let found = format!(
                "`{} {} {}`",
                describe_value(x),
                op_text(op),
                describe_value(y)
            );
            self.report(type_mismatch::value_mismatch(
                span,
                "constant arithmetic",
                &found,
            ));
        }
        result
    }

    /// The display form of a type, for messages.
    pub(super) fn show(&self, ty: &Ty) -> String {
        self.c.types.display(ty)
    }
}

fn number_value(n: &ast::Number) -> Value {
    match n {
        ast::Number::Int(i) => Value::Int(*i),
        ast::Number::Float(f) => Value::Float(*f),
    }
}

/// A numeric value as `f64` (integers rounded; NaN for other values).
pub(super) fn as_float(v: &Value) -> f64 {
    match v {
        #[allow(clippy::cast_precision_loss)]
        Value::Int(i) => *i as f64,
        Value::Float(f) => *f,
        _ => f64::NAN,
    }
}

fn int_op(a: i128, op: BinOp, b: i128) -> Option<i128> {
    match op {
        BinOp::Add => a.checked_add(b),
        BinOp::Sub => a.checked_sub(b),
        BinOp::Mul => a.checked_mul(b),
        BinOp::Div => a.checked_div(b),
        BinOp::Rem => a.checked_rem(b),
    }
}

fn float_op(a: f64, op: BinOp, b: f64) -> Option<f64> {
    let r = match op {
        BinOp::Add => a + b,
        BinOp::Sub => a - b,
        BinOp::Mul => a * b,
        BinOp::Div => a / b,
        BinOp::Rem => a % b,
    };
    r.is_finite().then_some(r)
}

fn op_text(op: BinOp) -> &'static str {
    match op {
        BinOp::Add => "+",
        BinOp::Sub => "-",
        BinOp::Mul => "*",
        BinOp::Div => "/",
        BinOp::Rem => "%",
    }
}

/// A value as it would be written, for messages.
pub(super) fn describe_value(v: &Value) -> String {
    match v {
        Value::Int(i) => i.to_string(),
        Value::Float(f) => format!("{f:?}"),
        Value::Bool(b) => b.to_string(),
        Value::Str(s) => format!("\"{s}\""),
        Value::Enum(e) => e.clone(),
        Value::Struct(_) => "{ ... }".to_owned(),
        Value::List(items) => format!("{{ {} elements }}", items.len()),
    }
}
