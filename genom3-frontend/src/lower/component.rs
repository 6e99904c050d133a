//! Lowering one `component` (or, for an interface-only file, one
//! `interface`) with the interfaces it provides and uses inlined: merged
//! `ids`, ports as import/export structures, tasks as threads, services with
//! their parameters, throws, interrupts and codels, and every codel
//! parameter resolved (service parameter or local, ids member path, port,
//! remote). The mapping is documented in `genom_model::component::genom3`.

use std::collections::{BTreeMap, BTreeSet};

use genom_model::component::Idx as _;
use genom_model::component::genom3::{
    FsmCodel, Genom3Info, Port as MPort, Remote, ServiceInfo, Task as MTask,
};
use genom_model::component::{
    Component, Duration, Field, Named, Param, Ref, Service, ServiceId, Structure, StructureId,
    Thread, ThreadId, Ty, TypeDef, TypeKind, Value,
};
use genom_model::kinds::{DataKind, ServiceKind};
use genom_model::{Code, Diagnostic, Span};

use super::closest_hint;
use super::types::{Types, as_f64};
use crate::ast::{self, Dir, Export, PropertyKind, TimeUnit};
use crate::diagnostics;

/// One element of the component body with where it comes from.
struct Part<'a> {
    export: &'a Export,
    /// The interface it comes from, if any.
    interface: Option<&'a str>,
    /// From a `uses` interface.
    used: bool,
}

/// The lowering context of one component.
pub(crate) struct Ctx<'a> {
    pub(crate) c: Component,
    pub(crate) g: Genom3Info,
    pub(crate) types: Types,
    pub(crate) diags: Vec<Diagnostic>,
    interfaces: &'a BTreeMap<String, &'a ast::Component>,
    pub(super) scope: Vec<String>,
    pub(super) ids: Option<StructureId>,
    /// Per service: parameter and local names (name → (output, index) for
    /// parameters, `None` for locals).
    pub(super) locals: BTreeMap<ServiceId, BTreeMap<String, Option<(bool, usize)>>>,
    /// FSM owners for the checks: (owner name, span, codels).
    pub(crate) machines: Vec<(String, Span, Vec<FsmCodel>, Option<ThreadId>)>,
}

/// A time in nanoseconds from a value and a unit (seconds when absent):
/// a whole number of nanoseconds, from 0 to a day
/// ([`genom_model::limits::MAX_DURATION_NS`]); otherwise why not.
fn to_ns(v: &Value, unit: Option<TimeUnit>) -> Result<u64, String> {
    let scale: u64 = match unit {
        None | Some(TimeUnit::S) => 1_000_000_000,
        Some(TimeUnit::Ms) => 1_000_000,
        Some(TimeUnit::Us) => 1_000,
    };
    let max = genom_model::limits::MAX_DURATION_NS;
    let too_long = || {
        "the duration is longer than genom-check's limit of one day (86400s): the timed engines' arithmetic must stay exact".to_owned()
    };
    match v {
        Value::Int(i) if *i < 0 => Err("expected a non-negative duration".to_owned()),
        Value::Int(i) => u64::try_from(*i)
            .ok()
            .and_then(|i| i.checked_mul(scale))
            .filter(|&ns| ns <= max)
            .ok_or_else(too_long),
        _ => {
            let f = as_f64(v).ok_or("expected a number of seconds, ms or us")?;
            #[allow(clippy::cast_precision_loss)]
            let ns = f * scale as f64;
            if !ns.is_finite() || ns < 0.0 {
                return Err("expected a non-negative duration".to_owned());
            }
            #[allow(clippy::cast_precision_loss)]
            if ns > max as f64 {
                return Err(too_long());
            }
            let whole = ns.round();
            if (ns - whole).abs() > 1e-6 * whole.max(1.0) {
                return Err("the duration is not a whole number of nanoseconds".to_owned());
            }
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            Ok(whole as u64)
        }
    }
}

impl<'a> Ctx<'a> {
    pub(crate) fn new(types: Types, interfaces: &'a BTreeMap<String, &'a ast::Component>) -> Self {
        Self {
            c: Component::default(),
            g: Genom3Info::default(),
            types,
            diags: Vec::new(),
            interfaces,
            scope: Vec::new(),
            ids: None,
            locals: BTreeMap::new(),
            machines: Vec::new(),
        }
    }

