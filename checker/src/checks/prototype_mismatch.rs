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
