//! Name resolution: turns the AST of a component (and its includes) into the
//! resolved [`Component`] model, reporting every resolution, structure and
//! type diagnostic on the way. Resolution never stops at an error: an
//! unresolved reference is left out of the model (it has been diagnosed),
//! and the rest is resolved as usual.
//!
//! Phases, in order: IDL declarations (types, enumerators, constants, in all
//! files, by module scope), the component item, data blocks, threads,
//! service names and codel names (so that references resolve in any
//! order), then service and codel bodies.

mod attrs;
mod codels;
mod data;
mod idl;
mod scope;
mod services;
mod values;

use std::collections::BTreeMap;

use crate::Ast;
use crate::ast::{self, Item};
use genom_model::component::{
    Component, DEFAULT_CREDENTIALS, Named, ServiceId, StructureId, ThreadId,
};
use genom_model::{Diagnostic, Span};

use crate::checks::{duplicate_definition, missing_component};
use scope::Scopes;

/// The resolved component and every diagnostic found while resolving.
#[derive(Debug, Clone, Default)]
pub struct ResolveReturn {
    /// The model (possibly partial when there were errors).
    pub component: Component,
    /// Resolution, structure and type diagnostics.
    pub diagnostics: Vec<Diagnostic>,
    /// Whether the file had a `component` item.
    pub has_component: bool,
}

/// Resolves a parsed component. `file_start` is where the checked file
/// starts (for `missing-component`).
pub fn resolve(ast: &Ast, file_start: Span) -> ResolveReturn {
    let mut r = Resolver {
        c: Component::default(),
        diags: Vec::new(),
        scopes: Scopes::default(),
        names: Names::default(),
        consts: idl::Consts::default(),
    };
    idl::declare_all(&mut r, ast);
    let has_component = r.component(ast, file_start);
    r.data_blocks(ast);
    r.threads(ast);
    let services: Vec<&ast::Service> = ast
        .items()
        .filter_map(|i| {
            if let Item::Service(s) = i {
                Some(s)
            } else {
                None
            }
        })
        .collect();
    services::resolve_services(&mut r, &services);
    ResolveReturn {
        component: r.c,
        diagnostics: r.diags,
        has_component,
    }
}

/// Name tables of things outside IDL scopes.
#[derive(Debug, Default)]
pub(crate) struct Names {
    /// Data blocks by name: kind, name span, and structures (one for IDS,
    /// one per item for export and import blocks, by item name).
    blocks: BTreeMap<String, Block>,
    /// Threads by name.
    threads: BTreeMap<String, ThreadId>,
    /// Services by name.
    services: BTreeMap<String, ServiceId>,
    /// Export and import items by kind and item name.
    items: BTreeMap<(genom_model::kinds::DataKind, String), StructureId>,
    /// Codels by service and name (the first declared of each name), so
    /// that a long chain of `next` resolves in linear time.
    codels: BTreeMap<(ServiceId, String), genom_model::component::CodelId>,
    /// Field positions of large struct types, by type (see
    /// `data::field_position`), with the field count they were built for.
    fields: BTreeMap<genom_model::component::TypeId, (usize, BTreeMap<String, usize>)>,
}

#[derive(Debug)]
struct Block {
    kind: genom_model::kinds::DataKind,
    span: Span,
    /// For IDS: the block's structure; for export/import: items by name.
    items: BTreeMap<String, StructureId>,
    ids: Option<StructureId>,
}

/// Resolution state.
pub(crate) struct Resolver {
    c: Component,
    diags: Vec<Diagnostic>,
    scopes: Scopes,
    names: Names,
    consts: idl::Consts,
}

impl Resolver {
    fn report(&mut self, d: Diagnostic) {
        self.diags.push(d);
    }

