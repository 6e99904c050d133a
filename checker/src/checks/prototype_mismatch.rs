//! `prototype-mismatch`: one codel function used with different prototypes
//! across the component (different arity, argument types or `const`-ness).

use genom_model::{Code, Diagnostic, Span};

/// `genom-check explain prototype-mismatch`.
pub const EXPLANATION: &str = r#"The same codel function name is used by several codels with different
prototypes: a different number of arguments, different argument types, or
an argument `const` in one use and not in another. Every use is labelled.

Why it matters: a codel is one C function; the engine calls it with the
arguments of each `exec:`. Two different prototypes cannot both match the
function in the codels library.

Example:

```
exec codel a { exec: step(demoIds.distRef); }            // step(double *)
exec codel b { exec: step(demoExport.state); }           // prototype-mismatch: step(DEMO_STATE_STR *)
```

Types are compared after resolving typedefs."#;

/// `function` is used with prototype `second` at `second_span` and with
/// `first` at `first_span`; `others` are further uses.
pub fn prototype_mismatch(
    function: &str,
    second: &str,
    second_span: Span,
    first: &str,
    first_span: Span,
    others: &[Span],
) -> Diagnostic {
    let mut d = Diagnostic::new(
        Code::PrototypeMismatch,
        format!("codel function `{function}` is used with different prototypes"),
        second_span,
        format!("`{function}({second})` here"),
    )
    .with_label(first_span, format!("`{function}({first})` here"));
    for &span in others {
        d = d.with_label(span, "also used here");
    }
    d.with_help("a codel function has one C prototype: use the same argument types and `const` everywhere, or rename one")
}

use genom_model::component::types::TypeTable as _;
use genom_model::component::{Call, Component, Ty};

use super::registry::{Applies, StaticCheck};

/// One argument of a prototype: const-ness and type (`None` when the
/// argument did not resolve, which matches anything).
type Signature = Vec<(bool, Option<Ty>)>;

fn signature(call: &Call) -> Signature {
    call.args
        .iter()
        .map(|a| (a.is_const, a.data.as_ref().map(|d| d.ty.clone())))
        .collect()
}

fn same(c: &Component, a: &Signature, b: &Signature) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|((ca, ta), (cb, tb))| {
            ca == cb
                && match (ta, tb) {
                    (Some(x), Some(y)) => c.types.same(x, y),
                    _ => true,
                }
        })
}

fn show(c: &Component, s: &Signature) -> String {
    let args: Vec<String> = s
        .iter()
        .map(|(is_const, ty)| {
            let t = ty
                .as_ref()
                .map_or_else(|| "?".to_owned(), |t| c.types.display(t));
            if *is_const { format!("const {t}") } else { t }
        })
        .collect();
    args.join(", ")
}

/// The registry's entry ([`super::STATIC_CHECKS`]).
pub const CHECK: StaticCheck = StaticCheck {
    name: "codel prototypes",
    applies: Applies::Always,
    run: check,
    codes: &[(Code::PrototypeMismatch, EXPLANATION)],
};

