//! The shared foundation of genom-check: source spans and files, the one
//! diagnostic type with its stable codes, traces and their rendering (human
//! reports with miette, and the versioned JSON document); the resolved
//! component model that every verification stage and export reads.

pub mod behaviour;
pub mod component;
pub mod diagnostic;
pub mod dialect;
mod duration;
pub mod frontend;
pub mod kinds;
pub mod limits;
pub mod loader;
pub mod nesting;
pub mod petri;
pub mod render;
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
