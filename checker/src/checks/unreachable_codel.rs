//! `unreachable-codel`, static part: a start, exec or inter codel that no
//! path from its service's start codel reaches, following the codel outcomes
//! of `next` and the `on-inter` cleanup edges (LANGUAGE.md 2.7 and 4).
//!
//! Such a codel is dead code in the service's state machine: usually a
//! forgotten `next` entry or `on-inter`, or a misspelt target that happens
//! to name another codel. Control codels are never unreachable (they run on
//! every request), and services without a start codel are left to
//! `missing-start`.
//!
//! This file also holds the codel transition graph that the other
//! reachability checks (`no-termination`, `auto-terminates`) share.

use std::collections::BTreeSet;
use std::hash::{BuildHasherDefault, DefaultHasher};

use genom_model::component::{CodelId, Component, Outcome, Service};
use genom_model::kinds::CodelKind;
use genom_model::{Code, Diagnostic, Span};
use petgraph::graphmap::DiGraphMap;
use petgraph::visit::Dfs;

use super::registry::{Applies, StaticCheck};

/// `genom-check explain unreachable-codel`.
pub const EXPLANATION: &str = r#"A start, exec or inter codel that no execution of its service reaches: no
chain of `next` outcomes and `on-inter` cleanups leads to it from the
service's start codel.

Why it matters: the codel is dead code in the service's state machine. It
is almost always a mistake: a `next` entry or an `on-inter` was forgotten,
or the codel that named it was itself removed. Code that never runs is
never tested either.

Example:

```
service move {
  thread: motionTask;
  start codel { exec: init(); next: goto; }
  exec codel goto { exec: go(); next: goto, end; }
  exec codel slowDown { exec: brake(); next: end; }   // unreachable-codel
  inter codel stop { exec: halt(); }                  // unreachable-codel: no `on-inter: stop`
}
```

Control codels run on every request and are never unreachable. This static
check only follows the codel graph; the model checker also reports codels
that no execution of the whole component reaches."#;

/// The transition graph of one service's codels, with deterministic
/// (insertion-ordered) iteration.
pub(crate) type CodelGraph = DiGraphMap<CodelId, (), BuildHasherDefault<DefaultHasher>>;

/// The graph of a service's start, exec and inter codels: an edge for every
/// codel outcome of `next` and, when `with_on_inter`, for every `on-inter`.
/// Nodes are added in codel order; control codels are left out.
pub(crate) fn codel_graph(c: &Component, service: &Service, with_on_inter: bool) -> CodelGraph {
    let mut graph = CodelGraph::new();
    for &id in &service.codels {
        let codel = &c.codels[id];
        if codel.kind == CodelKind::Control {
            continue;
        }
        graph.add_node(id);
        for next in &codel.next {
            if let Outcome::Codel(target) = next.outcome {
                graph.add_edge(id, target, ());
            }
        }
        if let Some(inter) = codel.on_inter.filter(|_| with_on_inter) {
            graph.add_edge(id, inter.id, ());
        }
    }
    graph
}

/// Every codel reachable from `from` (itself included).
pub(crate) fn reachable_from(graph: &CodelGraph, from: CodelId) -> BTreeSet<CodelId> {
    let mut dfs = Dfs::new(graph, from);
    let mut out = BTreeSet::new();
    while let Some(node) = dfs.next(graph) {
        out.insert(node);
    }
    out
}

/// A codel that no path from the start codel reaches.
pub fn unreachable(service: &str, codel: &str, kind: &str, span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::UnreachableCodel,
        format!("{kind} codel `{codel}` of service `{service}` is never reached"),
        span,
        "no path from the start codel leads here",
    )
    .with_help(format!(
        "nothing leads to `{codel}`: no `next` or `on-inter` of a codel reachable from the \
         start codel names it; {}, or remove it",
        if kind == "inter" {
            "name it in the `on-inter` of the codels it cleans up after"
        } else {
            "add it to the `next` of the codel that should run before it"
        }
    ))
}

/// The registry's entry ([`super::STATIC_CHECKS`]).
pub const CHECK: StaticCheck = StaticCheck {
    name: "codel reachability",
    applies: Applies::Always,
    run: check,
    codes: &[(Code::UnreachableCodel, EXPLANATION)],
};

/// Reports the start, exec and inter codels of every service with a start
/// codel that the service's codel graph does not reach from it.
pub fn check(c: &Component) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for service in c.services.values() {
        let Some(start) = service.start else { continue };
        let reached = reachable_from(&codel_graph(c, service, true), start);
        for &id in &service.codels {
            let codel = &c.codels[id];
            if codel.kind == CodelKind::Control || reached.contains(&id) {
                continue;
            }
            out.push(unreachable(
                &service.name.name,
                &codel.name.name,
                codel.kind.keyword(),
                codel.name.span,
            ));
        }
    }
    out
}

/// The codels of `service` that some path of the codel graph reaches from
/// its start codel (empty without a start codel).
pub fn statically_reachable(c: &Component, service: &Service) -> BTreeSet<CodelId> {
    let Some(start) = service.start else {
        return BTreeSet::new();
    };
    reachable_from(&codel_graph(c, service, true), start)
}

/// `unreachable-codel`, dynamic part: a codel that the codel graph reaches
/// but no execution of the whole component runs.
pub fn never_reached(service: &str, codel: &str, kind: &str, span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::UnreachableCodel,
        format!("{kind} codel `{codel}` of service `{service}` is never reached in any execution"),
        span,
        "no execution of the component runs this codel",
    )
    .with_help(
        "the codel graph leads here, but the component's rules never let it happen: \
         typically the only way in is an interrupt that no request or watchdog can cause at that point",
    )
}

