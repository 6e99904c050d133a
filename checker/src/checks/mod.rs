//! The static checks, one file per check with its explanation, its
//! diagnostic constructors and its pass/fail tests. Resolution checks are
//! reported by the resolver through these constructors; model checks
//! (`check` functions) run on the resolved component.

pub mod codel_transitions;
pub mod duplicate_definition;
pub mod invalid_attribute;
pub mod missing_component;
pub mod prototype_mismatch;
pub mod service_structure;
pub mod type_mismatch;
pub mod unknown_name;
pub mod update_rules;

use genom_model::Diagnostic;
use genom_model::component::Component;

/// Runs every check on the resolved model.
pub fn run(component: &Component) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    out.extend(prototype_mismatch::check(component));
    out.extend(update_rules::check(component));
    out
}
