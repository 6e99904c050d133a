//! `recursive-type` (error): a named type that contains itself by value (a
//! struct with a field of its own type, directly or through other structs,
//! fixed arrays and typedefs, or a typedef of itself). No value of it is
//! finite, so no IDS member, port or parameter of that type can exist. A
//! type reached through a `sequence` is not contained by value: a sequence
//! may be empty, as in IDL.

use genom_model::component::{Component, Idx, Ty, TypeId, TypeKind};
use genom_model::{Code, Diagnostic, Span};
use petgraph::algo::tarjan_scc;
use petgraph::graph::{DiGraph, NodeIndex};

use super::registry::{Applies, StaticCheck};

/// `genom-check explain recursive-type`.
pub const EXPLANATION: &str = r#"A type contains itself by value: a struct has a field of its own type
(directly, or through other structs, fixed arrays and typedefs), or a
typedef names itself. A value of such a type would be infinite, so the
component's data cannot be laid out, initialised or exported. The cycle is
labelled field by field.

A type reached through a `sequence<...>` is not contained by value (a
sequence may be empty), so a tree of sequences is allowed.

Example:

```
typedef struct node { node next; } node;   // recursive-type
typedef struct list { sequence<list> tail; } list;   // fine
```

LANGUAGE.md does not list this case; genom-check reports it with its own
code (docs/language.md)."#;

/// One step of a cycle: `from` holds `to` by value, written at `span`.
struct Edge {
    span: Span,
    text: String,
}

/// The registry's entry ([`super::STATIC_CHECKS`]).
pub const CHECK: StaticCheck = StaticCheck {
    name: "recursive types",
    applies: Applies::Always,
    run: check,
    codes: &[(Code::RecursiveType, EXPLANATION)],
};

/// Every cycle of by-value containment among the named types, one
/// diagnostic per cycle, at its first-declared type.
pub fn check(c: &Component) -> Vec<Diagnostic> {
    let mut graph: DiGraph<TypeId, Edge> = DiGraph::new();
    let nodes: Vec<NodeIndex> = c.types.iter().map(|(id, _)| graph.add_node(id)).collect();
    for (id, def) in c.types.iter() {
        for (held, span, text) in holds(c, &def.kind, &def.name, def.span) {
            if let (Some(&a), Some(&b)) = (nodes.get(id.index()), nodes.get(held.index())) {
                graph.add_edge(a, b, Edge { span, text });
            }
        }
    }
    let mut cycles: Vec<Vec<NodeIndex>> = tarjan_scc(&graph)
        .into_iter()
        .filter(|scc| scc.len() > 1 || graph.contains_edge(scc[0], scc[0]))
        .map(|mut scc| {
            scc.sort_by_key(|&n| graph[n]);
            scc
        })
        .collect();
    cycles.sort_by_key(|scc| graph[scc[0]]);
    cycles.iter().map(|scc| cycle(c, &graph, scc)).collect()
}

/// The diagnostic of one strongly connected set of types.
fn cycle(c: &Component, graph: &DiGraph<TypeId, Edge>, scc: &[NodeIndex]) -> Diagnostic {
    let first = &c.types[graph[scc[0]]];
    let others: Vec<String> = scc[1..]
        .iter()
        .map(|&n| format!("`{}`", c.types[graph[n]].name))
        .collect();
    let through = if others.is_empty() {
        String::new()
    } else {
        format!(" through {}", others.join(", "))
    };
    let mut d = Diagnostic::new(
        Code::RecursiveType,
        format!("the type `{}` contains itself{through}", first.name),
        first.span,
        "no value of this type is finite",
    );
    let mut edges: Vec<&Edge> = scc
        .iter()
        .flat_map(|&n| graph.edges(n))
        .filter(|e| scc.contains(&petgraph::visit::EdgeRef::target(e)))
        .map(|e| e.weight())
        .collect();
    edges.sort_by_key(|e| e.span);
    for e in edges {
        d = d.with_label(e.span, e.text.clone());
    }
    d.with_help(
        "hold the inner value through a `sequence<...>` (which may be empty), or remove the field",
    )
}

/// The named types a definition holds by value, each with where and how.
fn holds(c: &Component, kind: &TypeKind, name: &str, span: Span) -> Vec<(TypeId, Span, String)> {
    let mut out = Vec::new();
    match kind {
        TypeKind::Struct(fields) => {
            for f in fields {
                for id in by_value(&f.ty) {
                    let text = format!("`{name}.{}` holds a `{}`", f.name, c.types[id].name);
                    out.push((id, f.span, text));
                }
            }
        }
        TypeKind::Alias(ty) => {
            for id in by_value(ty) {
                out.push((id, span, format!("`{name}` is a `{}`", c.types[id].name)));
            }
        }
        TypeKind::Enum(_) => {}
    }
    out
}

/// The named types a type expression holds by value (not through
/// sequences or strings).
fn by_value(ty: &Ty) -> Vec<TypeId> {
    match ty {
        Ty::Named { id } => vec![*id],
        Ty::Array { elem, .. } => by_value(elem),
        Ty::Base { .. } | Ty::String { .. } | Ty::Sequence { .. } | Ty::Error => Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use genom_model::Code;

    use crate::testing::{self, HEADER};

    fn found(src: &str) -> Vec<String> {
        testing::check(src)
            .diagnostics
            .iter()
            .filter(|d| d.code == Code::RecursiveType)
            .map(|d| {
                let labels: Vec<&str> = d.labels.iter().map(|l| l.message.as_str()).collect();
                format!("{} [{}]", d.message, labels.join("; "))
            })
            .collect()
    }

    #[test]
    fn a_struct_holding_itself() {
        let src = format!("{HEADER}typedef struct X {{ long n; X x; }} X;\nids d {{ X a; }}\n");
        assert_eq!(
            found(&src),
            ["the type `X` contains itself [no value of this type is finite; `X.x` holds a `X`]"]
        );
    }

    #[test]
    fn a_typedef_of_itself_and_a_cycle_through_an_array() {
        let src = format!(
            "{HEADER}typedef T T;\nstruct A {{ B b[2]; }};\nstruct B {{ A a; }};\nids d {{ T t; A a; }}\n"
        );
        let all = found(&src);
        assert_eq!(all.len(), 2, "{all:?}");
        assert!(
            all.iter()
                .any(|d| d.starts_with("the type `T` contains itself")),
            "{all:?}"
        );
        assert!(
            all.iter()
                .any(|d| d.starts_with("the type `A` contains itself through `B`")),
            "{all:?}"
        );
    }

    #[test]
    fn recursion_through_a_sequence_is_allowed() {
        let src = format!(
            "{HEADER}struct tree {{ long v; sequence<tree> kids; }};\nids d {{ tree t; }}\n"
        );
        assert!(found(&src).is_empty());
        assert_eq!(testing::count(&src, Code::RecursiveType), 0);
    }

    #[test]
    fn snapshot() {
        let src = format!("{HEADER}struct A {{ B b; }};\nstruct B {{ A a; }};\nids d {{ A a; }}\n");
        insta::assert_snapshot!(testing::render(&src));
    }
}