    /// The component item: name, attributes, credentials.
    fn component(&mut self, ast: &Ast, file_start: Span) -> bool {
        let components: Vec<&ast::Component> = ast
            .items()
            .filter_map(|i| {
                if let Item::Component(c) = i {
                    Some(c)
                } else {
                    None
                }
            })
            .collect();
        let Some(first) = components.first() else {
            self.report(missing_component::missing_component(file_start));
            self.c.credentials = default_credentials(file_start);
            return false;
        };
        for extra in &components[1..] {
            self.report(duplicate_definition::duplicate(
                "component",
                &extra.name.name,
                extra.name.span,
                first.name.span,
            ));
        }
        self.c.name = Named {
            name: first.name.name.clone(),
            span: first.name.span,
        };
        let a = self.attrs(&first.attributes, "a component", attrs::COMPONENT);
        self.c.category = a.ident("category").map(named);
        self.c.lang = a.ident("lang").map(named);
        self.c.version = a.string("version").map(|s| s.value.clone());
        self.c.doc = a.string("doc").map(|s| s.value.clone());
        self.c.credentials = match a.credentials() {
            Some(list) => self.credentials(list),
            None => default_credentials(first.name.span),
        };
        true
    }

    fn credentials(&mut self, list: &[ast::Ident]) -> Vec<Named> {
        let mut out: Vec<Named> = Vec::new();
        for class in list {
            if let Some(prev) = out.iter().find(|c| c.name == class.name) {
                let first = prev.span;
                self.report(duplicate_definition::duplicate(
                    "credential class",
                    &class.name,
                    class.span,
                    first,
                ));
                continue;
            }
            out.push(named(class));
        }
        out
    }

    /// Threads: names (the control thread is implicit) and attributes.
    fn threads(&mut self, ast: &Ast) {
        for item in ast.items() {
            let Item::Thread(t) = item else { continue };
            if t.name.name == "control" {
                self.report(duplicate_definition::control_thread(t.name.span));
                continue;
            }
            if let Some(&prev) = self.names.threads.get(&t.name.name) {
                let first = self.c.threads[prev].name.span;
                self.report(duplicate_definition::duplicate(
                    "thread",
                    &t.name.name,
                    t.name.span,
                    first,
                ));
                continue;
            }
            let thread = self.thread(t);
            let id = self.c.threads.push(thread);
            self.names.threads.insert(t.name.name.clone(), id);
        }
    }

    fn thread(&mut self, t: &ast::Thread) -> genom_model::component::Thread {
        let a = self.attrs(&t.attributes, "a thread", attrs::THREAD);
        let priority = a.integer("priority").and_then(|i| i.value).unwrap_or(0);
        let period = a
            .duration("period")
            .and_then(|d| self.positive_duration("period", d));
        let stack = a.size("stack").and_then(|s| self.positive_size(s));
        genom_model::component::Thread {
            name: named(&t.name),
            priority,
            period,
            stack,
            start_hook: a.ident("start").map(named),
            stop_hook: a.ident("stop").map(named),
        }
    }

    fn positive_duration(
        &mut self,
        name: &str,
        d: &ast::DurationLit,
    ) -> Option<genom_model::component::Duration> {
        let ns = d.ns?;
        if ns <= 0 {
            self.report(crate::checks::invalid_attribute::not_positive(
                name, d.span, &d.text,
            ));
            return None;
        }
        Some(genom_model::component::Duration {
            ns: ns.unsigned_abs(),
            span: d.span,
        })
    }

    fn positive_size(&mut self, s: &ast::SizeLit) -> Option<u64> {
        let bytes = s.bytes?;
        if bytes == 0 {
            self.report(crate::checks::invalid_attribute::not_positive(
                "stack", s.span, &s.text,
            ));
            return None;
        }
        Some(bytes)
    }
}

/// The model's form of an AST name.
pub(crate) fn named(i: &ast::Ident) -> Named {
    Named {
        name: i.name.clone(),
        span: i.span,
    }
}

fn default_credentials(span: Span) -> Vec<Named> {
    DEFAULT_CREDENTIALS
        .iter()
        .map(|n| Named {
            name: (*n).to_owned(),
            span,
        })
        .collect()
}
