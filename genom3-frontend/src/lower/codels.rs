//! Codels and data paths: resolves codel parameters (explicit source, or
//! service parameter or local, then ids member, then port, then remote, as
//! GenoM3 looks them up), ids member paths with their types, and builds the
//! model codels: one per state of an activity's FSM codels, control codels
//! for `validate` and a function's `codel`, and the permanent codels of
//! tasks (GenoM3 facts only).

use std::collections::{BTreeMap, BTreeSet};

use genom_model::component::genom3::{
    CodelInfo, CodelParam as MParam, FsmCodel, ParamSource, Yield,
};
use genom_model::component::types::TypeTable as _;
use genom_model::component::{
    Arg, Call, Codel, CodelId, DataPath, DataRoot, Field, Idx as _, Named, Next, Outcome, Ref,
    ServiceId, Step, Ty, Value,
};
use genom_model::kinds::BaseType;
use genom_model::kinds::CodelKind;
use genom_model::{Code, Span};

use super::closest_hint;
use super::component::Ctx;
use crate::ast::{self, Dir, PathStep, PropertyKind, Source};
use crate::diagnostics;

impl Ctx<'_> {
    pub(super) fn whole_ids(&mut self, span: Span, name: &str) -> Option<DataPath> {
        let ids = self.ids?;
        Some(DataPath {
            root: DataRoot::Structure(ids),
            steps: Vec::new(),
            ty: self.c.structures[ids].ty.clone(),
            text: name.to_owned(),
            span,
        })
    }

    /// Resolves an ids member path, diagnosing unknown members.
    pub(super) fn ids_path(&mut self, path: &ast::MemberPath) -> Option<DataPath> {
        let ids = self.ids;
        let root_ty = ids.map(|i| self.c.structures[i].ty.clone());
        let (Some(ids), Some(root_ty)) = (ids, root_ty) else {
            self.diags.push(diagnostics::unknown(
                Code::UnknownData,
                "ids member",
                &path.root.name,
                path.root.span,
                None,
            ));
            return None;
        };
        let mut steps = vec![Step::Field(path.root.name.clone())];
        let mut names = vec![&path.root];
        for s in &path.steps {
            match s {
                PathStep::Field(f) => {
                    steps.push(Step::Field(f.name.clone()));
                    names.push(f);
                }
                PathStep::Index(e) => {
                    let i = self.types.positive(e, &self.scope.clone()).unwrap_or(0);
                    steps.push(Step::Index(i));
                }
            }
        }
        let mut ty = root_ty;
        let mut named = names.iter();
        for step in &steps {
            ty = match step {
                Step::Field(f) => {
                    let fields = self.types.defs.fields(&ty).map(<[Field]>::to_vec);
                    let span = named.next().map_or(path.span, |n| n.span);
                    match fields
                        .as_ref()
                        .and_then(|fs| fs.iter().find(|x| &x.name == f))
                    {
                        Some(field) => field.ty.clone(),
                        None => {
                            let cands: Vec<String> = fields
                                .unwrap_or_default()
                                .into_iter()
                                .map(|x| x.name)
                                .collect();
                            let hint = closest_hint(f, cands.iter());
                            self.diags.push(diagnostics::unknown(
                                Code::UnknownData,
                                "ids member",
                                f,
                                span,
                                hint.as_deref(),
                            ));
                            return None;
                        }
                    }
                }
                Step::Index(_) => match self.types.defs.resolve(&ty) {
                    Ty::Array { elem, .. } | Ty::Sequence { elem, .. } => (**elem).clone(),
                    _ => Ty::Error,
                },
            };
        }
        Some(DataPath {
            root: DataRoot::Structure(ids),
            steps: steps.into_iter().skip(1).collect(),
            ty,
            text: path_text(path),
            span: path.span,
        })
    }

    /// Lowers one codel's parameters and yields (GenoM3 facts only).
    pub(crate) fn fsm_codel(
        &mut self,
        c: &ast::Codel,
        service: Option<ServiceId>,
        _scope: &[String],
    ) -> FsmCodel {
        let params: Vec<MParam> = c
            .params
            .iter()
            .map(|p| self.codel_param(p, service))
            .collect();
        for (i, p) in params.iter().enumerate() {
            if let Some(first) = params[..i]
                .iter()
                .find(|q| q.name == p.name && !p.name.is_empty())
            {
                self.diags.push(diagnostics::duplicate(
                    "codel parameter",
                    &p.name,
                    p.span,
                    first.span,
                ));
            }
        }
        let named = |i: &ast::Ident| Named {
            name: i.name.clone(),
            span: i.span,
        };
        FsmCodel {
            states: c.states.iter().map(|e| named(&e.name)).collect(),
            function: named(&c.function),
            yields: c
                .yields
                .iter()
                .map(|e| Yield {
                    state: named(&e.name),
                    pause: e.pause,
                })
                .collect(),
            is_async: c.is_async,
            params,
            wcet: None,
            span: c.span,
        }
    }

    fn codel_param(&mut self, p: &ast::CodelParam, service: Option<ServiceId>) -> MParam {
        let dir = match p.dir {
            Dir::In => "in",
            Dir::Out => "out",
            Dir::InOut => "inout",
        };
        let path = p.path.as_ref().map_or_else(String::new, path_text);
        let name = p
            .rename
            .as_ref()
            .map(|r| r.name.clone())
            .or_else(|| p.path.as_ref().map(|x| x.last().name.clone()))
            .unwrap_or_default();
        let root = p.path.as_ref().map(|x| x.root.name.clone());
        let is_local = |ctx: &Self| {
            service
                .zip(root.as_ref())
                .is_some_and(|(s, r)| ctx.locals.get(&s).is_some_and(|t| t.contains_key(r)))
        };
        let is_port = |ctx: &Self| {
            root.as_ref()
                .is_some_and(|r| ctx.g.ports.iter().any(|q| &q.name.name == r))
        };
        let is_remote = |ctx: &Self| {
            root.as_ref()
                .is_some_and(|r| ctx.g.remotes.iter().any(|q| &q.name.name == r))
        };
        let is_ids = |ctx: &Self| {
            let Some(ids) = ctx.ids else { return false };
            match &root {
                None => true,
                Some(r) => ctx
                    .types
                    .defs
                    .fields(&ctx.c.structures[ids].ty)
                    .is_some_and(|fs| fs.iter().any(|f| &f.name == r)),
            }
        };
        let source = match p.src {
            Some(Source::Ids) => Some(ParamSource::Ids),
            Some(Source::Local) => Some(ParamSource::Local),
            Some(Source::Port) => Some(ParamSource::Port),
            Some(Source::Remote) => Some(ParamSource::Remote),
            None if root.is_none() => Some(ParamSource::Ids),
            None if is_local(self) => Some(ParamSource::Local),
            None if is_ids(self) => Some(ParamSource::Ids),
            None if is_port(self) => Some(ParamSource::Port),
            None if is_remote(self) => Some(ParamSource::Remote),
            None => None,
        };
        if p.src.is_none() && root.is_some() {
            let matches: Vec<&str> = [
                (is_local(self), "a service parameter or local"),
                (is_ids(self), "an ids member"),
                (is_port(self), "a port"),
                (is_remote(self), "a remote"),
            ]
            .into_iter()
            .filter_map(|(hit, what)| hit.then_some(what))
            .collect();
            if matches.len() > 1 {
                let span = p.path.as_ref().map_or(p.span, |x| x.root.span);
                self.diags.push(diagnostics::missing_source(
                    root.as_deref().unwrap_or_default(),
                    span,
                    &matches,
                ));
            }
        }
        let ok = match source {
            Some(ParamSource::Ids) => match &p.path {
                Some(path) => self.ids_path(path).is_some(),
                None => self.ids.is_some(),
            },
            Some(ParamSource::Local) => is_local(self),
            Some(ParamSource::Port) => is_port(self),
            Some(ParamSource::Remote) => is_remote(self),
            None => false,
        };
        if !ok && source != Some(ParamSource::Ids) {
            let what = match source {
                Some(ParamSource::Local) => "parameter or local",
                Some(ParamSource::Port) => "port",
                Some(ParamSource::Remote) => "remote",
                _ => "codel parameter source",
            };
            let mut cands: Vec<String> = self.g.ports.iter().map(|q| q.name.name.clone()).collect();
            cands.extend(self.g.remotes.iter().map(|q| q.name.name.clone()));
            if let Some(t) = service.and_then(|s| self.locals.get(&s)) {
                cands.extend(t.keys().cloned());
            }
            if let Some(fs) = self
                .ids
                .and_then(|i| self.types.defs.fields(&self.c.structures[i].ty))
            {
                cands.extend(fs.iter().map(|f| f.name.clone()));
            }
            let r = root.clone().unwrap_or_default();
            let hint = closest_hint(&r, cands.iter());
            let span = p.path.as_ref().map_or(p.span, |x| x.root.span);
            self.diags.push(diagnostics::unknown(
                Code::UnknownData,
                what,
                &r,
                span,
                hint.as_deref(),
            ));
        }
        MParam {
            source: source.unwrap_or(ParamSource::Ids),
            dir: dir.to_owned(),
            path,
            name,
            span: p.span,
        }
    }

    /// The model argument of a resolved parameter.
    fn arg(&self, p: &MParam, service: ServiceId) -> Arg {
        let root = p.path.split(['.', '[']).next().unwrap_or_default();
        let data = match p.source {
            ParamSource::Ids => self.ids.map(|ids| DataPath {
                root: DataRoot::Structure(ids),
                steps: if root.is_empty() {
                    Vec::new()
                } else {
                    vec![Step::Field(root.to_owned())]
                },
                ty: Ty::Error,
                text: if p.path.is_empty() {
                    "ids".to_owned()
                } else {
                    p.path.clone()
                },
                span: p.span,
            }),
            ParamSource::Port => self
                .g
                .ports
                .iter()
                .find(|q| q.name.name == root)
                .and_then(|q| {
                    q.structure.map(|s| DataPath {
                        root: DataRoot::Structure(s),
                        steps: Vec::new(),
                        ty: q.ty.clone(),
                        text: p.path.clone(),
                        span: p.span,
                    })
                }),
            ParamSource::Local => self
                .locals
                .get(&service)
                .and_then(|t| t.get(root))
                .copied()
                .flatten()
                .map(|(output, index)| DataPath {
                    root: DataRoot::Param {
                        service,
                        output,
                        index,
                    },
                    steps: Vec::new(),
                    ty: Ty::Error,
                    text: p.path.clone(),
                    span: p.span,
                }),
            ParamSource::Remote => None,
        };
        Arg {
            is_const: p.dir == "in",
            data,
            span: p.span,
        }
    }

    /// Checks an initializer against its type: a scalar cannot initialize
    /// a struct or array, and designated members must exist.
    /// Why the default `e` of a scalar of type `ty` cannot be one: a
    /// number out of the type's range, or a string for a number or a
    /// boolean. Other mismatches (an enumerator, `0` for a boolean) are
    /// left to GenoM3's C compiler, as genom3 does.
    fn default_misfit(&self, ty: &Ty, e: &ast::Expr) -> Option<String> {
        let value = self.types.eval(e, &self.scope).ok()?;
        let numeric =
            matches!(ty, Ty::Base { base } if base.integer_range().is_some() || base.is_float());
        match value {
            Value::Str(_)
                if numeric
                    || matches!(
                        ty,
                        Ty::Base {
                            base: BaseType::Boolean
                        }
                    ) =>
            {
                Some("a string cannot be the default of a number or a boolean".to_owned())
            }
            Value::Int(_) | Value::Float(_) if numeric => self.types.fits(ty, value).err(),
            _ => None,
        }
    }

    pub(super) fn check_init(&mut self, param: &str, v: &ast::InitValue, ty: &Ty) {
        let resolved = self.types.defs.resolve(ty).clone();
        let fields: Option<Vec<Field>> = self.types.defs.fields(&resolved).map(<[Field]>::to_vec);
        let elem = match &resolved {
            Ty::Array { elem, .. } | Ty::Sequence { elem, .. } => Some((**elem).clone()),
            _ => None,
        };
        match v {
            ast::InitValue::Expr(e) => {
                if fields.is_some() || matches!(resolved, Ty::Array { .. }) {
                    self.diags
                        .push(diagnostics::scalar_for_compound(param, e.span));
                } else if let Some(why) = self.default_misfit(&resolved, e) {
                    self.diags.push(diagnostics::bad_constant(e.span, &why));
                }
            }
            ast::InitValue::List(items) => {
                for (i, item) in items.iter().enumerate() {
                    let Some(value) = &item.value else { continue };
                    let positional = match value {
                        ast::InitValue::Field(..) | ast::InitValue::Index(..) => None,
                        _ => fields
                            .as_ref()
                            .and_then(|f| f.get(i).map(|f| f.ty.clone()))
                            .or_else(|| elem.clone()),
                    };
                    match positional {
                        Some(t) => self.check_init(param, value, &t),
                        None => self.check_init(param, value, &resolved),
                    }
                }
            }
            ast::InitValue::Field(f, sub) => match &fields {
                Some(fs) => match fs.iter().find(|x| x.name == f.name) {
                    Some(field) => {
                        if let Some(sub) = sub {
                            self.check_init(param, sub, &field.ty.clone());
                        }
                    }
                    None => {
                        let names: Vec<String> = fs.iter().map(|x| x.name.clone()).collect();
                        let hint = closest_hint(&f.name, names.iter());
                        self.diags.push(diagnostics::unknown(
                            Code::UnknownData,
                            "member",
                            &f.name,
                            f.span,
                            hint.as_deref(),
                        ));
                    }
                },
                None if resolved != Ty::Error => self.diags.push(diagnostics::unknown(
                    Code::UnknownData,
                    "member",
                    &f.name,
                    f.span,
                    None,
                )),
                None => {}
            },
            ast::InitValue::Index(_, sub) => {
                if let (Some(sub), Some(elem)) = (sub, elem) {
                    self.check_init(param, sub, &elem);
                }
            }
        }
    }

    /// The output ports a codel writes (GenoM3 publishes them after the
    /// codel runs): the model's `update`.
    fn published(&self, call: &Call) -> Vec<DataPath> {
        call.args
            .iter()
            .filter(|a| !a.is_const)
            .filter_map(|a| a.data.clone())
            .filter(|d| {
                d.structure().is_some_and(|s| {
                    self.c.structures[s].kind == genom_model::kinds::DataKind::Export
                })
            })
            .collect()
    }

    fn call(&self, f: &FsmCodel, service: ServiceId) -> Call {
        Call {
            function: f.function.clone(),
            args: f.params.iter().map(|p| self.arg(p, service)).collect(),
            span: f.span,
        }
    }

    pub(super) fn control_codel(&mut self, id: ServiceId, name: &str, f: FsmCodel) {
        let call = self.call(&f, id);
        let update = self.published(&call);
        let codel = self.c.codels.push(Codel {
            service: id,
            kind: CodelKind::Control,
            name: Named {
                name: name.to_owned(),
                span: f.function.span,
            },
            call: Some(call),
            update,
            on_inter: None,
            wcet: None,
            next: Vec::new(),
            next_span: None,
        });
        let svc = &mut self.c.services[id];
        svc.codels.push(codel);
        svc.control.get_or_insert(codel);
        self.g.codels.push(CodelInfo { codel, fsm: f });
    }

    /// One model codel per state of an activity's FSM codels.
    pub(super) fn state_codels(&mut self, id: ServiceId, fsm: &[FsmCodel]) {
        let mut by_state: BTreeMap<String, CodelId> = BTreeMap::new();
        for f in fsm {
            for state in &f.states {
                let kind = match state.name.as_str() {
                    "start" => CodelKind::Start,
                    "stop" => CodelKind::Inter,
                    _ => CodelKind::Exec,
                };
                let call = self.call(f, id);
                let update = self.published(&call);
                let codel = self.c.codels.push(Codel {
                    service: id,
                    kind,
                    name: state.clone(),
                    call: Some(call),
                    update,
                    on_inter: None,
                    wcet: None,
                    next: Vec::new(),
                    next_span: f.yields.first().map(|y| y.state.span),
                });
                by_state.entry(state.name.clone()).or_insert(codel);
                self.c.services[id].codels.push(codel);
                self.g.codels.push(CodelInfo {
                    codel,
                    fsm: f.clone(),
                });
                let svc = &mut self.c.services[id];
                if kind == CodelKind::Start {
                    svc.start.get_or_insert(codel);
                }
            }
        }
        let stop = by_state.get("stop").copied();
        let codels = self.c.services[id].codels.clone();
        for codel in codels {
            // Codels are pushed to the model and to `g.codels` together:
            // a codel's index is its place in both.
            let Some(info) = self
                .g
                .codels
                .get(codel.index())
                .filter(|i| i.codel == codel)
            else {
                continue;
            };
            let next: Vec<Next> = info
                .fsm
                .yields
                .iter()
                .filter_map(|y| {
                    let outcome = if y.state.name == "ether" {
                        Outcome::End
                    } else {
                        Outcome::Codel(*by_state.get(&y.state.name)?)
                    };
                    Some(Next {
                        outcome,
                        span: y.state.span,
                    })
                })
                .collect();
            let c = &mut self.c.codels[codel];
            c.next = next;
            if c.kind != CodelKind::Inter && c.kind != CodelKind::Control {
                c.on_inter = stop.map(|s| Ref {
                    id: s,
                    span: c.name.span,
                });
            }
        }
        // Port parameters are imports and exports of the service.
        let mut imports = BTreeSet::new();
        let mut exports = BTreeSet::new();
        for f in fsm {
            for p in f.params.iter().filter(|p| p.source == ParamSource::Port) {
                let root = p.path.split(['.', '[']).next().unwrap_or_default();
                if let Some(port) = self.g.ports.iter().find(|q| q.name.name == root) {
                    if let Some(s) = port.structure {
                        if port.is_out {
                            exports.insert(s)
                        } else {
                            imports.insert(s)
                        };
                    }
                }
            }
        }
        let svc = &mut self.c.services[id];
        svc.imports = imports
            .into_iter()
            .map(|id| Ref {
                id,
                span: Span::default(),
            })
            .collect();
        svc.exports = exports
            .into_iter()
            .map(|id| Ref {
                id,
                span: Span::default(),
            })
            .collect();
    }

    pub(super) fn task_codels(&mut self, t: &ast::Task, scope: &[String]) {
        let Some(tid) = self.c.thread_named(&t.name.name) else {
            return;
        };
        let codels: Vec<FsmCodel> = t
            .properties
            .iter()
            .filter_map(|p| match &p.kind {
                PropertyKind::Codel(c) => Some(c),
                _ => None,
            })
            .map(|c| self.fsm_codel(c, None, scope))
            .collect();
        if let Some(task) = self.g.tasks.iter_mut().find(|x| x.thread == tid) {
            task.codels.clone_from(&codels);
        }
        if !codels.is_empty() {
            self.machines
                .push((t.name.name.clone(), t.name.span, codels, Some(tid)));
        }
    }
}

/// `a.b[2]` as written.
pub(super) fn path_text(p: &ast::MemberPath) -> String {
    let mut s = p.root.name.clone();
    for step in &p.steps {
        match step {
            PathStep::Field(f) => {
                s.push('.');
                s.push_str(&f.name);
            }
            PathStep::Index(e) => match &e.kind {
                ast::ExprKind::Int(i) => s.push_str(&format!("[{i}]")),
                _ => s.push_str("[...]"),
            },
        }
    }
    s
}
