//! Lowering stub.
use genom_model::component::Component;
use genom_model::{Diagnostic, FileId};
use crate::ast::Ast;
/// Lowered.
#[derive(Debug, Default)]
pub struct LowerReturn { pub component: Option<Component>, pub diagnostics: Vec<Diagnostic>, pub has_component: bool, pub has_interface: bool }
/// Lowers.
pub fn lower(ast: &Ast, _root: FileId) -> LowerReturn { let _ = ast; LowerReturn::default() }
