//! Lowering the GenoM3 AST into the one model
//! ([`genom_model::component::Component`], with GenoM3-only facts in
//! [`genom_model::component::genom3::Genom3Info`]): IDL types and constants
//! first (`types.rs`), then the component with the interfaces it provides
//! and uses inlined (`component.rs`: ids, ports, tasks, services, codels and
//! their parameters), then GenoM3's static checks on every state machine
//! (`checks.rs`).

mod checks;
mod codels;
mod component;
mod types;

use std::collections::BTreeMap;

use genom_model::component::Component;
use genom_model::limits::Watch;
use genom_model::{Diagnostic, FileId};

use crate::ast::{self, Ast, Export, Statement};
use types::Types;

/// What lowering produces.
#[derive(Debug, Default)]
pub struct LowerReturn {
    /// The component (`None` when the files define none).
    pub component: Option<Component>,
    /// Name-resolution and static-check diagnostics.
    pub diagnostics: Vec<Diagnostic>,
    /// True when a `component` was found.
    pub has_component: bool,
    /// True when an `interface` was found outside the built-in file.
    pub has_interface: bool,
}

/// The closest of `candidates` to `name`, owned (for "did you mean").
pub(crate) fn closest_hint<'a>(
    name: &str,
    candidates: impl IntoIterator<Item = &'a String>,
) -> Option<String> {
    genom_model::diagnostic::closest(name, candidates.into_iter().map(String::as_str))
        .map(str::to_owned)
}

/// Lowers every statement. `builtin` is the file of the built-in `genom`
/// interface (its interface does not make a file interface-only).
pub fn lower(ast: &Ast, builtin: FileId, watch: &Watch) -> LowerReturn {
    let mut types = Types::default();
    let mut components: Vec<&ast::Component> = Vec::new();
    let mut interfaces: BTreeMap<String, &ast::Component> = BTreeMap::new();
    let mut has_interface = false;
    // The files' own `interface genom` (genom3's genom.gen) replaces the
    // built-in one.
    let own_genom = ast.statements.iter().any(|(f, s)| {
        *f != builtin
            && matches!(s, Statement::Component(c) if c.is_interface && c.name.name == "genom")
    });
    for (file, stmt) in ast
        .statements
        .iter()
        .filter(|(f, _)| !(own_genom && *f == builtin))
    {
        match stmt {
            Statement::Idl(d) => types.definition(d, &[]),
            Statement::Component(c) => {
                let scope = [c.name.name.clone()];
                for e in &c.body {
                    if let Export::Idl(d) = e {
                        types.definition(d, &scope);
                    }
                }
                if c.is_interface {
                    // Types named by an interface's services and ports are
                    // checked even when no component provides or uses it.
                    for e in &c.body {
                        match e {
                            Export::Service(svc) => {
                                for p in &svc.params {
                                    if let Some(t) = &p.ty {
                                        types.ty(t, &scope);
                                    }
                                }
                            }
                            Export::Port(port) => {
                                types.ty(&port.ty, &scope);
                            }
                            _ => {}
                        }
                    }
                    has_interface |= *file != builtin;
                    interfaces.entry(c.name.name.clone()).or_insert(c);
                } else {
                    components.push(c);
                }
            }
        }
    }
    let mut diagnostics = Vec::new();
    let first = components.first().copied();
    for extra in components.iter().skip(1) {
        if let Some(first) = first {
            diagnostics.push(crate::diagnostics::duplicate(
                "component",
                &extra.name.name,
                extra.name.span,
                first.name.span,
            ));
        }
    }
    // An interface-only file is still resolved (to report its mistakes),
    // through its interfaces read as a component.
    let target = first.or_else(|| {
        interfaces
            .values()
            .find(|i| {
                ast.statements.iter().any(|(f, s)| {
                    *f != builtin && matches!(s, Statement::Component(c) if std::ptr::eq(c, **i))
                })
            })
            .copied()
    });
    let mut component = None;
    if let Some(target) = target {
        let mut ctx = component::Ctx::new(types, &interfaces);
        // The watch is looked at before each step (lowering the component,
        // its static checks), each linear in the component.
        let stopped = |step: &[&str]| {
            watch
                .exceeded()
                .map(|limit| genom_model::limits::static_stopped(target.name.span, limit, step))
        };
        if let Some(d) = stopped(&["the component's resolution", "the static checks"]) {
            ctx.diags.push(d);
        } else {
            ctx.component(target);
            match stopped(&["the static checks"]) {
                Some(d) => ctx.diags.push(d),
                None => checks::run(&mut ctx),
            }
        }
        let (c, d) = ctx.finish();
        diagnostics.extend(d);
        if first.is_some() {
            component = Some(c);
        }
    } else {
        diagnostics.extend(types.diagnostics);
    }
    LowerReturn {
        component,
        diagnostics,
        has_component: first.is_some(),
        has_interface,
    }
}
