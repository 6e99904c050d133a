//! Services: names and kinds (`multiple-init`), then their attributes
//! (thread, reports, max-time, credential, stops/delays/forbids,
//! parameters, imports and exports), then their codels.

use crate::ast::{self, ParamTarget, TypedName};
use genom_model::component::types::TypeTable as _;
use genom_model::component::{Named, Param, Ref, Service, ServiceId, StructureId, Ty};
use genom_model::kinds::{DataKind, ServiceKind};

use super::attrs::{self, Attrs};
use super::{Resolver, named};
use crate::checks::{
    codel_transitions, duplicate_definition, invalid_attribute, service_structure, type_mismatch,
    unknown_name,
};

/// Resolves every service: names first, so that references resolve in any
/// order; then attributes (parameters are needed by codel arguments); then
/// codels.
pub(super) fn resolve_services(r: &mut Resolver, services: &[&ast::Service]) {
    let ids: Vec<Option<ServiceId>> = services.iter().map(|s| r.declare_service(s)).collect();
    let declared: Vec<(ServiceId, &ast::Service)> = ids
        .iter()
        .zip(services)
        .filter_map(|(id, s)| id.map(|id| (id, *s)))
        .collect();
    let codels: Vec<_> = declared
        .iter()
        .map(|&(id, s)| r.declare_codels(id, s))
        .collect();
    for &(id, s) in &declared {
        r.service_attributes(id, s);
    }
    for (&(id, s), codels) in declared.iter().zip(&codels) {
        r.service_structure(id, s);
        r.codel_bodies(codels);
    }
}

impl Resolver {
    fn declare_service(&mut self, s: &ast::Service) -> Option<ServiceId> {
        if let Some(&prev) = self.names.services.get(&s.name.name) {
            let first = self.c.services[prev].name.span;
            self.report(duplicate_definition::duplicate(
                "service",
                &s.name.name,
                s.name.span,
                first,
            ));
            return None;
        }
        if s.kind == ServiceKind::Init {
            if let Some(first) = self.c.init_service() {
                let f = &self.c.services[first].name;
                let d =
                    service_structure::multiple_init(&s.name.name, s.name.span, &f.name, f.span);
                self.report(d);
            }
        }
        let id = self.c.services.push(empty_service(s));
        self.names.services.insert(s.name.name.clone(), id);
        Some(id)
    }

    fn service_attributes(&mut self, id: ServiceId, s: &ast::Service) {
        let a = self.attrs(&s.attributes, "a service", attrs::SERVICE);
        let thread = a.ident("thread").and_then(|t| self.thread_ref(t));
        let reports = self.reports(a.idents("report"));
        let max_time = a
            .duration("max-time")
            .and_then(|d| self.positive_duration("max-time", d));
        let (credential, credential_span) = self.credential(&a);
        let stops = self.service_refs(a.idents("stops"));
        let delays = self.service_refs(a.idents("delays"));
        let forbids = self.service_refs(a.idents("forbids"));
        let inputs = self.params(a.params("input"), "input");
        let outputs = self.params(a.params("output"), "output");
        let imports = self.typed_items(a.typed("import"), DataKind::Import);
        let exports = self.typed_items(a.typed("export"), DataKind::Export);
        let svc = &mut self.c.services[id];
        svc.doc = a.string("doc").map(|d| d.value.clone());
        (svc.thread, svc.reports, svc.max_time) = (thread, reports, max_time);
        (svc.credential, svc.credential_span) = (credential, credential_span);
        (svc.stops, svc.delays, svc.forbids) = (stops, delays, forbids);
        (svc.inputs, svc.outputs, svc.imports, svc.exports) = (inputs, outputs, imports, exports);
        if s.kind == ServiceKind::Auto {
            self.auto_inputs(&s.name.name, a.params("input"));
        }
    }

    fn thread_ref(&mut self, t: &ast::Ident) -> Option<Ref<genom_model::component::ThreadId>> {
        if let Some(&id) = self.names.threads.get(&t.name) {
            return Some(Ref { id, span: t.span });
        }
        let candidates: Vec<&str> = self.names.threads.keys().map(String::as_str).collect();
        let mut d = unknown_name::unknown_thread(&t.name, t.span, candidates);
        if t.name == "control" {
            d = d.with_help("the control thread only runs control codels; a service with a start codel needs a declared execution thread");
        }
        self.report(d);
        None
    }

    fn reports(&mut self, list: &[ast::Ident]) -> Vec<Named> {
        let mut out: Vec<Named> = Vec::new();
        for r in list {
            if let Some(prev) = out.iter().find(|x| x.name == r.name) {
                let first = prev.span;
                self.report(duplicate_definition::duplicate(
                    "report", &r.name, r.span, first,
                ));
                continue;
            }
            if r.name == "end" {
                // Not a report: `next: end` can only mean termination.
                self.report(codel_transitions::report_named_end(r.span));
                continue;
            }
            out.push(named(r));
        }
        out
    }

