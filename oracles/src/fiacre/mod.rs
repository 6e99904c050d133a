//! A reader and an interpreter of timed Fiacre models, for the tests of
//! the `fiacre` export of GenoM3 components: a second reading written
//! from the Fiacre language's reference (docs/exports/fiacre.md,
//! "Reference"), not from genom-check's emitter, so that what the export
//! means is checked by executing it.
//!
//! - [`lexer`] and [`parser`]: the text into a [`Program`] (processes,
//!   components, properties; no ports, functions or priorities);
//! - [`paths`]: the transitions of a process in a state, as Fiacre
//!   compiles a `from` clause (one per way through `select` and `if`);
//! - [`explore`]: the reachable symbolic states of the root component,
//!   clocks as zones ([`crate::ta_sim`]'s), in the subset of Fiacre's
//!   timing its module doc states.

pub mod ast;
pub mod explore;
pub mod lexer;
pub mod parser;
pub mod paths;

pub use ast::Program;
pub use explore::{Net, Reach};
pub use parser::parse;
