//! genom-check as a library: the whole check of a file (the front-end
//! lowers the text into the component model, the checker checks it) and
//! the `explain` texts of every diagnostic code. It never prints: only the
//! binary does.

pub mod explain;
mod pipeline;
mod system;
mod types;

pub use pipeline::{
    CheckOptions, FRONTENDS, check_file, check_path, check_source, check_text, detect, frontend,
};
pub use system::{SystemResult, check_system};
pub use types::{CheckResult, InputError, Inputs, display, is_stdin};
