//! `unknown-type`, `unknown-data`, `unknown-thread`, `unknown-service`,
//! `unknown-codel`, `unknown-report`, `unknown-credential`: a name that
//! resolves to nothing. The help names the closest existing name, when one
//! is close enough to be a typo.

use genom_model::diagnostic::closest;
use genom_model::{Code, Diagnostic, Span};

/// `genom-check explain unknown-...` (shared by the seven codes).
pub const EXPLANATION: &str = r#"A name that resolves to nothing: a type, a data reference (IDS member,
export or import item, service parameter, or a field or index inside one),
a thread, a service, a codel of the same service, a report of the same
service, or a credential class. The help suggests the closest existing name
when there is one.

Why it matters: the component cannot be built or verified with a dangling
reference; most often it is a typo.

Example:

```
ids demoIds { double distRef; }
service move {
  thread: motionTsk;                        // unknown-thread: did you mean `motionTask`?
  control codel { exec: check(demoIds.distRf); }   // unknown-data: did you mean `distRef`?
}
```

Names resolve across the whole file (order does not matter). IDL names
resolve from the current module outwards; `::m::T` is absolute. In a codel
argument, the parameters of the codel's own service come first, then IDS
blocks, then export and import blocks (`block.item`)."#;

fn unknown<'a>(
    code: Code,
    what: &str,
    name: &str,
    span: Span,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Diagnostic {
    let candidates: Vec<&str> = candidates.into_iter().collect();
    let help = match closest(name, candidates.iter().copied()) {
        Some(c) => format!("did you mean `{c}`?"),
        None if candidates.is_empty() => format!("no {what} is declared here"),
        None => {
            let mut sorted = candidates.clone();
            sorted.sort_unstable();
            sorted.dedup();
            let shown: Vec<String> = sorted.iter().take(8).map(|c| format!("`{c}`")).collect();
            let more = if sorted.len() > 8 { ", ..." } else { "" };
            format!("known {what}s: {}{more}", shown.join(", "))
        }
    };
    Diagnostic::new(
        code,
        format!("unknown {what} `{name}`"),
        span,
        format!("no {what} of this name"),
    )
    .with_help(help)
}

/// A type name that resolves to nothing.
pub fn unknown_type<'a>(
    name: &str,
    span: Span,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Diagnostic {
    unknown(Code::UnknownType, "type", name, span, candidates)
}

/// A data reference that resolves to nothing; `what` says which part
/// (`data`, `field of DEMO_STATE_STR`, ...).
pub fn unknown_data<'a>(
    what: &str,
    name: &str,
    span: Span,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Diagnostic {
    unknown(Code::UnknownData, what, name, span, candidates)
}

/// A thread name that resolves to nothing.
pub fn unknown_thread<'a>(
    name: &str,
    span: Span,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Diagnostic {
    unknown(Code::UnknownThread, "thread", name, span, candidates)
}

/// A service name that resolves to nothing.
pub fn unknown_service<'a>(
    name: &str,
    span: Span,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Diagnostic {
    unknown(Code::UnknownService, "service", name, span, candidates)
}

/// A codel name that resolves to nothing in its service.
pub fn unknown_codel<'a>(
    name: &str,
    span: Span,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Diagnostic {
    unknown(Code::UnknownCodel, "codel", name, span, candidates)
}

/// A report name that resolves to nothing in its service.
pub fn unknown_report<'a>(
    name: &str,
    span: Span,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Diagnostic {
    unknown(Code::UnknownReport, "report", name, span, candidates)
}

/// A credential class that is not in the component's order.
pub fn unknown_credential<'a>(
    name: &str,
    span: Span,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Diagnostic {
    unknown(
        Code::UnknownCredential,
        "credential",
        name,
        span,
        candidates,
    )
}

/// A field step on data that has no such field.
pub fn unknown_field<'a>(
    field: &str,
    ty: &str,
    span: Span,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Diagnostic {
    let candidates: Vec<&str> = candidates.into_iter().collect();
    let help = match closest(field, candidates.iter().copied()) {
        Some(c) => format!("did you mean `{c}`?"),
        None if candidates.is_empty() => format!("`{ty}` has no fields"),
        None => format!(
            "`{ty}` has {}",
            candidates
                .iter()
                .map(|c| format!("`{c}`"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    Diagnostic::new(
        Code::UnknownData,
        format!("`{ty}` has no field `{field}`"),
        span,
        "no such field",
    )
    .with_help(help)
}

/// An index step on data that is not an array or sequence, or out of bounds.
pub fn bad_index(index: u64, ty: &str, span: Span, why: &str) -> Diagnostic {
    Diagnostic::new(
        Code::UnknownData,
        format!("cannot index `{ty}` with [{index}]: {why}"),
        span,
        "bad index",
    )
}
