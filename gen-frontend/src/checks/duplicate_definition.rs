//! `duplicate-definition`: two things of one kind share a name in one scope
//! (types and constants in one IDL module, data blocks, members of a block,
//! threads, services, codels or reports of a service, parameters,
//! credential classes, or a second `component`).

use genom_model::{Code, Diagnostic, Span};

/// `genom-check explain duplicate-definition`.
pub const EXPLANATION: &str = r#"Two definitions of the same kind share a name in the same scope: two
services, two threads, two codels or reports of one service, two members of
one data block, two types or constants in one IDL module, two credential
classes, or a second `component` item. Both places are labelled.

Why it matters: every reference to the name would be ambiguous. The
`control` thread is implicit and cannot be declared.

Example:

```
service move { ... }
service move { ... }    // duplicate-definition: the service `move` is defined twice
```"#;

/// `what` named `name` is defined at `first` and again at `second`.
pub fn duplicate(what: &str, name: &str, second: Span, first: Span) -> Diagnostic {
    Diagnostic::new(
        Code::DuplicateDefinition,
        format!("the {what} `{name}` is defined twice"),
        second,
        "defined again here",
    )
    .with_label(first, "first defined here")
    .with_help(format!("rename one of them or remove the second {what}"))
}

/// A thread declared with the name of the implicit control thread.
pub fn control_thread(span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::DuplicateDefinition,
        "the thread `control` is the implicit control thread and cannot be declared",
        span,
        "clashes with the implicit control thread",
    )
    .with_help("choose another name; control codels always run in the control thread")
}
