//! The shared foundation of genom-check: source spans and files, the one
//! diagnostic type with its stable codes, traces, durations as people read
//! them; the resolved component model that every verification stage and
//! export reads, its service machines ([`behaviour`]), and the data of the
//! networks it translates into (the [`timed_automata`] network and the
//! [`petri`] net, which the exports print and the test oracles interpret).
//!
//! It is the ground floor: it depends on no other crate of the workspace.
//! Rendering diagnostics (`genom-render`) and building the networks and nets
//! (`genom-translate`) live above it, so that a change there does not
//! rebuild the engines.

pub mod behaviour;
pub mod component;
pub mod diagnostic;
pub mod dialect;
pub mod duration;
pub mod frontend;
pub mod graph;
pub mod kinds;
pub mod limits;
pub mod loader;
pub mod nesting;
pub mod petri;
pub mod response;
pub mod span;
pub mod stats;
pub mod timed_automata;
pub mod trace;

pub use diagnostic::{Code, Counts, Diagnostic, Label, Severity, sort_diagnostics};
pub use dialect::{Dialect, Pragma};
pub use response::{Bound, ResponseTime};
pub use span::{FileId, Located, SourceFile, SourceMap, Span};
pub use stats::{Assumption, Statistics};
pub use trace::{Event, Trace, TraceStep};