    /// The component and every diagnostic.
    pub(crate) fn finish(mut self) -> (Component, Vec<Diagnostic>) {
        self.c.types = std::mem::take(&mut self.types.defs);
        self.c.constants = std::mem::take(&mut self.types.constants);
        self.g.exceptions = self.types.exceptions.values().cloned().collect();
        self.c.genom3 = Some(Box::new(self.g));
        let mut d = self.types.diagnostics;
        d.extend(self.diags);
        (self.c, d)
    }

    fn duration(
        &mut self,
        e: &ast::Expr,
        unit: Option<TimeUnit>,
        scope: &[String],
    ) -> Option<Duration> {
        match self.types.eval(e, scope) {
            Ok(v) => match to_ns(&v, unit) {
                Ok(ns) => Some(Duration { ns, span: e.span }),
                Err(why) => {
                    self.diags.push(diagnostics::bad_constant(e.span, &why));
                    None
                }
            },
            Err(why) => {
                self.diags.push(diagnostics::bad_constant(e.span, &why));
                None
            }
        }
    }

    /// The body parts: the component's own, then the built-in and provided
    /// interfaces' (transitively), then used interfaces'.
    fn parts(&mut self, comp: &'a ast::Component) -> Vec<Part<'a>> {
        let mut out: Vec<Part<'a>> = Vec::new();
        let mut seen = BTreeSet::new();
        seen.insert(comp.name.name.clone());
        let mut provided: Vec<(ast::Ident, bool)> = Vec::new();
        if !comp.is_interface {
            let builtin = ast::Ident {
                name: "genom".to_owned(),
                span: comp.name.span,
            };
            provided.push((builtin, false));
        }
        for e in &comp.body {
            out.push(Part {
                export: e,
                interface: None,
                used: false,
            });
            if let Export::Property(p) = e {
                match &p.kind {
                    PropertyKind::Provides(l) | PropertyKind::Extends(l) => {
                        provided.extend(l.iter().map(|i| (i.clone(), false)));
                    }
                    PropertyKind::Uses(l) => provided.extend(l.iter().map(|i| (i.clone(), true))),
                    _ => {}
                }
            }
        }
        let mut i = 0;
        while i < provided.len() {
            let (name, used) = provided[i].clone();
            i += 1;
            let Some(&iface) = self.interfaces.get(&name.name) else {
                let hint = closest_hint(&name.name, self.interfaces.keys());
                self.diags.push(diagnostics::unknown(
                    Code::UnknownInterface,
                    "interface",
                    &name.name,
                    name.span,
                    hint.as_deref(),
                ));
                continue;
            };
            if !seen.insert(format!("{}/{used}", name.name)) {
                continue;
            }
            let list = if used {
                &mut self.g.uses
            } else {
                &mut self.g.provides
            };
            list.push(Named {
                name: name.name.clone(),
                span: name.span,
            });
            for e in &iface.body {
                if let Export::Property(p) = e {
                    match &p.kind {
                        PropertyKind::Provides(l) | PropertyKind::Extends(l) => {
                            provided.extend(l.iter().map(|n| (n.clone(), used)));
                        }
                        PropertyKind::Uses(l) if !used => {
                            provided.extend(l.iter().map(|n| (n.clone(), true)));
                        }
                        _ => {}
                    }
                    continue;
                }
                out.push(Part {
                    export: e,
                    interface: Some(iface.name.name.as_str()),
                    used,
                });
            }
        }
        out
    }

    /// Lowers the component.
    pub(crate) fn component(&mut self, comp: &'a ast::Component) {
        self.c.name = Named {
            name: comp.name.name.clone(),
            span: comp.name.span,
        };
        self.g.is_interface = comp.is_interface;
        self.scope = vec![comp.name.name.clone()];
        self.c.credentials = genom_model::component::DEFAULT_CREDENTIALS
            .iter()
            .map(|n| Named {
                name: (*n).to_owned(),
                span: Span::default(),
            })
            .collect();
        let parts = self.parts(comp);
        let owner_scope = |p: &Part<'_>| {
            vec![
                p.interface
                    .map_or_else(|| comp.name.name.clone(), str::to_owned),
            ]
        };
        // Component properties.
        for p in parts.iter().filter(|p| p.interface.is_none()) {
            if let Export::Property(prop) = p.export {
                self.component_property(prop);
            }
        }
        // ids (merged) and ports.
        let mut fields: Vec<Field> = Vec::new();
        let mut ids_span = None;
        for p in parts.iter().filter(|p| !p.used) {
            if let Export::Ids(members, span) = p.export {
                ids_span.get_or_insert(*span);
                let mut scope = owner_scope(p);
                scope.push("ids".to_owned());
                let prefix = format!("{}::", scope.join("::"));
                let new_fields = self.types.fields(members, &scope);
                // Types declared in `ids` are also visible in the component.
                let nested: Vec<(String, genom_model::component::TypeId)> = self
                    .types
                    .by_name
                    .iter()
                    .filter_map(|(n, id)| {
                        n.strip_prefix(&prefix)
                            .map(|rest| (format!("{}::{rest}", scope[0]), *id))
                    })
                    .collect();
                for (n, id) in nested {
                    self.types.by_name.entry(n).or_insert(id);
                }
                for f in new_fields {
                    if let Some(first) = fields.iter().find(|g| g.name == f.name) {
                        self.diags.push(diagnostics::duplicate(
                            "ids member",
                            &f.name,
                            f.span,
                            first.span,
                        ));
                    } else {
                        fields.push(f);
                    }
                }
            }
        }
        if let Some(span) = ids_span {
            let name = format!("{}::ids", comp.name.name);
            let id = self.types.defs.push(TypeDef {
                name: name.clone(),
                span,
                kind: TypeKind::Struct(fields),
            });
            self.types.by_name.insert(name, id);
            self.ids = Some(self.c.structures.push(Structure {
                kind: DataKind::Ids,
                name: "ids".to_owned(),
                block: "ids".to_owned(),
                span,
                ty: Ty::Named { id },
                init: None,
                doc: None,
            }));
        }
        for p in &parts {
            if let Export::Port(port) = p.export {
                self.port(port, p.interface, p.used, &owner_scope(p));
            }
        }
        for p in parts.iter().filter(|p| !p.used) {
            if let Export::Task(t) = p.export {
                self.task_header(t, &owner_scope(p));
            }
        }
        self.clock_rate_fits();
        // Services: names first (for interrupts, before, after).
        let mut services: Vec<(&ast::Service, ServiceId, Option<&str>, Vec<String>)> = Vec::new();
        for p in &parts {
            let Export::Service(s) = p.export else {
                continue;
            };
            if p.used {
                self.g.remotes.push(Remote {
                    name: Named {
                        name: s.name.name.clone(),
                        span: s.name.span,
                    },
                    interface: p.interface.unwrap_or_default().to_owned(),
                });
                continue;
            }
            if let Some(first) = self.c.service_named(&s.name.name) {
                let first = self.c.services[first].name.span;
                self.diags.push(diagnostics::duplicate(
                    "service",
                    &s.name.name,
                    s.name.span,
                    first,
                ));
                continue;
            }
            let id = self.c.services.push(empty_service(s));
            services.push((s, id, p.interface, owner_scope(p)));
        }
        let component_throws: Vec<ast::Ident> = parts
            .iter()
            .filter(|p| p.interface.is_none())
            .filter_map(|p| match p.export {
                Export::Property(ast::Property {
                    kind: PropertyKind::Throws(l),
                    ..
                }) => Some(l.clone()),
                _ => None,
            })
            .flatten()
            .collect();
        for (s, id, iface, scope) in services {
            self.service(s, id, iface, &scope, &component_throws);
        }
        for p in parts.iter().filter(|p| !p.used) {
            if let Export::Task(t) = p.export {
                self.task_codels(t, &owner_scope(p));
            }
        }
    }

