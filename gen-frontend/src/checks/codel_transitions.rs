//! `bad-next`, `bad-on-inter` and `ambiguous-name`: the transition rules of
//! codels (LANGUAGE.md 2.7). `next` names codels of the same service, its
//! reports or `end`; `on-inter` names an inter codel and is not allowed on
//! control and inter codels; a name may not be both a codel and a report.

use genom_model::{Code, Diagnostic, Span};

/// `genom-check explain bad-next`.
pub const EXPLANATION_BAD_NEXT: &str = r#"A `next` outcome that is not allowed: the control codel (it only accepts or
rejects a request, so it has no `next` and is never a target), a codel of
another service, or the same outcome twice.

Why it matters: `next` is the state machine of the service; an outcome the
engine cannot follow would leave the service stuck.

Example:

```
service move {
  control codel { exec: check(); next: goto; }   // bad-next: control codels have no next
  exec codel goto { exec: go(); next: control; } // bad-next: the control codel is not a state
}
```

`next: ;` (or no `next`) means `next: end;`."#;

/// `genom-check explain bad-on-inter`.
pub const EXPLANATION_BAD_ON_INTER: &str = r#"An `on-inter` that is not allowed: on a control codel (it runs before the
service exists), on an inter codel (a stopping service is not interrupted
again), or naming a codel that is not an inter codel.

Why it matters: `on-inter` says how to clean up when the service is
interrupted at that codel; it must lead to cleanup code.

Example:

```
inter codel stop { exec: halt(); on-inter: stop; }   // bad-on-inter
exec codel goto { exec: go(); on-inter: goto; }      // bad-on-inter: `goto` is not an inter codel
```"#;

/// `genom-check explain ambiguous-name`.
pub const EXPLANATION_AMBIGUOUS_NAME: &str = r#"A name that is both a codel and a report of the same service, or a codel
named `end`.

Why it matters: in `next: X;` the engine could not tell whether to go to
codel `X` or to end the service with report `X`; `end` always means
successful termination.

Example:

```
service move {
  report: stop;
  inter codel stop { exec: halt(); }   // ambiguous-name: `stop` is also a report
}
```"#;

/// `next` on a control codel.
pub fn next_on_control(span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::BadNext,
        "a control codel has no `next`",
        span,
        "not allowed on a control codel",
    )
    .with_help(
        "the control codel only accepts the request or rejects it with a report; remove `next`",
    )
}

/// A `next` entry naming the control codel.
pub fn next_to_control(span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::BadNext,
        "`next` cannot go to the control codel",
        span,
        "the control codel is not a state",
    )
    .with_help("`next` names start, exec or inter codels of the service, its reports, or `end`")
}

/// A `next` entry naming a codel of another service.
pub fn next_to_other_service(name: &str, span: Span, owner: &str, owner_span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::BadNext,
        format!("`{name}` is a codel of service `{owner}`, not of this service"),
        span,
        "codel of another service",
    )
    .with_label(owner_span, format!("`{name}` is defined in `{owner}`"))
    .with_help("a service's codels can only go to codels of the same service")
}

/// The same outcome listed twice.
pub fn next_twice(name: &str, second: Span, first: Span) -> Diagnostic {
    Diagnostic::new(
        Code::BadNext,
        format!("`{name}` is listed twice in `next`"),
        second,
        "listed again",
    )
    .with_label(first, "first listed here")
}

/// `on-inter` on a control or inter codel.
pub fn on_inter_not_allowed(kind: &str, span: Span) -> Diagnostic {
    let why = if kind == "inter" {
        "a stopping service is not interrupted again"
    } else {
        "the control codel runs before the service instance exists"
    };
    Diagnostic::new(
        Code::BadOnInter,
        format!("`on-inter` is not allowed on {kind} codels"),
        span,
        "not allowed here",
    )
    .with_help(format!("remove it: {why}"))
}

/// `on-inter` naming a codel that is not an inter codel.
pub fn on_inter_not_inter(name: &str, kind: &str, span: Span, target: Span) -> Diagnostic {
    Diagnostic::new(
        Code::BadOnInter,
        format!(
            "`on-inter` must name an inter codel, and `{name}` is {} {kind} codel",
            article(kind)
        ),
        span,
        "not an inter codel",
    )
    .with_label(target, format!("`{name}` is declared here"))
    .with_help("declare the cleanup as `inter codel NAME { ... }`")
}

/// A name that is both a codel and a report.
pub fn codel_and_report(name: &str, codel: Span, report: Span) -> Diagnostic {
    Diagnostic::new(
        Code::AmbiguousName,
        format!("`{name}` is both a codel and a report of this service"),
        codel,
        "a codel",
    )
    .with_label(report, "a report")
    .with_help("rename the codel or the report so that `next` is unambiguous")
}

/// A codel named `end`.
pub fn codel_named_end(span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::AmbiguousName,
        "a codel cannot be named `end`",
        span,
        "`end` means successful termination",
    )
    .with_help("rename the codel")
}

/// A report named `end`.
pub fn report_named_end(span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::AmbiguousName,
        "a report cannot be named `end`",
        span,
        "`end` means successful termination",
    )
    .with_help("rename the report: `next: end` always ends the service successfully")
}

fn article(word: &str) -> &'static str {
    if word.starts_with(['a', 'e', 'i', 'o', 'u']) {
        "an"
    } else {
        "a"
    }
}
