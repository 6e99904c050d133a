//! The builders of the IDL part of the grammar: typed parameters and
//! names, type specifications and declarators, constant expressions, and
//! the IDL definitions (typedefs, structs, enums, constants, modules).

use super::{Builder, MAX_OPERATORS, P, build_boolean, find};
use crate::ast::*;
use crate::grammar::Rule;

impl Builder<'_> {
    pub(super) fn build_typed_param(&self, p: &P<'_>) -> ParamTarget {
        let span = self.span(p);
        let ty = find(p, Rule::type_spec).map_or(TypeSpec::Base(BaseType::Double, span), |c| {
            self.build_type_spec(&c)
        });
        let decl = find(p, Rule::declarator).map_or_else(
            || Declarator {
                name: Ident::new("", span),
                dims: vec![],
                span,
            },
            |c| self.build_declarator(&c),
        );
        ParamTarget::Typed(ty, decl)
    }

    pub(super) fn build_typed_names(&self, p: &P<'_>) -> Vec<TypedName> {
        p.clone()
            .into_inner()
            .filter(|c| c.as_rule() == Rule::typed_name)
            .map(|c| self.build_typed_name(&c))
            .collect()
    }

    fn build_typed_name(&self, p: &P<'_>) -> TypedName {
        let span = self.span(p);
        let ty = find(p, Rule::type_spec).map_or(TypeSpec::Base(BaseType::Double, span), |c| {
            self.build_type_spec(&c)
        });
        TypedName {
            ty,
            name: self.first_ident(p),
            span,
        }
    }

    pub(super) fn build_type_spec(&self, p: &P<'_>) -> TypeSpec {
        let span = self.span(p);
        let Some(c) = p.clone().into_inner().next() else {
            return TypeSpec::Base(BaseType::Double, span);
        };
        match c.as_rule() {
            Rule::base_type => TypeSpec::Base(build_base_type(&c), span),
            Rule::string_type => TypeSpec::String(self.bound(&c), span),
            Rule::sequence_type => {
                let elem = find(&c, Rule::type_spec)
                    .map_or(TypeSpec::Base(BaseType::Double, span), |e| {
                        self.build_type_spec(&e)
                    });
                TypeSpec::Sequence(Box::new(elem), self.bound(&c), span)
            }
            _ => TypeSpec::Named(self.build_scoped_name(&c)),
        }
    }

    fn bound(&self, p: &P<'_>) -> Option<Box<ConstExpr>> {
        find(p, Rule::const_expr).map(|c| Box::new(self.build_top_const_expr(&c)))
    }

    pub(super) fn build_declarator(&self, p: &P<'_>) -> Declarator {
        let dims = p
            .clone()
            .into_inner()
            .filter(|c| c.as_rule() == Rule::array_dim)
            .filter_map(|c| find(&c, Rule::const_expr))
            .map(|c| self.build_top_const_expr(&c))
            .collect();
        Declarator {
            name: self.first_ident(p),
            dims,
            span: self.span(p),
        }
    }

    /// A whole constant expression (not a sub-expression), refused with a
    /// placeholder when it has more than [`MAX_OPERATORS`] operators.
    fn build_top_const_expr(&self, p: &P<'_>) -> ConstExpr {
        let operators = p
            .clone()
            .into_inner()
            .flatten()
            .filter(|c| {
                matches!(
                    c.as_rule(),
                    Rule::plus | Rule::minus | Rule::star | Rule::slash | Rule::percent
                )
            })
            .count();
        if operators > MAX_OPERATORS {
            let span = self.span(p);
            self.too_long.borrow_mut().push(span);
            return ConstExpr::Bool(false, span);
        }
        self.build_const_expr(p)
    }

    /// `const_expr` and `const_term`: left-associative operator chains.
    fn build_const_expr(&self, p: &P<'_>) -> ConstExpr {
        let mut acc: Option<ConstExpr> = None;
        let mut op = BinOp::Add;
        for c in p.clone().into_inner() {
            let operand = match c.as_rule() {
                Rule::const_term => self.build_const_expr(&c),
                Rule::const_factor => self.build_const_factor(&c),
                Rule::plus | Rule::minus | Rule::star | Rule::slash | Rule::percent => {
                    op = build_bin_op(&c);
                    continue;
                }
                _ => continue,
            };
            acc = Some(match acc {
                None => operand,
                Some(lhs) => {
                    let span = lhs.span().to(operand.span());
                    ConstExpr::Binary(Box::new(lhs), op, Box::new(operand), span)
                }
            });
        }
        acc.unwrap_or(ConstExpr::Bool(false, self.span(p)))
    }

    fn build_const_factor(&self, p: &P<'_>) -> ConstExpr {
        let span = self.span(p);
        let mut negate = false;
        for c in p.clone().into_inner() {
            let expr = match c.as_rule() {
                Rule::minus => {
                    negate = true;
                    continue;
                }
                Rule::number => ConstExpr::Number(self.build_number(&c)),
                Rule::string => ConstExpr::Str(self.build_string(&c)),
                Rule::boolean => ConstExpr::Bool(build_boolean(&c), self.span(&c)),
                Rule::scoped_name => ConstExpr::Name(self.build_scoped_name(&c)),
                Rule::const_expr => self.build_const_expr(&c),
                Rule::const_factor => self.build_const_factor(&c),
                _ => continue,
            };
            return if negate {
                ConstExpr::Neg(Box::new(expr), span)
            } else {
                expr
            };
        }
        ConstExpr::Bool(false, span)
    }

    pub(super) fn build_idl_def(&mut self, p: P<'_>) -> Option<Item> {
        let inner = p.into_inner().next()?;
        Some(match inner.as_rule() {
            Rule::typedef_def => Item::Typedef(self.build_typedef_def(&inner)),
            Rule::struct_def => Item::Struct(self.build_struct_def(&inner)),
            Rule::enum_def => Item::Enum(self.build_enum_def(&inner)),
            Rule::const_def => Item::Const(self.build_const_def(&inner)),
            _ => Item::Module(self.build_module_def(&inner)),
        })
    }

    fn build_typedef_def(&self, p: &P<'_>) -> Typedef {
        let span = self.span(p);
        let mut target = TypedefTarget::Type(TypeSpec::Base(BaseType::Double, span));
        let mut declarators = vec![];
        for c in p.clone().into_inner() {
            match c.as_rule() {
                Rule::struct_type => target = self.build_struct_type(&c),
                Rule::enum_type => target = self.build_enum_type(&c),
                Rule::type_spec => target = TypedefTarget::Type(self.build_type_spec(&c)),
                Rule::declarator => declarators.push(self.build_declarator(&c)),
                _ => {}
            }
        }
        Typedef {
            target,
            declarators,
            span,
        }
    }

    fn build_struct_type(&self, p: &P<'_>) -> TypedefTarget {
        let tag = find(p, Rule::ident).map(|c| self.ident(&c));
        let members = find(p, Rule::struct_body)
            .map(|c| self.build_struct_body(&c))
            .unwrap_or_default();
        TypedefTarget::Struct(tag, members)
    }

    fn build_enum_type(&self, p: &P<'_>) -> TypedefTarget {
        let tag = find(p, Rule::ident).map(|c| self.ident(&c));
        let values = find(p, Rule::enum_body)
            .map(|c| self.idents(&c))
            .unwrap_or_default();
        TypedefTarget::Enum(tag, values)
    }

    fn build_struct_def(&self, p: &P<'_>) -> StructDef {
        let members = find(p, Rule::struct_body)
            .map(|c| self.build_struct_body(&c))
            .unwrap_or_default();
        StructDef {
            name: self.first_ident(p),
            members,
            span: self.span(p),
        }
    }

    fn build_struct_body(&self, p: &P<'_>) -> Vec<StructMember> {
        p.clone()
            .into_inner()
            .filter(|c| c.as_rule() == Rule::struct_member)
            .map(|c| self.build_struct_member(&c))
            .collect()
    }

    fn build_struct_member(&self, p: &P<'_>) -> StructMember {
        let span = self.span(p);
        let ty = find(p, Rule::type_spec).map_or(TypeSpec::Base(BaseType::Double, span), |c| {
            self.build_type_spec(&c)
        });
        let declarators = p
            .clone()
            .into_inner()
            .filter(|c| c.as_rule() == Rule::declarator)
            .map(|c| self.build_declarator(&c))
            .collect();
        StructMember {
            ty,
            declarators,
            span,
        }
    }

    fn build_enum_def(&self, p: &P<'_>) -> EnumDef {
        let enumerators = find(p, Rule::enum_body)
            .map(|c| self.idents(&c))
            .unwrap_or_default();
        EnumDef {
            name: self.first_ident(p),
            enumerators,
            span: self.span(p),
        }
    }

    fn build_const_def(&self, p: &P<'_>) -> ConstDef {
        let span = self.span(p);
        let ty = find(p, Rule::type_spec).map_or(TypeSpec::Base(BaseType::Long, span), |c| {
            self.build_type_spec(&c)
        });
        let value = find(p, Rule::const_expr).map_or(ConstExpr::Bool(false, span), |c| {
            self.build_top_const_expr(&c)
        });
        ConstDef {
            ty,
            name: self.first_ident(p),
            value,
            span,
        }
    }

    fn build_module_def(&mut self, p: &P<'_>) -> ModuleDef {
        let items = p
            .clone()
            .into_inner()
            .filter(|c| c.as_rule() == Rule::idl_def)
            .filter_map(|c| self.build_idl_def(c))
            .collect();
        ModuleDef {
            name: self.first_ident(p),
            items,
            span: self.span(p),
        }
    }

    pub(super) fn build_scoped_name(&self, p: &P<'_>) -> ScopedName {
        let text = p.as_str();
        let absolute = text.starts_with("::");
        let parts = text
            .split("::")
            .filter(|s| !s.is_empty())
            .map(str::to_owned)
            .collect();
        ScopedName {
            absolute,
            parts,
            span: self.span(p),
        }
    }
}