    /// Every task period and delay is a multiple of the `clock-rate`.
    fn clock_rate_fits(&mut self) {
        let Some(clock) = self.g.clock_rate.filter(|c| c.ns > 0) else {
            return;
        };
        let mut bad = Vec::new();
        for t in &self.g.tasks {
            let thread = &self.c.threads[t.thread];
            for (what, d) in [("period", thread.period), ("delay", t.delay)] {
                if let Some(d) = d.filter(|d| d.ns % clock.ns != 0) {
                    bad.push(diagnostics::off_clock(
                        what,
                        &thread.name.name,
                        d.span,
                        clock.span,
                    ));
                }
            }
        }
        self.diags.extend(bad);
    }

    fn component_property(&mut self, prop: &ast::Property) {
        let scope = self.scope.clone();
        match &prop.kind {
            PropertyKind::Doc(d) => append_doc(&mut self.c.doc, d),
            PropertyKind::Version(v) => self.c.version = Some(v.clone()),
            PropertyKind::Lang(l) => {
                self.c.lang = Some(Named {
                    name: l.clone(),
                    span: prop.span,
                });
            }
            PropertyKind::Email(e) => self.g.email = Some(e.clone()),
            PropertyKind::Require(r) => self.g.require.extend(r.iter().cloned()),
            PropertyKind::CodelsRequire(r) => self.g.codels_require.extend(r.iter().cloned()),
            PropertyKind::ClockRate(e, u) => self.g.clock_rate = self.duration(e, *u, &scope),
            PropertyKind::Provides(_)
            | PropertyKind::Uses(_)
            | PropertyKind::Extends(_)
            | PropertyKind::Throws(_) => {}
            other => self.misplaced(prop.span, other, "a component"),
        }
    }

