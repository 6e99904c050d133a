//! `missing-component`: a file with no `component` item.
//!
//! Every description describes exactly one component; without the item there
//! is nothing to verify. (A second `component` item is
//! `duplicate-definition`.)

use genom_model::{Code, Diagnostic, Span};

/// `genom-check explain missing-component`.
pub const EXPLANATION: &str = r#"The file has no `component` item. A description file describes exactly one
component: its name, the engine category and the codel language.

Why it matters: services, threads and data belong to a component; without
it the file cannot be verified or exported.

Example:

```
thread motionTask { period: 1s; }      // missing-component: add
component pilot { category: default; lang: C; }
```"#;

/// The file has no `component` item; `start` is the start of the file.
pub fn missing_component(start: Span) -> Diagnostic {
    Diagnostic::new(
        Code::MissingComponent,
        "no `component` item in this file",
        start,
        "the file starts here",
    )
    .with_help("declare the component, e.g. `component pilot { category: default; lang: C; }`")
}