fn build_bin_op(p: &P<'_>) -> BinOp {
    match p.as_rule() {
        Rule::plus => BinOp::Add,
        Rule::minus => BinOp::Sub,
        Rule::star => BinOp::Mul,
        Rule::slash => BinOp::Div,
        _ => BinOp::Rem,
    }
}

fn build_base_type(p: &P<'_>) -> BaseType {
    let words = words_outside_comments(p.as_str());
    match words.as_slice() {
        ["unsigned", "long", "long"] => BaseType::ULongLong,
        ["unsigned", "long"] => BaseType::ULong,
        ["unsigned", "short"] => BaseType::UShort,
        ["long", "long"] => BaseType::LongLong,
        ["long"] => BaseType::Long,
        ["short"] => BaseType::Short,
        ["float"] => BaseType::Float,
        ["char"] => BaseType::Char,
        ["boolean"] => BaseType::Boolean,
        ["octet"] => BaseType::Octet,
        _ => BaseType::Double,
    }
}

/// The blank-separated words of a multi-word base type, skipping the
/// comments the grammar allows between them (`unsigned /* c */ long`).
fn words_outside_comments(text: &str) -> Vec<&str> {
    let mut words = Vec::new();
    let mut rest = text;
    while !rest.is_empty() {
        rest = rest.trim_start();
        if let Some(after) = rest.strip_prefix("/*") {
            rest = after.split_once("*/").map_or("", |(_, r)| r);
        } else if let Some(after) = rest.strip_prefix("//") {
            rest = after.split_once('\n').map_or("", |(_, r)| r);
        } else {
            let end = rest
                .find(|c: char| c.is_whitespace() || c == '/')
                .unwrap_or(rest.len());
            let (word, after) = rest.split_at(end);
            if word.is_empty() {
                // A lone `/` cannot occur in a base type; skip it defensively.
                rest = &rest[1..];
            } else {
                words.push(word);
                rest = after;
            }
        }
    }
    words
}
