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

use super::registry::{Applies, StaticCheck};

fn same_data(a: &DataPath, b: &DataPath) -> bool {
    a.root == b.root && a.steps == b.steps
}

/// The registry's entry ([`super::STATIC_CHECKS`]).
pub const CHECK: StaticCheck = StaticCheck {
    name: "update rules",
    applies: Applies::Always,
    run: check,
    codes: &[
        (Code::UpdateNotArgument, EXPLANATION_NOT_ARGUMENT),
        (Code::ConstUpdate, EXPLANATION_CONST),
    ],
};

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

#[cfg(test)]
mod tests {
    use genom_model::{Code, Span};

    use crate::CheckResult;
    use crate::testing::{self, HEADER};

    /// Every diagnostic of `code` in `src`, as
    /// ``line:col `primary text` + line:col `label text`...: message``.
    fn found(src: &str, code: Code) -> Vec<String> {
        let r = testing::check(src);
        r.diagnostics
            .iter()
            .filter(|d| d.code == code)
            .map(|d| {
                let spans: Vec<String> = d.labels.iter().map(|l| at(&r, l.span)).collect();
                format!("{}: {}", spans.join(" + "), d.message)
            })
            .collect()
    }

    fn at(r: &CheckResult, span: Span) -> String {
        let (line, col) = r
            .sources
            .locate(span)
            .and_then(|l| Some(r.sources.file(l.file)?.line_col(l.offset)))
            .unwrap_or_default();
        format!("{line}:{col} `{}`", r.sources.slice(span))
    }

    /// Data on lines 3-5; the start codel's `exec` and `update` on lines 10-11.
    fn codel(exec: &str, update: &str) -> String {
        format!(
            "{HEADER}typedef struct state_t {{ double x; double v; }} state_t;\nids d {{ double x; state_t s; }}\nexport e {{ state_t state; }}\n\
             service move {{\n  thread: main;\n  input: double speed;\n  start codel {{\n    exec: {exec};\n    update: {update};\n  }}\n}}\n"
        )
    }

    fn clean(exec: &str, update: &str) {
        let src = codel(exec, update);
        assert!(testing::codes(&src).is_empty(), "{}", testing::render(&src));
    }

    #[test]
    fn an_update_that_is_not_an_argument() {
        let src = codel("go(d.x)", "d.x, e.state");
        assert_eq!(
            found(&src, Code::UpdateNotArgument),
            [
                "11:18 `e.state` + 10:11 `go(d.x)`: `e.state` is updated but is not an argument of `exec`"
            ]
        );
        clean("go(d.x, e.state)", "d.x, e.state");
    }

    #[test]
    fn a_path_is_not_its_parent_nor_its_member() {
        let src = codel("go(d.s.x, e.state)", "d.s, e.state.x");
        assert_eq!(
            found(&src, Code::UpdateNotArgument),
            [
                "11:13 `d.s` + 10:11 `go(d.s.x, e.state)`: `d.s` is updated but is not an argument of `exec`",
                "11:18 `e.state.x` + 10:11 `go(d.s.x, e.state)`: `e.state.x` is updated but is not an argument of `exec`",
            ]
        );
        clean("go(d.s.x, e.state)", "d.s.x, e.state");
    }

    #[test]
    fn a_parameter_can_be_updated() {
        clean("go(speed)", "speed");
        let src = codel("go(d.x)", "speed");
        assert_eq!(testing::count(&src, Code::UpdateNotArgument), 1);
    }

    #[test]
    fn an_unknown_update_entry_is_only_unknown_data() {
        let src = codel("go(d.x)", "d.y");
        assert_eq!(testing::codes(&src), [Code::UnknownData]);
    }

    #[test]
    fn a_const_argument_cannot_be_updated() {
        let src = codel("go(d.x, const e.state)", "d.x, e.state");
        assert_eq!(
            found(&src, Code::ConstUpdate),
            ["11:18 `e.state` + 10:19 `const e.state`: `e.state` is updated but passed `const`"]
        );
        assert_eq!(testing::count(&src, Code::UpdateNotArgument), 0);
        clean("go(d.x, const e.state)", "d.x");
    }

    #[test]
    fn snapshot() {
        insta::assert_snapshot!(testing::render(&codel(
            "go(const d.x, e.state)",
            "d.x, e.state, d.s"
        )));
    }
}
