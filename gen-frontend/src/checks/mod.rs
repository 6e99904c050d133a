//! The checks that resolution raises, one file per check with its
//! explanation (for `genom-check explain`) and its diagnostic constructors:
//! unknown names, duplicates, attributes, types, service structure and
//! codel transitions. Their pass/fail tests run the whole check and live in
//! the checker's file of the same name (`checker/src/checks/`).

pub mod codel_transitions;
pub mod duplicate_definition;
pub mod invalid_attribute;
pub mod missing_component;
pub mod service_structure;
pub mod type_mismatch;
pub mod unknown_name;
