//! Data: IDS blocks (one lockable structure each, typed as an anonymous
//! struct of its members), export and import items (one structure each),
//! and data references resolved to a root and a typed member path.

use std::collections::BTreeMap;

use crate::Ast;
use crate::ast::{self, DataRef, Item, PathElem};
use genom_model::Diagnostic;
use genom_model::component::types::TypeTable as _;
use genom_model::component::{
    DataPath, DataRoot, Field, Param, ServiceId, Step, Structure, Ty, TypeDef, TypeKind,
};
use genom_model::kinds::DataKind;

use super::{Block, Resolver};
use crate::checks::{duplicate_definition, unknown_name};

impl Resolver {
    /// Declares every data block and its structures.
    pub(super) fn data_blocks(&mut self, ast: &Ast) {
        for item in ast.items() {
            let Item::Data(b) = item else { continue };
            if let Some(first) = self.names.blocks.get(&b.name.name) {
                let first = first.span;
                self.report(duplicate_definition::duplicate(
                    "data block",
                    &b.name.name,
                    b.name.span,
                    first,
                ));
                continue;
            }
            let block = match b.kind {
                DataKind::Ids => self.ids_block(b),
                DataKind::Export | DataKind::Import => self.item_block(b),
            };
            self.names.blocks.insert(b.name.name.clone(), block);
        }
    }

    fn ids_block(&mut self, b: &ast::DataBlock) -> Block {
        let mut fields: Vec<Field> = Vec::new();
        for m in &b.members {
            if let Some(prev) = fields.iter().find(|f| f.name == m.decl.name.name) {
                let first = prev.span;
                let name = format!("{}.{}", b.name.name, m.decl.name.name);
                self.report(duplicate_definition::duplicate(
                    "ids member",
                    &name,
                    m.decl.name.span,
                    first,
                ));
                continue;
            }
            let ty = self.ty_dims(&m.ty, &m.decl.dims, &[]);
            let default = m.init.as_ref().and_then(|v| self.value(v, &ty, &[]));
            let doc = m.doc.as_ref().map(|d| d.value.clone());
            fields.push(Field {
                name: m.decl.name.name.clone(),
                ty,
                span: m.decl.name.span,
                default,
                doc,
            });
        }
        let id = self.c.types.push(TypeDef {
            name: b.name.name.clone(),
            span: b.name.span,
            kind: TypeKind::Struct(fields),
        });
        let structure = self.c.structures.push(Structure {
            kind: DataKind::Ids,
            name: b.name.name.clone(),
            block: b.name.name.clone(),
            span: b.name.span,
            ty: Ty::Named { id },
            init: None,
            doc: None,
        });
        Block {
            kind: DataKind::Ids,
            span: b.name.span,
            items: BTreeMap::new(),
            ids: Some(structure),
        }
    }

    fn item_block(&mut self, b: &ast::DataBlock) -> Block {
        let mut items = BTreeMap::new();
        for m in &b.members {
            let name = &m.decl.name;
            if let Some(&prev) = self.names.items.get(&(b.kind, name.name.clone())) {
                let first = self.c.structures[prev].span;
                let what = format!("{} item", b.kind.keyword());
                self.report(duplicate_definition::duplicate(
                    &what, &name.name, name.span, first,
                ));
                continue;
            }
            let ty = self.ty_dims(&m.ty, &m.decl.dims, &[]);
            let init = m.init.as_ref().and_then(|v| self.value(v, &ty, &[]));
            let id = self.c.structures.push(Structure {
                kind: b.kind,
                name: name.name.clone(),
                block: b.name.name.clone(),
                span: name.span,
                ty,
                init,
                doc: m.doc.as_ref().map(|d| d.value.clone()),
            });
            self.names.items.insert((b.kind, name.name.clone()), id);
            items.insert(name.name.clone(), id);
        }
        Block {
            kind: b.kind,
            span: b.name.span,
            items,
            ids: None,
        }
    }

    /// Resolves a data reference; service parameters are visible when the
    /// reference is written in a codel of `service`.
    pub(super) fn data_path(
        &mut self,
        r: &DataRef,
        service: Option<ServiceId>,
    ) -> Option<DataPath> {
        let (root, mut ty, rest) = self.data_root(r, service)?;
        let mut steps = Vec::new();
        for elem in rest {
            let (step, next) = self.data_step(&ty, elem)?;
            steps.push(step);
            ty = next;
        }
        Some(DataPath {
            root,
            steps,
            ty,
            text: r.to_string(),
            span: r.span,
        })
    }

