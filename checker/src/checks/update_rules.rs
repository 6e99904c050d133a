//! `update-not-argument` and `const-update`: each `update:` entry must be a
//! non-`const` argument of the codel's `exec` (LANGUAGE.md 2.7).

use genom_model::{Code, Diagnostic, Span};

/// `genom-check explain update-not-argument`.
pub const EXPLANATION_NOT_ARGUMENT: &str = r#"An `update:` entry is not an argument of the codel's `exec`.

Why it matters: `update` tells the engine which data the codel wrote so that
it refreshes or publishes them; a codel can only write the data it is given.

Example:

```
exec codel goto {
  exec: go(demoIds.distRef);
  update: demoExport.state;     // update-not-argument
}
```"#;

/// `genom-check explain const-update`.
pub const EXPLANATION_CONST: &str = r#"An `update:` entry is passed `const` (read-only) to the codel function.

Why it matters: a codel cannot write data it receives read-only, so
publishing it after the codel runs would publish nothing new; either the
argument should not be `const` or the update is wrong.

Example:

```
exec codel goto {
  exec: go(const demoExport.state);
  update: demoExport.state;     // const-update
}
```"#;

/// An update entry that is not an argument.
pub fn not_argument(data: &str, span: Span, call: Span) -> Diagnostic {
    Diagnostic::new(
        Code::UpdateNotArgument,
        format!("`{data}` is updated but is not an argument of `exec`"),
        span,
        "not an argument",
    )
    .with_label(call, "the codel's arguments")
    .with_help(format!(
        "pass `{data}` to the codel function, or remove it from `update`"
    ))
}

/// An update entry passed `const`.
pub fn const_update(data: &str, span: Span, arg: Span) -> Diagnostic {
    Diagnostic::new(
        Code::ConstUpdate,
        format!("`{data}` is updated but passed `const`"),
        span,
        "updated here",
    )
    .with_label(arg, "passed read-only here")
    .with_help("remove `const` from the argument, or remove the entry from `update`")
}

use genom_model::component::{Component, DataPath};

fn same_data(a: &DataPath, b: &DataPath) -> bool {
    a.root == b.root && a.steps == b.steps
}

/// Checks every `update` entry of every codel against its `exec` arguments.
pub fn check(c: &Component) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for codel in c.codels.values() {
        let Some(call) = &codel.call else { continue };
        for entry in &codel.update {
            match call
                .args
                .iter()
                .find(|a| a.data.as_ref().is_some_and(|d| same_data(d, entry)))
            {
                None => out.push(not_argument(&entry.text, entry.span, call.span)),
                Some(arg) if arg.is_const => {
                    out.push(const_update(&entry.text, entry.span, arg.span));
                }
                Some(_) => {}
            }
        }
    }
    out
}