    fn credential(&mut self, a: &Attrs<'_>) -> (usize, Option<genom_model::Span>) {
        let Some(c) = a.ident("credential") else {
            return (0, None);
        };
        if let Some(index) = self.c.credentials.iter().position(|k| k.name == c.name) {
            return (index, Some(c.span));
        }
        let candidates: Vec<&str> = self.c.credentials.iter().map(|k| k.name.as_str()).collect();
        let d = unknown_name::unknown_credential(&c.name, c.span, candidates);
        self.report(d);
        (0, Some(c.span))
    }

    fn service_refs(&mut self, list: &[ast::Ident]) -> Vec<Ref<ServiceId>> {
        let mut out: Vec<Ref<ServiceId>> = Vec::new();
        for name in list {
            match self.names.services.get(&name.name) {
                Some(&id) if out.iter().all(|r| r.id != id) => out.push(Ref {
                    id,
                    span: name.span,
                }),
                Some(_) => {}
                None => {
                    let candidates: Vec<&str> =
                        self.names.services.keys().map(String::as_str).collect();
                    let d = unknown_name::unknown_service(&name.name, name.span, candidates);
                    self.report(d);
                }
            }
        }
        out
    }

    fn params(&mut self, list: &[ast::Param], what: &str) -> Vec<Param> {
        let mut out: Vec<Param> = Vec::new();
        for p in list {
            let Some(param) = self.param(p) else { continue };
            if let Some(prev) = out.iter().find(|x| x.name.name == param.name.name) {
                let first = prev.name.span;
                let kind = format!("{what} parameter");
                self.report(duplicate_definition::duplicate(
                    &kind,
                    &param.name.name,
                    param.name.span,
                    first,
                ));
                continue;
            }
            out.push(param);
        }
        out
    }

    fn param(&mut self, p: &ast::Param) -> Option<Param> {
        let (name, ty, data) = match &p.target {
            ParamTarget::Typed(spec, decl) => {
                (named(&decl.name), self.ty_dims(spec, &decl.dims, &[]), None)
            }
            ParamTarget::Data(r) => {
                let path = self.ids_path(r)?;
                let name = named(r.path.iter().rev().find_map(field_name).unwrap_or(&r.root));
                (name, path.ty.clone(), Some(path))
            }
        };
        let default = p.default.as_ref().and_then(|v| self.value(v, &ty, &[]));
        Some(Param {
            name,
            ty,
            data,
            default,
            doc: p.doc.as_ref().map(|d| d.value.clone()),
        })
    }

    /// A parameter stored into or read from an IDS member.
    fn ids_path(&mut self, r: &ast::DataRef) -> Option<genom_model::component::DataPath> {
        let path = self.data_path(r, None)?;
        let is_ids = path
            .structure()
            .is_some_and(|s| self.c.structures[s].kind == DataKind::Ids);
        if !is_ids {
            let ids: Vec<String> = self.ids_blocks();
            let ids: Vec<&str> = ids.iter().map(String::as_str).collect();
            let d = unknown_name::not_ids_member(&r.to_string(), r.span, &ids);
            self.report(d);
            return None;
        }
        Some(path)
    }

    fn ids_blocks(&self) -> Vec<String> {
        self.c
            .structures
            .values()
            .filter(|s| s.kind == DataKind::Ids)
            .map(|s| s.name.clone())
            .collect()
    }

    fn typed_items(&mut self, list: &[TypedName], kind: DataKind) -> Vec<Ref<StructureId>> {
        let mut out = Vec::new();
        for t in list {
            let declared = self.ty(&t.ty, &[]);
            let Some(&id) = self.names.items.get(&(kind, t.name.name.clone())) else {
                let candidates: Vec<&str> = self
                    .names
                    .items
                    .keys()
                    .filter(|(k, _)| *k == kind)
                    .map(|(_, n)| n.as_str())
                    .collect();
                let what = format!("{} item", kind.keyword());
                let d = unknown_name::unknown_data(&what, &t.name.name, t.name.span, candidates);
                self.report(d);
                continue;
            };
            self.same_item_type(t, &declared, id);
            out.push(Ref {
                id,
                span: t.name.span,
            });
        }
        out
    }

    fn same_item_type(&mut self, t: &TypedName, declared: &Ty, id: StructureId) {
        let item = &self.c.structures[id];
        if self.c.types.same(declared, &item.ty) {
            return;
        }
        let (actual, item_span) = (self.show(&item.ty), item.span);
        let d = type_mismatch::declared_type_differs(
            t.ty.span(),
            &t.name.name,
            &self.show(declared),
            &actual,
            item_span,
        );
        self.report(d);
    }

    fn auto_inputs(&mut self, service: &str, inputs: &[ast::Param]) {
        for p in inputs.iter().filter(|p| p.default.is_none()) {
            let name = match &p.target {
                ParamTarget::Typed(_, decl) => &decl.name,
                ParamTarget::Data(r) => r.path.iter().rev().find_map(field_name).unwrap_or(&r.root),
            };
            self.report(invalid_attribute::auto_input_without_default(
                service, &name.name, name.span,
            ));
        }
    }
}

fn empty_service(s: &ast::Service) -> Service {
    Service::empty(named(&s.name), s.kind, s.kind_span)
}

/// The name of a field step.
fn field_name(e: &ast::PathElem) -> Option<&ast::Ident> {
    match e {
        ast::PathElem::Field(f) => Some(f),
        ast::PathElem::Index(..) => None,
    }
}