    fn data_root<'r>(
        &mut self,
        r: &'r DataRef,
        service: Option<ServiceId>,
    ) -> Option<(DataRoot, Ty, &'r [PathElem])> {
        let name = &r.root.name;
        if let Some(found) = service.and_then(|s| self.param_root(s, name)) {
            return Some((found.0, found.1, &r.path));
        }
        let Some(block) = self.names.blocks.get(name) else {
            let d = self.unknown_root(&r.root, service);
            self.report(d);
            return None;
        };
        if let Some(id) = block.ids {
            return Some((
                DataRoot::Structure(id),
                self.c.structures[id].ty.clone(),
                &r.path,
            ));
        }
        let kind = block.kind.keyword();
        let Some(PathElem::Field(item)) = r.path.first() else {
            let items = block.items.keys().map(String::as_str);
            let d = unknown_name::block_without_item(name, kind, r.root.span, items);
            self.report(d);
            return None;
        };
        let Some(&id) = block.items.get(&item.name) else {
            let items: Vec<String> = block.items.keys().map(|i| format!("{name}.{i}")).collect();
            let what = format!("{kind} item");
            let written = format!("{name}.{}", item.name);
            let candidates = items.iter().map(String::as_str);
            let d = unknown_name::unknown_data(&what, &written, item.span, candidates);
            self.report(d);
            return None;
        };
        Some((
            DataRoot::Structure(id),
            self.c.structures[id].ty.clone(),
            &r.path[1..],
        ))
    }

    /// The diagnostic of a data root that names nothing: a parameter of
    /// another service, or a typo among blocks and own parameters.
    fn unknown_root(&self, root: &ast::Ident, service: Option<ServiceId>) -> Diagnostic {
        let typed = |p: &&Param| p.data.is_none();
        let elsewhere = service.and_then(|own| {
            let others = self.c.services.iter().filter(|&(id, _)| id != own);
            others.map(|(_, s)| s).find_map(|s| {
                let mut params = s.inputs.iter().chain(&s.outputs).filter(typed);
                params.find(|p| p.name.name == root.name).map(|p| (s, p))
            })
        });
        if let Some((s, p)) = elsewhere {
            return unknown_name::other_service_param(
                &root.name,
                root.span,
                &s.name.name,
                p.name.span,
            );
        }
        let mut candidates: Vec<String> = self.names.blocks.keys().cloned().collect();
        if let Some(s) = service.and_then(|s| self.c.services.get(s)) {
            let params = s.inputs.iter().chain(&s.outputs).filter(typed);
            candidates.extend(params.map(|p| p.name.name.clone()));
        }
        unknown_name::unknown_data(
            "data",
            &root.name,
            root.span,
            candidates.iter().map(String::as_str),
        )
    }

    fn param_root(&self, service: ServiceId, name: &str) -> Option<(DataRoot, Ty)> {
        let s = self.c.services.get(service)?;
        let find = |list: &[Param], output: bool| {
            list.iter()
                .position(|p| p.name.name == name && p.data.is_none())
                .map(|index| {
                    (
                        DataRoot::Param {
                            service,
                            output,
                            index,
                        },
                        list[index].ty.clone(),
                    )
                })
        };
        find(&s.inputs, false).or_else(|| find(&s.outputs, true))
    }

    fn data_step(&mut self, ty: &Ty, elem: &PathElem) -> Option<(Step, Ty)> {
        match elem {
            PathElem::Field(f) => {
                // The field names are gathered only for the diagnostic
                // (cloning them all for every reference made resolving
                // quadratic in the size of a large `ids`).
                let struct_id = match self.c.types.resolve(ty) {
                    Ty::Named { id } => Some(*id),
                    _ => None,
                };
                let index = &mut self.names.fields;
                let found = self.c.types.fields(ty).map(|fs| {
                    field_position(index, struct_id, fs, &f.name)
                        .and_then(|k| fs.get(k))
                        .map(|x| x.ty.clone())
                        .ok_or_else(|| fs.iter().map(|x| x.name.clone()).collect::<Vec<_>>())
                });
                match found {
                    Some(Ok(t)) => Some((Step::Field(f.name.clone()), t)),
                    Some(Err(names)) => {
                        let shown = self.show(ty);
                        self.report(unknown_name::unknown_field(
                            &f.name,
                            &shown,
                            f.span,
                            names.iter().map(String::as_str),
                        ));
                        None
                    }
                    None if matches!(self.c.types.resolve(ty), Ty::Error) => None,
                    None => {
                        let shown = self.show(ty);
                        self.report(unknown_name::unknown_field(&f.name, &shown, f.span, []));
                        None
                    }
                }
            }
            PathElem::Index(n, span) => self.index_step(ty, *n, *span),
        }
    }

    fn index_step(&mut self, ty: &Ty, n: u64, span: genom_model::Span) -> Option<(Step, Ty)> {
        let (elem, bound) = match self.c.types.resolve(ty) {
            Ty::Array { elem, len } => ((**elem).clone(), Some(*len)),
            Ty::Sequence { elem, bound } => ((**elem).clone(), *bound),
            Ty::Error => return None,
            _ => {
                let shown = self.show(ty);
                self.report(unknown_name::bad_index(
                    n,
                    &shown,
                    span,
                    "it is not an array or sequence",
                ));
                return None;
            }
        };
        if let Some(max) = bound.filter(|&m| n >= m) {
            let shown = self.show(ty);
            let why = format!("the index must be below {max}");
            self.report(unknown_name::bad_index(n, &shown, span, &why));
            return None;
        }
        Some((Step::Index(n), elem))
    }
}

/// Where field `name` is among `fields` (of struct type `id`): a linear
/// search in a small struct; in a large one (an `ids` of thousands of
/// members), an index built once per type, so that resolving every
/// reference stays linear in the component.
fn field_position(
    index: &mut BTreeMap<genom_model::component::TypeId, (usize, BTreeMap<String, usize>)>,
    id: Option<genom_model::component::TypeId>,
    fields: &[Field],
    name: &str,
) -> Option<usize> {
    const SMALL: usize = 32;
    let Some(id) = id.filter(|_| fields.len() > SMALL) else {
        return fields.iter().position(|x| x.name == name);
    };
    let (len, map) = index.entry(id).or_default();
    // Built again if the struct changed since (a forward declaration
    // completed): the index always matches the fields it is used with.
    if *len != fields.len() {
        *len = fields.len();
        map.clear();
        for (k, f) in fields.iter().enumerate().rev() {
            map.insert(f.name.clone(), k);
        }
    }
    map.get(name).copied()
}