/// Reports each codel function used with more than one prototype, once,
/// labelling every use.
pub fn check(c: &Component) -> Vec<Diagnostic> {
    let mut by_function: std::collections::BTreeMap<&str, Vec<(&Call, Signature)>> =
        std::collections::BTreeMap::new();
    for codel in c.codels.values() {
        if let Some(call) = &codel.call {
            by_function
                .entry(call.function.name.as_str())
                .or_default()
                .push((call, signature(call)));
        }
    }
    let mut out = Vec::new();
    for (function, uses) in by_function {
        let Some((first, first_sig)) = uses.first() else {
            continue;
        };
        let Some((second, second_sig)) = uses.iter().find(|(_, s)| !same(c, first_sig, s)) else {
            continue;
        };
        let others: Vec<Span> = uses
            .iter()
            .map(|(call, _)| call.function.span)
            .filter(|&s| s != first.function.span && s != second.function.span)
            .collect();
        out.push(prototype_mismatch(
            function,
            &show(c, second_sig),
            second.function.span,
            &show(c, first_sig),
            first.function.span,
            &others,
        ));
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

    /// Data on lines 3-5, then a service whose start codel (line 8) and exec
    /// codel `b` (line 9) call `first` and `second`.
    fn two_uses(first: &str, second: &str) -> String {
        format!(
            "{HEADER}typedef double meters;\nids d {{ double x; meters m; long n; }}\nexport e {{ double pos; }}\n\
             service s {{\n  thread: main;\n  start codel {{ exec: {first}; next: b; }}\n  exec codel b {{ exec: {second}; }}\n}}\n"
        )
    }

    fn labels(src: &str) -> Vec<String> {
        let r = testing::check(src);
        r.diagnostics
            .iter()
            .filter(|d| d.code == Code::PrototypeMismatch)
            .flat_map(|d| d.labels.iter().map(|l| l.message.clone()))
            .collect()
    }

    fn same_prototype(first: &str, second: &str) {
        let src = two_uses(first, second);
        assert_eq!(
            testing::count(&src, Code::PrototypeMismatch),
            0,
            "{}",
            testing::render(&src)
        );
    }

    #[test]
    fn a_different_arity() {
        let src = two_uses("step(d.x)", "step(d.x, d.n)");
        assert_eq!(
            found(&src, Code::PrototypeMismatch),
            ["9:24 `step` + 8:23 `step`: codel function `step` is used with different prototypes"]
        );
        assert_eq!(
            labels(&src),
            ["`step(double, long)` here", "`step(double)` here"]
        );
        same_prototype("step(d.x, d.n)", "step(d.x, d.n)");
    }

    #[test]
    fn a_different_argument_type() {
        let src = two_uses("step(d.x)", "step(d.n)");
        assert_eq!(labels(&src), ["`step(long)` here", "`step(double)` here"]);
        same_prototype("step(d.x)", "step(e.pos)");
    }

    #[test]
    fn a_different_constness() {
        let src = two_uses("step(const d.x)", "step(d.x)");
        assert_eq!(
            labels(&src),
            ["`step(double)` here", "`step(const double)` here"]
        );
        same_prototype("step(const d.x)", "step(const e.pos)");
    }

    #[test]
    fn aliases_of_one_type_are_the_same_prototype() {
        same_prototype("step(d.x)", "step(d.m)");
    }

    #[test]
    fn parameters_count_with_their_types() {
        let src = format!(
            "{HEADER}ids d {{ double x; }}\nservice s {{\n  thread: main;\n  input: double speed, long count;\n  \
             start codel {{ exec: step(speed); next: b; }}\n  exec codel b {{ exec: step(d.x); next: c; }}\n  exec codel c {{ exec: step(count); }}\n}}\n"
        );
        assert_eq!(
            found(&src, Code::PrototypeMismatch),
            [
                "9:24 `step` + 7:23 `step` + 8:24 `step`: codel function `step` is used with different prototypes"
            ]
        );
    }

    #[test]
    fn three_uses_label_all_three_and_report_once() {
        let src = format!(
            "{HEADER}ids d {{ double x; long n; }}\n\
             service s {{\n  thread: main;\n  start codel {{ exec: step(d.x); next: b; }}\n  exec codel b {{ exec: step(d.n); next: c; }}\n  exec codel c {{ exec: step(d.x, d.n); }}\n}}\n\
             service u {{\n  control codel {{ exec: step(); }}\n}}\n"
        );
        assert_eq!(
            found(&src, Code::PrototypeMismatch),
            [
                "7:24 `step` + 6:23 `step` + 8:24 `step` + 11:25 `step`: codel function `step` is used with different prototypes"
            ]
        );
        assert_eq!(
            labels(&src),
            [
                "`step(long)` here",
                "`step(double)` here",
                "also used here",
                "also used here"
            ]
        );
    }

    #[test]
    fn different_functions_are_independent() {
        same_prototype("start(d.x)", "step(d.n)");
    }

    #[test]
    fn an_unresolved_argument_matches_anything() {
        let src = two_uses("step(d.y)", "step(d.x)");
        assert_eq!(testing::count(&src, Code::PrototypeMismatch), 0);
        assert_eq!(testing::count(&src, Code::UnknownData), 1);
    }

    #[test]
    fn snapshot() {
        let src = format!(
            "{HEADER}ids d {{ double x; long n; }}\n\
             service s {{\n  thread: main;\n  start codel {{ exec: step(d.x); next: b; }}\n  exec codel b {{ exec: step(const d.x); next: c; }}\n  exec codel c {{ exec: step(d.n); }}\n}}\n"
        );
        insta::assert_snapshot!(testing::render(&src));
    }
}
