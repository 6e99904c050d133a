//! The port checks of a system file: every name exists, connections go
//! from an out port to an in port of the same IDL type (compared
//! structurally across the two components' type tables), no input is fed
//! twice, and every input is fed (a warning).

use std::collections::BTreeMap;

use genom_model::component::genom3::Port;
use genom_model::component::types::TypeTable;
use genom_model::component::{Component, TypeDef, TypeId, TypeKind};
use genom_model::component::{IdVec, Ty};
use genom_model::diagnostic::{closest, quote};
use genom_model::{Code, Diagnostic, Span};

use crate::description::{Endpoint, SystemFile};

/// A resolved port: the component's name and the port.
pub type Resolved<'a> = (&'a str, &'a Port, &'a IdVec<TypeId, TypeDef>);

/// Looks `e` up among `comps`; an unknown name is a diagnostic.
pub fn resolve<'a>(
    e: &Endpoint,
    comps: &'a BTreeMap<String, Component>,
) -> Result<Resolved<'a>, Diagnostic> {
    let Some((name, c)) = comps.get_key_value(&e.component) else {
        let hint = closest(&e.component, comps.keys().map(String::as_str));
        return Err(Diagnostic::new(
            Code::UnknownSystemName,
            format!("no component {} in the system", quote(&e.component)),
            e.span,
            "not a `[component.NAME]` of this file",
        )
        .with_optional_help(hint.map(|h| format!("did you mean `{h}`?"))));
    };
    let port_name = e.port.as_deref().unwrap_or_default();
    let ports = c
        .genom3
        .as_deref()
        .map(|g| g.ports.as_slice())
        .unwrap_or_default();
    match ports.iter().find(|p| p.name.name == port_name) {
        Some(p) => Ok((name.as_str(), p, &c.types)),
        None => {
            let hint = closest(port_name, ports.iter().map(|p| p.name.name.as_str()));
            Err(Diagnostic::new(
                Code::UnknownSystemName,
                format!("component `{name}` has no port {}", quote(port_name)),
                e.span,
                "no such port",
            )
            .with_optional_help(hint.map(|h| format!("did you mean `{h}`?"))))
        }
    }
}

/// Structural equality of `a` in table `ta` and `b` in table `tb`: base
/// types, strings, sequences and arrays by their bounds and elements,
/// structs and enums by their qualified names and their members.
pub fn same_type(
    ta: &IdVec<TypeId, TypeDef>,
    a: &Ty,
    tb: &IdVec<TypeId, TypeDef>,
    b: &Ty,
    depth: usize,
) -> bool {
    if depth > 32 {
        return true;
    }
    match (ta.resolve(a), tb.resolve(b)) {
        (Ty::Error, _) | (_, Ty::Error) => true,
        (Ty::Base { base: x }, Ty::Base { base: y }) => x == y,
        (Ty::String { bound: x }, Ty::String { bound: y }) => x == y,
        (Ty::Sequence { elem: x, bound: m }, Ty::Sequence { elem: y, bound: n }) => {
            m == n && same_type(ta, x, tb, y, depth + 1)
        }
        (Ty::Array { elem: x, len: m }, Ty::Array { elem: y, len: n }) => {
            m == n && same_type(ta, x, tb, y, depth + 1)
        }
        (Ty::Named { id: x }, Ty::Named { id: y }) => {
            let (Some(dx), Some(dy)) = (ta.def(*x), tb.def(*y)) else {
                return false;
            };
            if dx.name != dy.name {
                return false;
            }
            match (&dx.kind, &dy.kind) {
                (TypeKind::Struct(fx), TypeKind::Struct(fy)) => {
                    fx.len() == fy.len()
                        && fx.iter().zip(fy).all(|(f, g)| {
                            f.name == g.name && same_type(ta, &f.ty, tb, &g.ty, depth + 1)
                        })
                }
                (TypeKind::Enum(vx), TypeKind::Enum(vy)) => {
                    vx.len() == vy.len() && vx.iter().zip(vy).all(|(p, q)| p.0 == q.0)
                }
                _ => false,
            }
        }
        _ => false,
    }
}

