//! Small named constructors for every diagnostic the GenoM3 front end
//! produces (preprocessor, syntax, lowering, static checks, WCET file).

use genom_model::{Code, Diagnostic, Span};

/// A directive that is not interpreted.
pub(crate) fn ignored_directive(span: Span, word: &str) -> Diagnostic {
    Diagnostic::new(
        Code::IgnoredDirective,
        format!("`#{word}` is ignored"),
        span,
        "this directive has no effect here",
    )
}

/// `#else`/`#elif`/`#endif` without `#if`.
pub(crate) fn unbalanced_directive(span: Span, word: &str) -> Diagnostic {
    Diagnostic::new(
        Code::Syntax,
        format!("`#{word}` without a matching `#if`"),
        span,
        "no open conditional",
    )
}

/// `#if` without `#endif`.
pub(crate) fn unterminated_conditional(span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::Syntax,
        "conditional directive is never closed",
        span,
        "expected `#endif` before the end of the file",
    )
}

/// `#include` with no `"…"` or `<…>`.
pub(crate) fn bad_include(span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::Syntax,
        "malformed `#include`",
        span,
        "expected `\"file\"` or `<file>`",
    )
}

/// An include that is not found anywhere.
pub(crate) fn include_not_found(span: Span, path: &str, searched: &[String]) -> Diagnostic {
    let list = if searched.is_empty() {
        "no folder".to_owned()
    } else {
        searched.join(", ")
    };
    Diagnostic::new(
        Code::IncludeNotFound,
        format!("cannot find included file `{path}`"),
        span,
        format!("searched in: {list}"),
    )
    .with_help("add the folder holding it with `-I DIR` (or to GENOM_INCLUDE_PATH)")
}

/// A file that includes itself, directly or not.
pub(crate) fn include_cycle(span: Span, path: &str) -> Diagnostic {
    Diagnostic::new(
        Code::IncludeCycle,
        format!("`{path}` includes itself"),
        span,
        "this include closes a cycle",
    )
    .with_help("add an include guard (`#ifndef X` / `#define X` / `#endif`) or remove the include")
}

/// A file that exists but cannot be read.
pub(crate) fn include_unreadable(span: Span, path: &str, why: &str) -> Diagnostic {
    Diagnostic::new(
        Code::IncludeNotFound,
        format!("cannot read included file `{path}`: {why}"),
        span,
        "included here",
    )
}

/// A syntax error.
pub(crate) fn syntax(span: Span, message: String, label: String) -> Diagnostic {
    Diagnostic::new(Code::Syntax, message, span, label)
}

/// No component in a file that is not interface-only.
pub(crate) fn missing_component(span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::MissingComponent,
        "no `component` in this file",
        span,
        "a GenoM3 description needs one `component NAME { ... };`",
    )
}

/// Something named twice.
pub(crate) fn duplicate(what: &str, name: &str, span: Span, first: Span) -> Diagnostic {
    Diagnostic::new(
        Code::DuplicateDefinition,
        format!("{what} `{name}` is defined twice"),
        span,
        "second definition",
    )
    .with_label(first, "first defined here")
}

/// An unknown name, with a suggestion.
pub(crate) fn unknown(
    code: Code,
    what: &str,
    name: &str,
    span: Span,
    hint: Option<&str>,
) -> Diagnostic {
    Diagnostic::new(
        code,
        format!("unknown {what} `{name}`"),
        span,
        format!("no {what} of this name"),
    )
    .with_optional_help(hint.map(|h| format!("did you mean `{h}`?")))
}

/// A property where it has no meaning.
pub(crate) fn misplaced_property(span: Span, what: &str, owner: &str) -> Diagnostic {
    Diagnostic::new(
        Code::InvalidAttribute,
        format!("`{what}` is not a property of {owner}"),
        span,
        "not allowed here",
    )
}

/// A constant expression that cannot be evaluated.
pub(crate) fn bad_constant(span: Span, why: &str) -> Diagnostic {
    Diagnostic::new(
        Code::TypeMismatch,
        format!("cannot evaluate this constant expression: {why}"),
        span,
        "here",
    )
}

/// An activity or task with codels but no `codel<start>`.
pub(crate) fn missing_start(what: &str, name: &str, span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::MissingStart,
        format!("{what} `{name}` has no `codel<start>`"),
        span,
        "its state machine has no entry",
    )
    .with_help("add `codel<start> f(...) yield ...;`")
}

