//! `missing-start`, `missing-thread`, `multiple-init` and
//! `duplicate-codel-kind`: the structure rules of services (LANGUAGE.md
//! 2.6–2.7). A service runs on a thread exactly when it has a start codel;
//! at most one `init` service; at most one start and one control codel per
//! service.

use genom_model::{Code, Diagnostic, Span};

/// `genom-check explain missing-start`.
pub const EXPLANATION_MISSING_START: &str = r#"A service that runs on a thread has no start codel: it names a `thread:` or
has exec or inter codels, but no `start codel`.

Why it matters: the thread starts a service at its start codel; without one
the exec codels can never run.

Example:

```
service move {
  thread: motionTask;
  exec codel goto { exec: go(); }    // missing-start: which codel runs first?
}
```

A service that runs entirely in the control thread (an attribute setter)
has only a control codel and no `thread:`."#;

/// `genom-check explain missing-thread`.
pub const EXPLANATION_MISSING_THREAD: &str = r#"A service with a start codel does not say which thread runs it.

Why it matters: start, exec and inter codels run in an execution thread;
the engine cannot schedule the service without one.

Example:

```
thread motionTask { period: 10ms; }
service move {
  start codel { exec: go(); }        // missing-thread: add `thread: motionTask;`
}
```"#;

/// `genom-check explain multiple-init`.
pub const EXPLANATION_MULTIPLE_INIT: &str = r#"More than one service is declared `init`.

Why it matters: the `init` service must complete before any other request is
accepted; with two, each would block the other forever.

Example:

```
init service setup { ... }
init service calibrate { ... }    // multiple-init: at most one init service
```

Make one of them a plain service and have clients request it after
initialisation."#;

/// `genom-check explain duplicate-codel-kind`.
pub const EXPLANATION_DUPLICATE_CODEL_KIND: &str = r#"A service has two start codels or two control codels.

Why it matters: a service starts at exactly one codel and validates its
request with at most one control codel.

Example:

```
service move {
  thread: motionTask;
  start codel { exec: a(); }
  start codel { exec: b(); }    // duplicate-codel-kind
}
```"#;

/// A service with a thread or exec/inter codels but no start codel.
pub fn missing_start(service: &str, span: Span, why: Span, why_label: &str) -> Diagnostic {
    Diagnostic::new(
        Code::MissingStart,
        format!("service `{service}` has no start codel"),
        span,
        "service without start codel",
    )
    .with_label(why, why_label.to_owned())
    .with_help(
        "add `start codel { exec: ...; next: ...; }`, or remove the thread and execution codels",
    )
}

/// A service with a start codel but no thread.
pub fn missing_thread(service: &str, span: Span, start: Span, threads: &[&str]) -> Diagnostic {
    let help = match threads.first() {
        Some(t) => format!("name the thread that runs it, e.g. `thread: {t};`"),
        None => "declare a thread (`thread t { period: 10ms; }`) and name it with `thread: t;`"
            .to_owned(),
    };
    Diagnostic::new(
        Code::MissingThread,
        format!("service `{service}` has a start codel but no thread"),
        span,
        "no `thread:`",
    )
    .with_label(start, "its start codel")
    .with_help(help)
}

/// A second `init` service.
pub fn multiple_init(second: &str, second_span: Span, first: &str, first_span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::MultipleInit,
        format!("`{second}` is another init service (the first is `{first}`)"),
        second_span,
        "another init service",
    )
    .with_label(first_span, "first init service")
    .with_help("a component has at most one init service")
}

/// A second start or control codel in a service.
pub fn duplicate_codel_kind(kind: &str, service: &str, second: Span, first: Span) -> Diagnostic {
    Diagnostic::new(
        Code::DuplicateCodelKind,
        format!("service `{service}` has two {kind} codels"),
        second,
        format!("second {kind} codel"),
    )
    .with_label(first, format!("first {kind} codel"))
    .with_help(format!("a service has at most one {kind} codel"))
}