/// The port checks of `file` over the loaded `comps`.
pub fn check(file: &SystemFile, comps: &BTreeMap<String, Component>) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    // Per input (component, port): where it is fed from, first span.
    let mut fed: BTreeMap<(String, String), (String, Span)> = BTreeMap::new();
    let mut feed = |to: Resolved<'_>, what: String, span: Span, out: &mut Vec<Diagnostic>| {
        let key = (to.0.to_owned(), to.1.name.name.clone());
        if let Some((before, first)) = fed.get(&key) {
            out.push(
                Diagnostic::new(
                    Code::DuplicateConnection,
                    format!("input `{}.{}` is connected more than once", key.0, key.1),
                    span,
                    format!("fed by {what} here"),
                )
                .with_label(*first, format!("fed by {before} here"))
                .with_help("an in port reads one out port: keep one connection"),
            );
        } else {
            fed.insert(key, (what, span));
        }
    };
    let ty_name = |r: &Resolved<'_>| r.2.display(&r.1.ty);
    for conn in &file.connections {
        let from = resolve(&conn.from, comps);
        let to = resolve(&conn.to, comps);
        let (from, to) = match (from, to) {
            (Ok(f), Ok(t)) => (f, t),
            (f, t) => {
                out.extend(f.err());
                out.extend(t.err());
                continue;
            }
        };
        if !from.1.is_out {
            out.push(Diagnostic::new(
                Code::BadConnection,
                format!(
                    "`{}` is an in port: a connection starts at an out port",
                    conn.from.text()
                ),
                conn.from.span,
                "an in port",
            ));
            continue;
        }
        if to.1.is_out {
            out.push(Diagnostic::new(
                Code::BadConnection,
                format!(
                    "`{}` is an out port: a connection ends at an in port",
                    conn.to.text()
                ),
                conn.to.span,
                "an out port",
            ));
            continue;
        }
        if !same_type(from.2, &from.1.ty, to.2, &to.1.ty, 0) {
            out.push(
                Diagnostic::new(
                    Code::PortTypeMismatch,
                    format!(
                        "`{}` ({}) feeds `{}` ({}), of another type",
                        conn.from.text(),
                        ty_name(&from),
                        conn.to.text(),
                        ty_name(&to)
                    ),
                    conn.to.span,
                    format!("of type `{}`", ty_name(&to)),
                )
                .with_label(conn.from.span, format!("of type `{}`", ty_name(&from))),
            );
        }
        feed(
            to,
            format!("`{}`", conn.from.text()),
            conn.to.span,
            &mut out,
        );
    }
    for ext in &file.externals {
        let mut first: Option<(Resolved<'_>, &Endpoint)> = None;
        for e in &ext.feeds {
            let to = match resolve(e, comps) {
                Ok(t) => t,
                Err(d) => {
                    out.push(d);
                    continue;
                }
            };
            if to.1.is_out {
                out.push(Diagnostic::new(
                    Code::BadConnection,
                    format!(
                        "`{}` is an out port: an external source feeds in ports",
                        e.text()
                    ),
                    e.span,
                    "an out port",
                ));
                continue;
            }
            match &first {
                Some((f, fe)) if !same_type(f.2, &f.1.ty, to.2, &to.1.ty, 0) => out.push(
                    Diagnostic::new(
                        Code::PortTypeMismatch,
                        format!(
                            "external source `{}` feeds `{}` ({}) and `{}` ({}), of different types",
                            ext.name,
                            fe.text(),
                            ty_name(f),
                            e.text(),
                            ty_name(&to)
                        ),
                        e.span,
                        format!("of type `{}`", ty_name(&to)),
                    )
                    .with_label(fe.span, format!("of type `{}`", ty_name(f))),
                ),
                Some(_) => {}
                None => first = Some((to, e)),
            }
            feed(to, format!("external `{}`", ext.name), e.span, &mut out);
        }
    }
    for entry in &file.components {
        let Some(c) = comps.get(&entry.name) else {
            continue;
        };
        let ports = c
            .genom3
            .as_deref()
            .map(|g| g.ports.as_slice())
            .unwrap_or_default();
        for p in ports.iter().filter(|p| !p.is_out) {
            if !fed.contains_key(&(entry.name.clone(), p.name.name.clone())) {
                out.push(
                    Diagnostic::new(
                        Code::UnconnectedInput,
                        format!(
                            "input `{}.{}` is fed by no connection or external source",
                            entry.name, p.name.name
                        ),
                        entry.span,
                        format!("its port `{}` reads nothing", p.name.name),
                    )
                    .with_help(format!(
                        "connect it (`[[connect]]`), or declare its source (`[external.NAME]` with `feeds = [\"{}.{}\"]`)",
                        entry.name, p.name.name
                    )),
                );
            }
        }
    }
    out
}
