//! Resolved IDL types and values: type expressions ([`Ty`]) that refer to
//! named definitions ([`TypeDef`]) by id, alias resolution, structural
//! equality (for codel prototypes) and typed values.

use std::fmt::Write as _;

use serde::Serialize;

use super::{IdVec, TypeId};
use crate::kinds::BaseType;
use crate::span::Span;

/// A type expression.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Ty {
    /// A base type.
    Base {
        /// Which one.
        base: BaseType,
    },
    /// `string` or `string<N>`.
    String {
        /// The bound, if any.
        bound: Option<u64>,
    },
    /// `sequence<T>` or `sequence<T, N>`.
    Sequence {
        /// Element type.
        elem: Box<Ty>,
        /// The bound, if any.
        bound: Option<u64>,
    },
    /// A fixed array `T[N]` (multi-dimensional arrays nest, outermost first).
    Array {
        /// Element type.
        elem: Box<Ty>,
        /// Length.
        len: u64,
    },
    /// A named type.
    Named {
        /// Its definition.
        id: TypeId,
    },
    /// A type that did not resolve (already diagnosed); compatible with
    /// everything so that one mistake gives one diagnostic.
    Error,
}

impl Ty {
    /// A base type.
    pub fn base(base: BaseType) -> Ty {
        Ty::Base { base }
    }
}

/// A named type definition.
#[derive(Debug, Clone, PartialEq)]
pub struct TypeDef {
    /// Qualified name without leading `::` (`geo::Pose`), or the IDS block
    /// name for the anonymous struct of an IDS block.
    pub name: String,
    /// Where the name is written.
    pub span: Span,
    /// What it is.
    pub kind: TypeKind,
}

/// What a named type is.
#[derive(Debug, Clone, PartialEq)]
pub enum TypeKind {
    /// A struct with fields.
    Struct(Vec<Field>),
    /// An enum with its values, in order.
    Enum(Vec<(String, Span)>),
    /// A typedef of another type.
    Alias(Ty),
}

/// A struct field (or IDS member).
#[derive(Debug, Clone, PartialEq)]
pub struct Field {
    /// Its name.
    pub name: String,
    /// Its type.
    pub ty: Ty,
    /// Where the name is written.
    pub span: Span,
    /// Initial value (IDS members).
    pub default: Option<Value>,
    /// Documentation string (IDS members).
    pub doc: Option<String>,
}

/// A typed constant value.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Value {
    /// An integer.
    Int(i128),
    /// A floating-point number.
    Float(f64),
    /// A boolean.
    Bool(bool),
    /// A string (also a `char`).
    Str(String),
    /// An enum value, by name.
    Enum(String),
    /// A struct, by field, in declaration order.
    Struct(Vec<(String, Value)>),
    /// An array or sequence.
    List(Vec<Value>),
}

/// Lookups over the type table.
pub trait TypeTable {
    /// The definition with this id.
    fn def(&self, id: TypeId) -> Option<&TypeDef>;

    /// Follows aliases to the underlying type expression.
    fn resolve<'a>(&'a self, ty: &'a Ty) -> &'a Ty {
        let mut current = ty;
        for _ in 0..64 {
            match current {
                Ty::Named { id } => match self.def(*id).map(|d| &d.kind) {
                    Some(TypeKind::Alias(inner)) => current = inner,
                    _ => return current,
                },
                _ => return current,
            }
        }
        current
    }

    /// The fields of a struct type (after aliases).
    fn fields<'a>(&'a self, ty: &'a Ty) -> Option<&'a [Field]> {
        match self.resolve(ty) {
            Ty::Named { id } => match self.def(*id).map(|d| &d.kind) {
                Some(TypeKind::Struct(fields)) => Some(fields),
                _ => None,
            },
            _ => None,
        }
    }

