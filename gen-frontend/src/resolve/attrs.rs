//! Attribute lists: which attributes each kind of block accepts, and typed
//! access to them once duplicates and misplaced ones are reported.

use crate::ast::{
    AttrValue, Attribute, Call, DataRef, DurationLit, Ident, IntLit, Param, SizeLit, StrLit,
    TypedName,
};

use super::Resolver;
use crate::checks::invalid_attribute;

/// Attributes of a `component`.
pub(super) const COMPONENT: &[&str] = &["category", "lang", "version", "doc", "credentials"];
/// Attributes of a `thread`.
pub(super) const THREAD: &[&str] = &["priority", "period", "stack", "start", "stop", "doc"];
/// Attributes of a `service`.
pub(super) const SERVICE: &[&str] = &[
    "doc",
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
];
/// Attributes of a codel (`next` and `on-inter` are then checked per kind).
pub(super) const CODEL: &[&str] = &["exec", "update", "on-inter", "max-time", "next", "doc"];

/// The accepted attributes of one block, at most one per name.
pub(super) struct Attrs<'a> {
    list: Vec<&'a Attribute>,
}

impl Resolver {
    /// Keeps the first of each allowed attribute; reports misplaced and
    /// repeated ones. Unknown names were reported by the parser.
    pub(super) fn attrs<'a>(
        &mut self,
        attributes: &'a [Attribute],
        place: &str,
        allowed: &[&str],
    ) -> Attrs<'a> {
        let mut list: Vec<&'a Attribute> = Vec::new();
        for a in attributes {
            if matches!(a.value, AttrValue::Unknown(_)) {
                continue;
            }
            if !allowed.contains(&a.name.name.as_str()) {
                self.report(invalid_attribute::not_allowed(
                    &a.name.name,
                    a.name.span,
                    place,
                    allowed,
                ));
                continue;
            }
            if let Some(first) = list.iter().find(|f| f.name.name == a.name.name) {
                self.report(invalid_attribute::given_twice(
                    &a.name.name,
                    a.name.span,
                    first.name.span,
                ));
                continue;
            }
            list.push(a);
        }
        Attrs { list }
    }
}

impl<'a> Attrs<'a> {
    /// The attribute with this name.
    pub(super) fn get(&self, name: &str) -> Option<&'a Attribute> {
        self.list.iter().copied().find(|a| a.name.name == name)
    }

    fn value(&self, name: &str) -> Option<&'a AttrValue> {
        self.get(name).map(|a| &a.value)
    }

    pub(super) fn string(&self, name: &str) -> Option<&'a StrLit> {
        match self.value(name)? {
            AttrValue::Str(s) => Some(s),
            _ => None,
        }
    }

    pub(super) fn ident(&self, name: &str) -> Option<&'a Ident> {
        match self.value(name)? {
            AttrValue::Ident(i) => Some(i),
            _ => None,
        }
    }

    pub(super) fn idents(&self, name: &str) -> &'a [Ident] {
        match self.value(name) {
            Some(AttrValue::Idents(v)) => v,
            _ => &[],
        }
    }

    pub(super) fn credentials(&self) -> Option<&'a [Ident]> {
        match self.value("credentials")? {
            AttrValue::Credentials(v) => Some(v),
            _ => None,
        }
    }

    pub(super) fn integer(&self, name: &str) -> Option<&'a IntLit> {
        match self.value(name)? {
            AttrValue::Integer(i) => Some(i),
            _ => None,
        }
    }

    pub(super) fn duration(&self, name: &str) -> Option<&'a DurationLit> {
        match self.value(name)? {
            AttrValue::Duration(d) => Some(d),
            _ => None,
        }
    }

    pub(super) fn size(&self, name: &str) -> Option<&'a SizeLit> {
        match self.value(name)? {
            AttrValue::Size(s) => Some(s),
            _ => None,
        }
    }

    pub(super) fn call(&self) -> Option<&'a Call> {
        match self.value("exec")? {
            AttrValue::Call(c) => Some(c),
            _ => None,
        }
    }

    pub(super) fn params(&self, name: &str) -> &'a [Param] {
        match self.value(name) {
            Some(AttrValue::Params(v)) => v,
            _ => &[],
        }
    }

    pub(super) fn typed(&self, name: &str) -> &'a [TypedName] {
        match self.value(name) {
            Some(AttrValue::Typed(v)) => v,
            _ => &[],
        }
    }

    pub(super) fn data_refs(&self, name: &str) -> &'a [DataRef] {
        match self.value(name) {
            Some(AttrValue::DataRefs(v)) => v,
            _ => &[],
        }
    }
}