    fn misplaced(&mut self, span: Span, kind: &PropertyKind, owner: &str) {
        let word = kind.keyword();
        self.diags
            .push(diagnostics::misplaced_property(span, word, owner));
    }

    fn port(&mut self, p: &ast::Port, iface: Option<&str>, used: bool, scope: &[String]) {
        if let Some(first) = self.g.ports.iter().find(|q| q.name.name == p.name.name) {
            let first = first.name.span;
            self.diags.push(diagnostics::duplicate(
                "port",
                &p.name.name,
                p.name.span,
                first,
            ));
            return;
        }
        if !matches!(p.ty, ast::TypeSpec::Named(_)) {
            self.diags
                .push(diagnostics::anonymous_port_type(&p.name.name, p.name.span));
        }
        // As genom3's port.c: a port takes `doc` only.
        for prop in &p.properties {
            if !matches!(prop.kind, PropertyKind::Doc(_)) {
                self.misplaced(prop.span, &prop.kind, "a port");
            }
        }
        let ty = self.types.ty(&p.ty, scope);
        let is_out = (p.dir == ast::PortDir::Out) != used;
        let structure = self.c.structures.push(Structure {
            kind: if is_out {
                DataKind::Export
            } else {
                DataKind::Import
            },
            name: p.name.name.clone(),
            block: "port".to_owned(),
            span: p.name.span,
            ty: ty.clone(),
            init: None,
            doc: None,
        });
        self.g.ports.push(MPort {
            name: Named {
                name: p.name.name.clone(),
                span: p.name.span,
            },
            is_out,
            multiple: p.multiple,
            ty,
            structure: Some(structure),
            interface: iface.map(str::to_owned),
        });
    }

    fn task_header(&mut self, t: &ast::Task, scope: &[String]) {
        if let Some(first) = self.c.thread_named(&t.name.name) {
            let first = self.c.threads[first].name.span;
            self.diags.push(diagnostics::duplicate(
                "task",
                &t.name.name,
                t.name.span,
                first,
            ));
            return;
        }
        let mut thread = Thread {
            name: Named {
                name: t.name.name.clone(),
                span: t.name.span,
            },
            priority: 0,
            period: None,
            stack: None,
            start_hook: None,
            stop_hook: None,
        };
        let mut info = MTask {
            thread: ThreadId::new(0),
            delay: None,
            real_time: false,
            throws: Vec::new(),
            codels: Vec::new(),
        };
        for prop in &t.properties {
            match &prop.kind {
                PropertyKind::Period(e, u) => thread.period = self.duration(e, *u, scope),
                PropertyKind::Delay(e, u) => info.delay = self.duration(e, *u, scope),
                PropertyKind::Priority(e) => match self.types.eval(e, scope) {
                    Ok(Value::Int(v)) => thread.priority = i64::try_from(v).unwrap_or(0),
                    _ => self.diags.push(diagnostics::bad_constant(
                        e.span,
                        "expected an integer priority",
                    )),
                },
                PropertyKind::Stack(e, mult) => {
                    thread.stack = self
                        .types
                        .positive(e, scope)
                        .map(|v| v.saturating_mul(*mult));
                }
                PropertyKind::SchedulingRealTime => info.real_time = true,
                PropertyKind::Throws(l) => info.throws = self.throws(l, scope),
                PropertyKind::Doc(_) | PropertyKind::Codel(_) => {}
                other => self.misplaced(prop.span, other, "a task"),
            }
        }
        info.thread = self.c.threads.push(thread);
        self.g.tasks.push(info);
    }

