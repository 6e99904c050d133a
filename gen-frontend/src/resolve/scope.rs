//! IDL scopes: qualified names of types, enumerators and constants, and the
//! lookup rule of IDL (from the current module outwards; `::m::T` is
//! absolute).

use std::collections::BTreeMap;

use crate::ast::ScopedName;
use genom_model::Span;
use genom_model::component::TypeId;

/// What a qualified IDL name designates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Symbol {
    /// A named type.
    Type(TypeId),
    /// A value of this enum type.
    Enumerator(TypeId),
    /// A constant (index in the component's constants).
    Const(usize),
}

/// Every IDL name, by qualified name without leading `::` (`geo::Pose`).
#[derive(Debug, Default)]
pub(super) struct Scopes {
    symbols: BTreeMap<String, (Symbol, Span)>,
}

/// `scope::name` without leading `::`.
pub(super) fn qualify(scope: &[String], name: &str) -> String {
    if scope.is_empty() {
        name.to_owned()
    } else {
        format!("{}::{name}", scope.join("::"))
    }
}

impl Scopes {
    /// Declares a name; returns the span of the earlier definition when the
    /// name is already taken in that scope.
    pub(super) fn declare(
        &mut self,
        qualified: String,
        symbol: Symbol,
        span: Span,
    ) -> Result<(), Span> {
        match self.symbols.get(&qualified) {
            Some(&(_, first)) => Err(first),
            None => {
                self.symbols.insert(qualified, (symbol, span));
                Ok(())
            }
        }
    }

    /// Looks a name up from `scope` outwards; returns the qualified name and
    /// symbol.
    pub(super) fn lookup(&self, scope: &[String], name: &ScopedName) -> Option<(&str, Symbol)> {
        let written = name.parts.join("::");
        let depths: Vec<usize> = if name.absolute {
            vec![0]
        } else {
            (0..=scope.len()).rev().collect()
        };
        depths.into_iter().find_map(|depth| {
            let key = qualify(&scope[..depth], &written);
            self.symbols
                .get_key_value(&key)
                .map(|(k, &(s, _))| (k.as_str(), s))
        })
    }

    /// Qualified names of every symbol accepted by `keep`, for suggestions.
    pub(super) fn names(&self, keep: impl Fn(Symbol) -> bool) -> Vec<&str> {
        self.symbols
            .iter()
            .filter(|(_, (s, _))| keep(*s))
            .map(|(k, _)| k.as_str())
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn name(text: &str) -> ScopedName {
        ScopedName {
            absolute: text.starts_with("::"),
            parts: text
                .split("::")
                .filter(|p| !p.is_empty())
                .map(str::to_owned)
                .collect(),
            span: Span::default(),
        }
    }

    #[test]
    fn lookup_goes_from_the_current_module_outwards() {
        let mut s = Scopes::default();
        s.declare("T".into(), Symbol::Type(TypeId(0)), Span::default())
            .unwrap();
        s.declare("m::T".into(), Symbol::Type(TypeId(1)), Span::default())
            .unwrap();
        let inner = vec!["m".to_owned(), "n".to_owned()];
        assert_eq!(
            s.lookup(&inner, &name("T")).map(|x| x.1),
            Some(Symbol::Type(TypeId(1)))
        );
        assert_eq!(
            s.lookup(&inner, &name("::T")).map(|x| x.1),
            Some(Symbol::Type(TypeId(0)))
        );
        assert_eq!(
            s.lookup(&[], &name("m::T")).map(|x| x.1),
            Some(Symbol::Type(TypeId(1)))
        );
        assert_eq!(s.lookup(&[], &name("n::T")), None);
        assert!(
            s.declare("m::T".into(), Symbol::Const(0), Span::default())
                .is_err()
        );
    }
}
