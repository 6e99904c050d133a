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
            format!("known {}: {}{more}", plural(what), shown.join(", "))
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

fn plural(what: &str) -> String {
    if what.ends_with("data") {
        what.to_owned()
    } else {
        format!("{what}s")
    }
}

/// A type name that resolves to nothing. When a type of that name exists in
/// another module (`Pose` for `geo::Pose`), the help names it.
pub fn unknown_type<'a>(
    name: &str,
    span: Span,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Diagnostic {
    let candidates: Vec<&str> = candidates.into_iter().collect();
    let d = unknown(
        Code::UnknownType,
        "type",
        name,
        span,
        candidates.iter().copied(),
    );
    let written = name.trim_start_matches("::");
    let last = written.rsplit("::").next().unwrap_or(written);
    match candidates
        .iter()
        .find(|c| **c != written && c.rsplit("::").next() == Some(last))
    {
        Some(c) => d.with_help(format!("did you mean `{c}`?")),
        None => d,
    }
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

/// An export or import block named where one of its items is expected.
pub fn block_without_item<'a>(
    block: &str,
    kind: &str,
    span: Span,
    items: impl IntoIterator<Item = &'a str>,
) -> Diagnostic {
    let items: Vec<String> = items
        .into_iter()
        .map(|i| format!("`{block}.{i}`"))
        .collect();
    let help = if items.is_empty() {
        format!("`{block}` has no items")
    } else {
        format!("name one of its items: {}", items.join(", "))
    };
    Diagnostic::new(
        Code::UnknownData,
        format!("`{block}` is an {kind} block, not a data item"),
        span,
        format!("an {kind} block"),
    )
    .with_help(help)
}

/// A service parameter that refers to data outside every `ids` block.
pub fn not_ids_member(text: &str, span: Span, ids_blocks: &[&str]) -> Diagnostic {
    let help = if ids_blocks.is_empty() {
        "declare it as `TYPE name`: no `ids` block is declared".to_owned()
    } else {
        let list: Vec<String> = ids_blocks.iter().map(|b| format!("`{b}`")).collect();
        format!(
            "declare it as `TYPE name`, or refer into an `ids` block ({})",
            list.join(", ")
        )
    };
    Diagnostic::new(
        Code::UnknownData,
        format!("`{text}` is not an ids member"),
        span,
        "parameters refer into an `ids` block",
    )
    .with_help(help)
}

/// A codel argument naming a parameter of another service.
pub fn other_service_param(name: &str, span: Span, owner: &str, declared: Span) -> Diagnostic {
    Diagnostic::new(
        Code::UnknownData,
        format!("`{name}` is a parameter of service `{owner}`, not of this service"),
        span,
        "parameter of another service",
    )
    .with_label(declared, format!("`{name}` is declared in `{owner}`"))
    .with_help(
        "a codel sees only the parameters of its own service; share data through an `ids` member",
    )
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

/// An `on-inter` naming no codel of its service.
pub fn unknown_inter_codel<'a>(
    name: &str,
    span: Span,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Diagnostic {
    unknown(Code::UnknownCodel, "inter codel", name, span, candidates)
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
