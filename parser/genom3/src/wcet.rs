//! stub
use genom_model::component::Component;
use genom_model::{Diagnostic, FileId, SourceMap};
/// x
pub struct WcetReturn { pub entries: Vec<()>, pub diagnostics: Vec<Diagnostic> }
/// x
pub fn parse_wcet(_s: &SourceMap, _f: FileId) -> WcetReturn { WcetReturn { entries: vec![], diagnostics: vec![] } }
/// x
pub fn apply_wcets(_c: &mut Component, _e: &[()]) -> Vec<Diagnostic> { vec![] }