/// A yield or state that names no state.
pub(crate) fn unknown_state(name: &str, span: Span, owner: &str, hint: Option<&str>) -> Diagnostic {
    Diagnostic::new(
        Code::UnknownState,
        format!("`{name}` is not a state of `{owner}`"),
        span,
        "no codel runs in this state",
    )
    .with_optional_help(
        hint.map(|h| format!("did you mean `{h}`?"))
            .or_else(|| Some("yield `ether` to end, or add a codel for this state".to_owned())),
    )
}

/// A state no yield reaches.
pub(crate) fn unreachable_state(name: &str, span: Span, owner: &str) -> Diagnostic {
    Diagnostic::new(
        Code::UnreachableState,
        format!("state `{name}` of `{owner}` is never reached"),
        span,
        "no yield leads here from `start` or `stop`",
    )
}

/// A stop codel that cannot reach ether.
pub(crate) fn stop_no_ether(owner: &str, span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::StopNoEther,
        format!("`codel<stop>` of `{owner}` never reaches `ether`"),
        span,
        "no path of yields from here ends in `ether`",
    )
    .with_help("make some codel reachable from `stop` yield `ether`")
}

/// An async codel sharing ids data with another task.
pub(crate) fn async_shared(
    codel: &str,
    member: &str,
    span: Span,
    other: &str,
    other_span: Span,
) -> Diagnostic {
    Diagnostic::new(
        Code::AsyncSharedData,
        format!("async codel `{codel}` shares ids member `{member}` with another task"),
        span,
        "async codel",
    )
    .with_label(other_span, format!("also used by `{other}`"))
    .with_help("an async codel runs outside its task's lock: pass a copy through a port or a local")
}

/// A WCET file problem.
pub(crate) fn bad_wcet(span: Span, message: String, hint: Option<&str>) -> Diagnostic {
    Diagnostic::new(Code::BadWcet, message, span, "in the WCET file")
        .with_optional_help(hint.map(|h| format!("did you mean `{h}`?")))
}

/// A port whose type is not a named type.
pub(crate) fn anonymous_port_type(name: &str, span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::InvalidAttribute,
        format!("port `{name}` has an anonymous type"),
        span,
        "a port's type must be a named type",
    )
    .with_help("declare it first, e.g. `typedef double speed_t;`, and use the name")
}

/// A task period or delay that is not a multiple of the clock rate.
pub(crate) fn off_clock(what: &str, task: &str, span: Span, clock: Span) -> Diagnostic {
    Diagnostic::new(
        Code::InvalidAttribute,
        format!("the {what} of task `{task}` is not a multiple of the `clock-rate`"),
        span,
        "not a whole number of clock ticks",
    )
    .with_label(clock, "clock-rate set here")
}

/// A scalar default for a struct or array parameter.
pub(crate) fn scalar_for_compound(name: &str, span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::TypeMismatch,
        format!("parameter `{name}` is a struct or array: a scalar cannot initialize it"),
        span,
        "a scalar value",
    )
    .with_help("use a braced initializer such as `{ .x = 1 }` or `{ 1, 2 }`")
}

/// An unqualified codel parameter that names several things.
pub(crate) fn missing_source(name: &str, span: Span, matches: &[&str]) -> Diagnostic {
    Diagnostic::new(
        Code::MissingSource,
        format!("codel parameter `{name}` needs a source qualifier"),
        span,
        format!("`{name}` is {}", matches.join(" and ")),
    )
    .with_help("write `ids`, `local`, `port` or `remote` before the direction")
}

/// One codel function with two prototypes.
pub(crate) fn prototype_mismatch(
    name: &str,
    here: (Span, usize),
    first: (Span, usize),
) -> Diagnostic {
    Diagnostic::new(
        Code::PrototypeMismatch,
        format!("codel `{name}` is used with two different prototypes"),
        here.0,
        format!("{} parameter(s) here", here.1),
    )
    .with_label(first.0, format!("{} parameter(s) and other directions here", first.1))
    .with_help("a codel function has one C prototype: give the two uses the same parameters, or rename one")
}

/// A macro that is not expanded.
pub(crate) fn macro_not_expanded(span: Span, name: &str, why: &str) -> Diagnostic {
    Diagnostic::new(
        Code::IgnoredDirective,
        format!("macro `{name}` is not expanded: {why}"),
        span,
        "here",
    )
}
