//! Lowering details through the public API: constant evaluation with IDL
//! precedence, scoping, IDL types in the model, service relations, codel
//! parameter resolution order.

#![allow(clippy::unwrap_used)]

use std::path::Path;

use genom_model::component::genom3::ParamSource;
use genom_model::component::{Component, DataRoot, TypeKind, Value};
use genom_model::{Code, Severity};
use genom3_frontend::{Genom3Return, MemoryLoader, load_with};

fn load(text: &str) -> Genom3Return {
    load_with(
        Path::new("t.gen"),
        text.to_owned(),
        &[],
        &MemoryLoader::default(),
    )
}

fn component(text: &str) -> Component {
    let out = load(text);
    let errors: Vec<_> = out
        .diagnostics
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .collect();
    assert!(errors.is_empty(), "{errors:?}");
    out.component.unwrap()
}

fn constant(c: &Component, name: &str) -> Option<Value> {
    c.constants
        .iter()
        .find(|k| k.name == name)
        .unwrap()
        .value
        .clone()
}

#[test]
fn constants_follow_idl_precedence_and_scopes() {
    let c = component(
        "module m { const long a = 2 + 3 * 4; const long b = (2 + 3) * 4; const long c = 1 << 4 | 1; \
         enum e { x, y }; const long d = -a % 5; };\n\
         const double f = m::a / 4.0;\ncomponent k { const long g = m::c - 1; };\n",
    );
    assert_eq!(constant(&c, "m::a"), Some(Value::Int(14)));
    assert_eq!(constant(&c, "m::b"), Some(Value::Int(20)));
    assert_eq!(constant(&c, "m::c"), Some(Value::Int(17)));
    assert_eq!(constant(&c, "m::d"), Some(Value::Int(-4)));
    assert_eq!(constant(&c, "f"), Some(Value::Float(3.5)));
    assert_eq!(constant(&c, "k::g"), Some(Value::Int(16)));
}

#[test]
fn idl_types_reach_the_model() {
    let c = component(
        "module m { struct p { double x; }; struct q; struct q { p a[2][3]; sequence<p, 4> s; optional<p> o; }; \
         union u switch (long) { case 1: double d; default: p q; }; native n; exception ex { long code; }; };\n\
         component k { };\n",
    );
    let def = |n: &str| c.types.values().find(|d| d.name == n).unwrap().kind.clone();
    let TypeKind::Struct(q) = def("m::q") else {
        panic!("struct")
    };
    assert_eq!(q.len(), 3, "forward declaration completed");
    let TypeKind::Struct(u) = def("m::u") else {
        panic!("union as struct")
    };
    assert_eq!(u.len(), 2);
    assert!(matches!(
        def("m::n"),
        TypeKind::Alias(genom_model::component::Ty::Error)
    ));
    let g = c.genom3.as_deref().unwrap();
    assert!(
        g.exceptions
            .iter()
            .any(|e| e.name.name == "m::ex" && e.fields.len() == 1)
    );
}

#[test]
fn service_relations_are_resolved() {
    let c = component(
        "component k {\n  task t { period 1 s; };\n  activity a() { task t; codel<start> f() yield ether; };\n  \
         activity b() { task t; codel<start> g() yield ether; after a; before c; interrupts a; };\n  \
         function c() { interrupts all; };\n};\n",
    );
    let b = c.service_named("b").unwrap();
    let a = c.service_named("a").unwrap();
    assert_eq!(
        c.services[b].stops.iter().map(|r| r.id).collect::<Vec<_>>(),
        [a]
    );
    let cc = c.service_named("c").unwrap();
    // `interrupts all`: every service (built-in ones included).
    assert_eq!(c.services[cc].stops.len(), c.services.len());
    let g = c.genom3.as_deref().unwrap();
    let info = g.services.iter().find(|s| s.service == b).unwrap();
    assert_eq!(info.after[0].id, a);
    assert_eq!(info.before[0].id, cc);
}