/// `unreachable-codel` on a GenoM3 component: the codel of `state` (function
/// `function`) of `owner` (`activity `a`` or `task `t``), which its yields
/// lead to but no execution under GenoM3's semantics runs.
pub fn never_run_genom3(owner: &str, state: &str, function: &str, span: Span) -> Diagnostic {
    Diagnostic::new(
        Code::UnreachableCodel,
        format!("codel `{function}` of {owner} (state `{state}`) is never run in any execution"),
        span,
        "no execution of the component runs this codel",
    )
    .with_help(
        "its state machine leads here, but GenoM3's rules never let it happen: typically the \
         only way in is after a service that can never complete, or a stop path nothing reaches",
    )
}

/// Reports codels the codel graph reaches but exploration never ran; skips
/// dead services (`dead-service` covers them) and services whose
/// exploration did not finish.
pub fn dynamic(c: &Component, analysis: &crate::dialect::Analysis) -> Vec<Diagnostic> {
    let dead: BTreeSet<_> = analysis.dead.iter().map(|d| d.service).collect();
    let mut out = Vec::new();
    for (sid, service) in c.services.iter() {
        if dead.contains(&sid) || analysis.unproven.contains(&sid) {
            continue;
        }
        for id in statically_reachable(c, service) {
            if !analysis.reached.contains(&id) {
                let codel = &c.codels[id];
                out.push(never_reached(
                    &service.name.name,
                    &codel.name.name,
                    codel.kind.keyword(),
                    codel.name.span,
                ));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use genom_model::{Code, Diagnostic};

    use crate::testing;

    fn src(body: &str) -> String {
        format!("{}{body}", testing::HEADER)
    }

    fn found(src: &str) -> Vec<Diagnostic> {
        testing::check(src)
            .diagnostics
            .into_iter()
            .filter(|d| d.code == Code::UnreachableCodel)
            .collect()
    }

    fn text(src: &str, d: &Diagnostic, label: usize) -> String {
        let span = d.labels[label].span;
        src[span.start as usize..span.end as usize].to_owned()
    }

    const FORGOTTEN: &str = "service move {
  thread: main;
  start codel { exec: init(); next: goto; }
  exec codel goto { exec: go(); next: goto, end; }
  exec codel slow { exec: brake(); next: end; }
  inter codel stop { exec: halt(); }
}
";

    const CONNECTED: &str = "service move {
  thread: main;
  stops: move;
  start codel { exec: init(); on-inter: stop; next: goto; }
  exec codel goto { exec: go(); next: goto, slow, end; }
  exec codel slow { exec: brake(); next: end; }
  inter codel stop { exec: halt(); }
}
";

    #[test]
    fn a_codel_no_next_or_on_inter_leads_to_is_unreachable() {
        let s = src(FORGOTTEN);
        let d = found(&s);
        assert_eq!(d.len(), 2, "{d:?}");
        assert_eq!(
            d[0].message,
            "exec codel `slow` of service `move` is never reached"
        );
        assert_eq!(text(&s, &d[0], 0), "slow");
        assert_eq!(
            d[0].labels[0].message,
            "no path from the start codel leads here"
        );
        assert_eq!(
            d[1].message,
            "inter codel `stop` of service `move` is never reached"
        );
        assert_eq!(text(&s, &d[1], 0), "stop");
        assert!(
            d[0].help
                .as_deref()
                .is_some_and(|h| h.contains("nothing leads to `slow`"))
        );
    }

    #[test]
    fn next_and_on_inter_edges_both_reach() {
        assert_eq!(testing::count(&src(CONNECTED), Code::UnreachableCodel), 0);
        // Without `stops`, nothing can interrupt `move`: the codel graph
        // reaches `stop`, but no execution does (the dynamic part).
        let quiet = src(&CONNECTED.replace("  stops: move;\n", ""));
        let d = found(&quiet);
        assert_eq!(d.len(), 1);
        assert_eq!(
            d[0].message,
            "inter codel `stop` of service `move` is never reached in any execution"
        );
    }

    #[test]
    fn a_codel_reached_only_through_an_unreachable_one_is_unreachable_too() {
        let s = src("service move {
  thread: main;
  start codel { exec: init(); next: end; }
  exec codel a { exec: go(); on-inter: c; next: b; }
  exec codel b { exec: go(); next: a, end; }
  inter codel c { exec: halt(); }
}
");
        let d = found(&s);
        let names: Vec<String> = d.iter().map(|d| text(&s, d, 0)).collect();
        assert_eq!(names, ["a", "b", "c"]);
    }

    #[test]
    fn codels_after_an_inter_codel_are_reached() {
        let s = src("service move {
  thread: main;
  stops: move;
  start codel { exec: init(); on-inter: release; next: end; }
  inter codel release { exec: open(); next: halt; }
  inter codel halt { exec: halt(); }
}
");
        assert_eq!(testing::count(&s, Code::UnreachableCodel), 0);
    }

    #[test]
    fn control_codels_and_services_without_start_are_skipped() {
        let setter = src("service set {
  control codel { exec: check(); }
}
");
        assert_eq!(testing::count(&setter, Code::UnreachableCodel), 0);
        let no_start = src("service move {
  exec codel goto { exec: go(); next: end; }
}
");
        let codes = testing::codes(&no_start);
        assert!(codes.contains(&Code::MissingStart), "{codes:?}");
        assert!(!codes.contains(&Code::UnreachableCodel), "{codes:?}");
    }

    #[test]
    fn report() {
        insta::assert_snapshot!(testing::render(&src(FORGOTTEN)));
    }
}
