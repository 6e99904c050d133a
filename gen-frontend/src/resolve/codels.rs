//! Codels: declaration per service (`duplicate-codel-kind`, `ambiguous-name`),
//! the service structure rules (`missing-start`, `missing-thread`), and codel
//! bodies: the call and its arguments, `update`, `on-inter`, WCET and `next`.

use crate::ast;
use genom_model::component::{Arg, Call, Codel, CodelId, Named, Next, Outcome, Ref, ServiceId};
use genom_model::kinds::CodelKind;

use super::attrs::{self, Attrs};
use super::{Resolver, named};
use crate::checks::{
    codel_transitions, duplicate_definition, invalid_attribute, service_structure, unknown_name,
};

impl Resolver {
    /// Declares the codels of a service; returns each declared codel with
    /// its AST.
    pub(super) fn declare_codels<'a>(
        &mut self,
        id: ServiceId,
        s: &'a ast::Service,
    ) -> Vec<(CodelId, &'a ast::Codel)> {
        let mut out = Vec::new();
        for c in &s.codels {
            if !self.codel_name_is_free(id, c) {
                continue;
            }
            let cid = self.c.codels.push(empty_codel(id, c));
            self.names
                .codels
                .entry((id, c.name.name.clone()))
                .or_insert(cid);
            let svc = &mut self.c.services[id];
            svc.codels.push(cid);
            match c.kind {
                CodelKind::Start => svc.start = Some(cid),
                CodelKind::Control => svc.control = Some(cid),
                CodelKind::Exec | CodelKind::Inter => {}
            }
            out.push((cid, c));
        }
        out
    }

    /// The codel of `service` named `name` (the first of that name).
    fn codel_named(&self, service: ServiceId, name: &str) -> Option<CodelId> {
        self.names.codels.get(&(service, name.to_owned())).copied()
    }

    fn codel_name_is_free(&mut self, id: ServiceId, c: &ast::Codel) -> bool {
        let svc = &self.c.services[id];
        let existing = match c.kind {
            CodelKind::Start => svc.start,
            CodelKind::Control => svc.control,
            CodelKind::Exec | CodelKind::Inter => self.codel_named(id, &c.name.name),
        };
        let Some(first) = existing.map(|e| self.c.codels[e].name.span) else {
            if c.name.name == "end" {
                self.report(codel_transitions::codel_named_end(c.name.span));
            }
            return true;
        };
        let service = svc.name.name.clone();
        let d = match c.kind {
            CodelKind::Start | CodelKind::Control => service_structure::duplicate_codel_kind(
                c.kind.keyword(),
                &service,
                c.name.span,
                first,
            ),
            _ => duplicate_definition::duplicate("codel", &c.name.name, c.name.span, first),
        };
        self.report(d);
        false
    }

    /// `missing-start`, `missing-thread` and codels named like reports.
    pub(super) fn service_structure(&mut self, id: ServiceId, s: &ast::Service) {
        let svc = &self.c.services[id];
        let thread_attr = s.attributes.iter().find(|a| a.name.name == "thread");
        let name = svc.name.clone();
        let mut found = Vec::new();
        for &cid in &svc.codels {
            let c = &self.c.codels[cid];
            if let Some(r) = svc.reports.iter().find(|r| r.name == c.name.name) {
                found.push(codel_transitions::codel_and_report(
                    &r.name,
                    c.name.span,
                    r.span,
                ));
            }
        }
        let first_exec = svc
            .codels
            .iter()
            .map(|&c| &self.c.codels[c])
            .find(|c| matches!(c.kind, CodelKind::Exec | CodelKind::Inter));
        if svc.start.is_none() {
            if let Some(t) = thread_attr {
                found.push(service_structure::missing_start(
                    &name.name,
                    name.span,
                    t.name.span,
                    "it names a thread",
                ));
            } else if let Some(c) = first_exec {
                let why = format!("it has {} codel `{}`", c.kind.keyword(), c.name.name);
                found.push(service_structure::missing_start(
                    &name.name,
                    name.span,
                    c.name.span,
                    &why,
                ));
            }
        } else if thread_attr.is_none() {
            let start = svc.start.map_or(name.span, |c| self.c.codels[c].name.span);
            let threads: Vec<&str> = self
                .c
                .threads
                .values()
                .map(|t| t.name.name.as_str())
                .collect();
            found.push(service_structure::missing_thread(
                &name.name, name.span, start, &threads,
            ));
        }
        self.diags.extend(found);
    }

    /// Resolves the body of every declared codel of a service.
    pub(super) fn codel_bodies(&mut self, codels: &[(CodelId, &ast::Codel)]) {
        for &(cid, c) in codels {
            let a = self.attrs(&c.attributes, "a codel", attrs::CODEL);
            let service = self.c.codels[cid].service;
            let call = self.call(service, c, &a);
            let update = a
                .data_refs("update")
                .iter()
                .filter_map(|r| self.data_path(r, Some(service)))
                .collect();
            let on_inter = self.on_inter(cid, c.kind, &a);
            let wcet = a
                .duration("max-time")
                .and_then(|d| self.positive_duration("max-time", d));
            let next = self.next(cid, c.kind, &a);
            let codel = &mut self.c.codels[cid];
            (codel.call, codel.update, codel.on_inter, codel.wcet) = (call, update, on_inter, wcet);
            codel.next_span = a.get("next").map(|n| n.span);
            codel.next = next;
        }
    }

    fn call(&mut self, service: ServiceId, c: &ast::Codel, a: &Attrs<'_>) -> Option<Call> {
        let Some(call) = a.call() else {
            self.report(invalid_attribute::missing_exec(&c.name.name, c.name.span));
            return None;
        };
        let args = call
            .args
            .iter()
            .map(|arg| Arg {
                is_const: arg.is_const,
                data: self.data_path(&arg.data, Some(service)),
                span: arg.span,
            })
            .collect();
        Some(Call {
            function: named(&call.function),
            args,
            span: call.span,
        })
    }

    fn on_inter(&mut self, cid: CodelId, kind: CodelKind, a: &Attrs<'_>) -> Option<Ref<CodelId>> {
        let target = a.ident("on-inter")?;
        if matches!(kind, CodelKind::Control | CodelKind::Inter) {
            let span = a.get("on-inter").map_or(target.span, |x| x.name.span);
            self.report(codel_transitions::on_inter_not_allowed(
                kind.keyword(),
                span,
            ));
            return None;
        }
        let service = self.c.codels[cid].service;
        let Some(found) = self.codel_named(service, &target.name) else {
            let candidates = self.codel_names(service, |k| k == CodelKind::Inter);
            self.report(unknown_name::unknown_inter_codel(
                &target.name,
                target.span,
                candidates.iter().map(String::as_str),
            ));
            return None;
        };
        let t = &self.c.codels[found];
        if t.kind != CodelKind::Inter {
            let d = codel_transitions::on_inter_not_inter(
                &target.name,
                t.kind.keyword(),
                target.span,
                t.name.span,
            );
            self.report(d);
            return None;
        }
        Some(Ref {
            id: found,
            span: target.span,
        })
    }

    fn next(&mut self, cid: CodelId, kind: CodelKind, a: &Attrs<'_>) -> Vec<Next> {
        let Some(attr) = a.get("next") else {
            return Vec::new();
        };
        if kind == CodelKind::Control {
            self.report(codel_transitions::next_on_control(attr.name.span));
            return Vec::new();
        }
        let service = self.c.codels[cid].service;
        let mut out: Vec<Next> = Vec::new();
        for name in a.idents("next") {
            let Some(outcome) = self.outcome(service, name) else {
                continue;
            };
            if let Some(first) = out.iter().find(|n| n.outcome == outcome) {
                self.report(codel_transitions::next_twice(
                    &name.name, name.span, first.span,
                ));
                continue;
            }
            out.push(Next {
                outcome,
                span: name.span,
            });
        }
        out
    }

    fn outcome(&mut self, service: ServiceId, name: &ast::Ident) -> Option<Outcome> {
        if name.name == "end" {
            return Some(Outcome::End);
        }
        if let Some(target) = self.codel_named(service, &name.name) {
            if self.c.codels[target].kind == CodelKind::Control {
                self.report(codel_transitions::next_to_control(name.span));
                return None;
            }
            return Some(Outcome::Codel(target));
        }
        if let Some(index) = self.c.services[service].report(&name.name) {
            return Some(Outcome::Report(index));
        }
        self.unknown_outcome(service, name);
        None
    }

    fn unknown_outcome(&mut self, service: ServiceId, name: &ast::Ident) {
        let elsewhere = self.c.codels.values().find(|c| {
            c.service != service && c.name.name == name.name && c.kind != CodelKind::Control
        });
        if let Some(other) = elsewhere {
            let owner = self.c.services[other.service].name.name.clone();
            let d = codel_transitions::next_to_other_service(
                &name.name,
                name.span,
                &owner,
                other.name.span,
            );
            self.report(d);
            return;
        }
        self.c.services[service].unresolved_next = true;
        let reports: Vec<String> = self.c.services[service]
            .reports
            .iter()
            .map(|r| r.name.clone())
            .collect();
        let looks_like_report = name.name.chars().any(char::is_alphabetic)
            && !name.name.chars().any(char::is_lowercase);
        let d = if looks_like_report {
            unknown_name::unknown_report(&name.name, name.span, reports.iter().map(String::as_str))
        } else {
            let mut candidates = self.codel_names(service, |k| k != CodelKind::Control);
            candidates.extend(reports);
            candidates.push("end".to_owned());
            unknown_name::unknown_codel(
                &name.name,
                name.span,
                candidates.iter().map(String::as_str),
            )
        };
        self.report(d);
    }

    fn codel_names(&self, service: ServiceId, keep: impl Fn(CodelKind) -> bool) -> Vec<String> {
        self.c.services[service]
            .codels
            .iter()
            .map(|&c| &self.c.codels[c])
            .filter(|c| keep(c.kind))
            .map(|c| c.name.name.clone())
            .collect()
    }
}

fn empty_codel(service: ServiceId, c: &ast::Codel) -> Codel {
    Codel {
        service,
        kind: c.kind,
        name: Named {
            name: c.name.name.clone(),
            span: c.name.span,
        },
        call: None,
        update: Vec::new(),
        on_inter: None,
        wcet: None,
        next: Vec::new(),
        next_span: None,
    }
}