#[test]
fn codel_parameters_resolve_locals_then_ids_then_ports() {
    let c = component(
        "typedef double real;\ncomponent k {\n  ids { double x; double p; };\n  port out real p;\n  port in real q;\n  \
         task t { period 1 s; };\n  activity a(in double x) {\n    task t;\n    local long n;\n    \
         codel<start> f(local in x, out n, ids inout p, in q, ids in x::y, port out p::pp) yield ether;\n  };\n};\n",
    );
    let g = c.genom3.as_deref().unwrap();
    let a = c.service_named("a").unwrap();
    let start = c.services[a].start.unwrap();
    let info = g.codels.iter().find(|i| i.codel == start).unwrap();
    let sources: Vec<ParamSource> = info.fsm.params.iter().map(|p| p.source).collect();
    use ParamSource::*;
    assert_eq!(sources, [Local, Local, Ids, Port, Ids, Port]);
    assert_eq!(info.fsm.params[4].name, "y");
    let args = &c.codels[start].call.as_ref().unwrap().args;
    assert!(matches!(
        args[0].data.as_ref().unwrap().root,
        DataRoot::Param {
            output: false,
            index: 0,
            ..
        }
    ));
    assert!(args[0].is_const && !args[2].is_const);
}

#[test]
fn an_ambiguous_unqualified_parameter_needs_a_source() {
    let out = load(
        "component k {\n  ids { double x; };\n  task t { period 1 s; };\n  activity a(in double x) {\n    \
         task t;\n    codel<start> f(in x) yield ether;\n  };\n};\n",
    );
    let d = out
        .diagnostics
        .iter()
        .find(|d| d.code == Code::MissingSource)
        .unwrap();
    assert_eq!(
        d.labels[0].message,
        "`x` is a service parameter or local and an ids member"
    );
}

#[test]
fn unknown_codel_parameters_suggest_a_name() {
    let out = load(
        "component k {\n  ids { double speed; };\n  task t { period 1 s; codel<start> f(in sped) yield ether; };\n};\n",
    );
    let d = out
        .diagnostics
        .iter()
        .find(|d| d.code == Code::UnknownData)
        .unwrap();
    assert_eq!(d.help.as_deref(), Some("did you mean `speed`?"));
}

#[test]
fn an_empty_initializer_keeps_every_member_default() {
    let text = "struct point { double x; double y; };\n\
        component k {\n\
          ids { point p; };\n\
          task t { period 10 ms; };\n\
          attribute set_p(in p = {} : \"where\");\n\
          activity go(in point to = {}, in long n = 3) { task t; codel<start> k_go(in to) yield ether; };\n\
        };\n";
    let out = load(text);
    assert!(out.diagnostics.is_empty(), "{:?}", out.diagnostics);
    let c = out.component.unwrap();
    let set_p = &c.services[c.service_named("set_p").unwrap()];
    assert_eq!(set_p.inputs.len(), 1);
    assert_eq!(set_p.inputs[0].default, None);
    assert_eq!(set_p.inputs[0].doc.as_deref(), Some("where"));
    let go = &c.services[c.service_named("go").unwrap()];
    let defaults: Vec<_> = go
        .inputs
        .iter()
        .map(|p| (p.name.name.as_str(), p.default.clone()))
        .collect();
    assert_eq!(defaults, [("to", None), ("n", Some(Value::Int(3)))]);
}

#[test]
fn a_comma_without_values_in_braces_is_a_syntax_error_at_the_comma() {
    let text = "component k { ids { long n; }; attribute set_n(in n = {,}); };\n";
    let out = load(text);
    let syntax: Vec<_> = out
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::Syntax)
        .collect();
    assert_eq!(syntax.len(), 1, "{:?}", out.diagnostics);
    assert_eq!(syntax[0].message, "expected `}` or a value, found `,`");
    let comma = u32::try_from(text.find("{,}").unwrap() + 1).unwrap();
    let span = syntax[0].labels[0].span;
    assert_eq!((span.start, span.end), (comma, comma + 1));
}