    fn throws(&mut self, list: &[ast::Ident], scope: &[String]) -> Vec<Named> {
        let mut out = Vec::new();
        for n in list {
            let cands = super::types::candidates(scope, &n.name);
            let found = cands
                .iter()
                .find(|c| self.types.exceptions.contains_key(*c))
                .cloned();
            match found {
                Some(q) => out.push(Named {
                    name: q,
                    span: n.span,
                }),
                None => {
                    let hint = closest_hint(&n.name, self.types.exceptions.keys());
                    self.diags.push(diagnostics::unknown(
                        Code::UnknownReport,
                        "exception",
                        &n.name,
                        n.span,
                        hint.as_deref(),
                    ));
                }
            }
        }
        out
    }

    fn service(
        &mut self,
        s: &ast::Service,
        id: ServiceId,
        iface: Option<&str>,
        scope: &[String],
        component_throws: &[ast::Ident],
    ) {
        let mut info = ServiceInfo {
            service: id,
            kind: match s.kind {
                ast::ServiceKind::Attribute => "attribute",
                ast::ServiceKind::Function => "function",
                ast::ServiceKind::Activity => "activity",
            }
            .to_owned(),
            before: Vec::new(),
            after: Vec::new(),
            interrupts_all: false,
            locals: Vec::new(),
            interface: iface.map(str::to_owned),
        };
        self.parameters(s, id, scope);
        let mut reports = self.throws(component_throws, &self.scope.clone());
        let mut fsm: Vec<FsmCodel> = Vec::new();
        let mut validate = None;
        let mut simple = Vec::new();
        for prop in &s.properties {
            match &prop.kind {
                PropertyKind::Doc(d) => append_doc(&mut self.c.services[id].doc, d),
                PropertyKind::Task(t) => match self.c.thread_named(&t.name) {
                    Some(tid) => {
                        self.c.services[id].thread = Some(Ref {
                            id: tid,
                            span: t.span,
                        });
                    }
                    None => {
                        let names: Vec<String> = self
                            .c
                            .threads
                            .values()
                            .map(|t| t.name.name.clone())
                            .collect();
                        let hint = closest_hint(&t.name, names.iter());
                        self.diags.push(diagnostics::unknown(
                            Code::UnknownThread,
                            "task",
                            &t.name,
                            t.span,
                            hint.as_deref(),
                        ));
                    }
                },
                PropertyKind::Interrupts(l) => {
                    for n in l {
                        if n.name == "all" {
                            info.interrupts_all = true;
                            let all: Vec<ServiceId> = self.c.services.ids().collect();
                            self.c.services[id]
                                .stops
                                .extend(all.into_iter().map(|sid| Ref {
                                    id: sid,
                                    span: n.span,
                                }));
                        } else if let Some(r) = self.service_ref(n) {
                            self.c.services[id].stops.push(r);
                        }
                    }
                }
                PropertyKind::Before(l) => {
                    info.before = l.iter().filter_map(|n| self.service_ref(n)).collect();
                }
                PropertyKind::After(l) => {
                    info.after = l.iter().filter_map(|n| self.service_ref(n)).collect();
                }
                PropertyKind::Throws(l) => reports.extend(self.throws(l, scope)),
                PropertyKind::Local(ty, decls) => {
                    let base = self.types.ty(ty, scope);
                    for d in decls {
                        let ty = self.types.array(base.clone(), d, scope);
                        self.locals
                            .entry(id)
                            .or_default()
                            .insert(d.name.name.clone(), None);
                        info.locals.push(Field {
                            name: d.name.name.clone(),
                            ty,
                            span: d.name.span,
                            default: None,
                            doc: None,
                        });
                    }
                }
                PropertyKind::Validate(c) => validate = Some(c),
                PropertyKind::Codel(c) if c.states.is_empty() => simple.push(c),
                PropertyKind::Codel(c) => fsm.push(self.fsm_codel(c, Some(id), scope)),
                other => self.misplaced(prop.span, other, "a service"),
            }
        }
        reports.dedup_by(|a, b| a.name == b.name);
        self.c.services[id].reports = reports;
        if let Some(v) = validate {
            let f = self.fsm_codel(v, Some(id), scope);
            self.control_codel(id, "validate", f);
        }
        // A function's codels run in sequence: `codel`, `codel2`, ...
        for (i, c) in simple.into_iter().enumerate() {
            let f = self.fsm_codel(c, Some(id), scope);
            let name = if i == 0 {
                "codel".to_owned()
            } else {
                format!("codel{}", i + 1)
            };
            self.control_codel(id, &name, f);
        }
        if s.kind == ast::ServiceKind::Activity {
            let names_task = s
                .properties
                .iter()
                .any(|p| matches!(p.kind, PropertyKind::Task(_)));
            if self.c.services[id].thread.is_none() && !fsm.is_empty() && !names_task {
                self.diags.push(Diagnostic::new(
                    Code::MissingThread,
                    format!("activity `{}` has codels but no `task`", s.name.name),
                    s.name.span,
                    "which task runs its codels?",
                ));
            }
            self.state_codels(id, &fsm);
            let thread = self.c.services[id].thread.map(|r| r.id);
            self.machines
                .push((s.name.name.clone(), s.name.span, fsm, thread));
        } else if !fsm.is_empty() {
            self.diags.push(diagnostics::misplaced_property(
                fsm[0].span,
                "codel<...>",
                "a function or attribute (only activities and tasks have states)",
            ));
        }
        self.g.services.push(info);
    }

