//! `invalid-attribute`: an attribute in a place where it means nothing, given
//! twice, or with a bad value (a non-positive period or duration, a missing
//! `exec`, an `auto` service input without default). Unknown attribute
//! names and durations that are not whole nanoseconds are found by the
//! parser with the same code.

use genom_model::{Code, Diagnostic, Span};

/// `genom-check explain invalid-attribute`.
pub const EXPLANATION: &str = r#"An attribute that is unknown, not allowed where it is written, given twice,
or whose value is not acceptable:

- an attribute name the language does not know (`perod:`), with the closest
  known name as help;
- a known attribute in the wrong place (`period:` in a service, `thread:`
  in a codel);
- the same attribute twice in one block;
- a period, `max-time` or stack that is not positive, or a duration that is
  not a whole number of nanoseconds (`0.5ns`);
- a codel without `exec`, or an `auto` service input without a default
  (nobody sends the request of an auto service, so its inputs must have
  defaults).

Why it matters: such an attribute is silently meaningless to the engine;
the description does not say what its author thinks.

Example:

```
thread motionTask { period: 0s; }   // invalid-attribute: the period must be positive
service move { period: 10ms; }      // invalid-attribute: `period` is not allowed in a service
```"#;

/// A known attribute where it is not allowed.
pub fn not_allowed(name: &str, span: Span, place: &str, allowed: &[&str]) -> Diagnostic {
    let list: Vec<String> = allowed.iter().map(|a| format!("`{a}`")).collect();
    Diagnostic::new(
        Code::InvalidAttribute,
        format!("`{name}` is not allowed in {place}"),
        span,
        "not allowed here",
    )
    .with_help(format!("{place} takes {}", list.join(", ")))
}

/// An attribute given twice in one block.
pub fn given_twice(name: &str, second: Span, first: Span) -> Diagnostic {
    Diagnostic::new(
        Code::InvalidAttribute,
        format!("`{name}` is given twice"),
        second,
        "given again here",
    )
    .with_label(first, "first given here")
    .with_help("keep one of them")
}

/// A duration or size that must be positive.
pub fn not_positive(name: &str, span: Span, text: &str) -> Diagnostic {
    Diagnostic::new(
        Code::InvalidAttribute,
        format!("`{name}` must be positive, not `{text}`"),
        span,
        "not positive",
    )
}

/// A codel without an `exec` attribute.
pub fn missing_exec(codel: &str, span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::InvalidAttribute,
        format!("codel `{codel}` has no `exec`"),
        span,
        "no codel function",
    )
    .with_help("name the codel function and its arguments: `exec: f(ids.member);`")
}

/// An `auto` service input without a default value.
pub fn auto_input_without_default(service: &str, input: &str, span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::InvalidAttribute,
        format!("input `{input}` of auto service `{service}` has no default"),
        span,
        "no default value",
    )
    .with_help("auto services are started by the component itself, so every input needs `:= value`")
}
