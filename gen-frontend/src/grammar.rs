//! The pest parser generated from `grammar.pest` (documented rule by rule
//! there). Only this crate sees pest types.

use pest_derive::Parser;

/// The generated parser; its `Rule` enum has one variant per grammar rule.
#[derive(Parser)]
#[grammar = "grammar.pest"]
pub(crate) struct GenParser;