    /// The values of an enum type (after aliases).
    fn enumerators<'a>(&'a self, ty: &'a Ty) -> Option<(TypeId, &'a [(String, Span)])> {
        match self.resolve(ty) {
            Ty::Named { id } => match self.def(*id).map(|d| &d.kind) {
                Some(TypeKind::Enum(values)) => Some((*id, values)),
                _ => None,
            },
            _ => None,
        }
    }

    /// Structural equality after resolving aliases; named structs and enums
    /// are equal only to themselves. [`Ty::Error`] equals everything.
    fn same(&self, a: &Ty, b: &Ty) -> bool {
        match (self.resolve(a), self.resolve(b)) {
            (Ty::Error, _) | (_, Ty::Error) => true,
            (Ty::Sequence { elem: x, bound: m }, Ty::Sequence { elem: y, bound: n }) => {
                m == n && self.same(x, y)
            }
            (Ty::Array { elem: x, len: m }, Ty::Array { elem: y, len: n }) => {
                m == n && self.same(x, y)
            }
            (x, y) => x == y,
        }
    }

    /// The type as IDL would write it (aliases keep their name).
    fn display(&self, ty: &Ty) -> String {
        let mut out = String::new();
        write_ty(self, ty, &mut out);
        out
    }
}

fn write_ty<T: TypeTable + ?Sized>(table: &T, ty: &Ty, out: &mut String) {
    match ty {
        Ty::Base { base } => out.push_str(base.idl()),
        Ty::String { bound: None } => out.push_str("string"),
        Ty::String { bound: Some(n) } => {
            let _ = write!(out, "string<{n}>");
        }
        Ty::Sequence { elem, bound } => {
            out.push_str("sequence<");
            write_ty(table, elem, out);
            if let Some(n) = bound {
                let _ = write!(out, ", {n}");
            }
            out.push('>');
        }
        Ty::Array { elem, len } => {
            write_ty(table, elem, out);
            let _ = write!(out, "[{len}]");
        }
        Ty::Named { id } => out.push_str(table.def(*id).map_or("?", |d| d.name.as_str())),
        Ty::Error => out.push_str("{unknown}"),
    }
}

impl TypeTable for IdVec<TypeId, TypeDef> {
    fn def(&self, id: TypeId) -> Option<&TypeDef> {
        self.get(id)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> IdVec<TypeId, TypeDef> {
        let mut t = IdVec::new();
        let span = Span::default();
        let pose = t.push(TypeDef {
            name: "geo::Pose".into(),
            span,
            kind: TypeKind::Struct(vec![Field {
                name: "x".into(),
                ty: Ty::base(BaseType::Double),
                span,
                default: None,
                doc: None,
            }]),
        });
        t.push(TypeDef {
            name: "PoseAlias".into(),
            span,
            kind: TypeKind::Alias(Ty::Named { id: pose }),
        });
        t.push(TypeDef {
            name: "Other".into(),
            span,
            kind: TypeKind::Struct(vec![]),
        });
        t
    }

    #[test]
    fn aliases_resolve_and_compare_equal() {
        let t = table();
        let pose = Ty::Named { id: TypeId(0) };
        let alias = Ty::Named { id: TypeId(1) };
        let other = Ty::Named { id: TypeId(2) };
        assert!(t.same(&pose, &alias));
        assert!(!t.same(&pose, &other));
        assert_eq!(t.fields(&alias).map(<[Field]>::len), Some(1));
        assert!(t.same(&Ty::Error, &other));
    }

    #[test]
    fn display_is_idl() {
        let t = table();
        let seq = Ty::Sequence {
            elem: Box::new(Ty::Named { id: TypeId(1) }),
            bound: Some(8),
        };
        assert_eq!(t.display(&seq), "sequence<PoseAlias, 8>");
        let arr = Ty::Array {
            elem: Box::new(Ty::String { bound: Some(32) }),
            len: 3,
        };
        assert_eq!(t.display(&arr), "string<32>[3]");
    }
}