    fn service_ref(&mut self, n: &ast::Ident) -> Option<Ref<ServiceId>> {
        match self.c.service_named(&n.name) {
            Some(id) => Some(Ref { id, span: n.span }),
            None => {
                let names: Vec<String> = self
                    .c
                    .services
                    .values()
                    .map(|s| s.name.name.clone())
                    .collect();
                let hint = closest_hint(&n.name, names.iter());
                self.diags.push(diagnostics::unknown(
                    Code::UnknownService,
                    "service",
                    &n.name,
                    n.span,
                    hint.as_deref(),
                ));
                None
            }
        }
    }

    fn parameters(&mut self, s: &ast::Service, id: ServiceId, scope: &[String]) {
        for p in &s.params {
            let Some(name) = p.name().cloned() else {
                continue;
            };
            let (ty, data) = match (&p.ty, &p.path) {
                (Some(ty), _) => {
                    let base = self.types.ty(ty, scope);
                    let decl = ast::Declarator {
                        name: name.clone(),
                        dims: p.dims.clone(),
                    };
                    (self.types.array(base, &decl, scope), None)
                }
                (None, Some(path)) => match self.ids_path(path) {
                    Some(dp) => (dp.ty.clone(), Some(dp)),
                    None => (Ty::Error, None),
                },
                (None, None) => match self.whole_ids(p.span, &name.name) {
                    Some(dp) => (dp.ty.clone(), Some(dp)),
                    None => (Ty::Error, None),
                },
            };
            let value = p.init.as_ref().and_then(|i| i.value.as_ref());
            if let Some(v) = value {
                self.check_init(&name.name, v, &ty);
            }
            let default = value.and_then(|v| match v {
                ast::InitValue::Expr(e) => self.types.eval(e, scope).ok(),
                _ => None,
            });
            let param = Param {
                name: Named {
                    name: name.name.clone(),
                    span: name.span,
                },
                ty,
                data,
                default,
                doc: p.init.as_ref().and_then(|i| i.doc.clone()),
            };
            let svc = &mut self.c.services[id];
            let table = self.locals.entry(id).or_default();
            if matches!(p.dir, Dir::In | Dir::InOut) {
                table.insert(name.name.clone(), Some((false, svc.inputs.len())));
                svc.inputs.push(param.clone());
            }
            if matches!(p.dir, Dir::Out | Dir::InOut) {
                if p.dir == Dir::Out {
                    table.insert(name.name.clone(), Some((true, svc.outputs.len())));
                }
                svc.outputs.push(param);
            }
        }
    }
}

fn empty_service(s: &ast::Service) -> Service {
    Service::empty(
        Named {
            name: s.name.name.clone(),
            span: s.name.span,
        },
        ServiceKind::Plain,
        None,
    )
}

fn append_doc(doc: &mut Option<String>, line: &str) {
    match doc {
        Some(d) => {
            d.push('\n');
            d.push_str(line);
        }
        None => *doc = Some(line.to_owned()),
    }
}
