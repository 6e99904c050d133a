//! `no-termination`: a non-`auto` service with a reachable codel from which
//! no chain of `next` outcomes ever ends the service (LANGUAGE.md 3 and 4).
//!
//! Reachable means reached from the start codel through `next` outcomes and
//! `on-inter` cleanups; ending means reaching a codel with an `end` or
//! report outcome through `next` outcomes only, that is without being
//! interrupted. A client of such a service waits for a final reply that
//! only an interruption (another request, or the `max-time` watchdog) can
//! produce: usually an exit outcome was forgotten in a loop. `auto`
//! services are meant to run forever (see `auto-terminates`), and services
//! without a start codel complete at once.

use std::collections::BTreeSet;

use genom_model::component::{CodelId, Component, Outcome, Service};
use genom_model::kinds::ServiceKind;
use genom_model::{Code, Diagnostic, Dialect, Span};
use petgraph::visit::{Dfs, Reversed};

use super::registry::{Applies, StaticCheck};
use super::unreachable_codel::{CodelGraph, codel_graph, reachable_from};

/// `genom-check explain no-termination`.
pub const EXPLANATION: &str = r#"A service (not `auto`) has a reachable codel from which it can never end by
itself: no chain of `next` outcomes from that codel reaches `end` or a
report, so once there the service loops until something interrupts it.

Why it matters: the client waits for a final reply that only an
interruption can produce: another request that `stops` the service, or the
`max-time` watchdog, and then the reply is `INTERRUPTED` or `TIMEOUT`,
never success. This is almost always a forgotten exit outcome in a loop.

Example:

```
service track {
  thread: motionTask;
  start codel { exec: init(); next: follow; }
  exec codel follow { exec: go(); next: follow; }   // no-termination: no `end` nor report
}
```

Add an exit outcome (`next: follow, end;` or a report) to the loop. A
service meant to run until it is stopped should be `auto`, or at least have
a `max-time` so that the watchdog bounds it. Codels reached only through
`on-inter` count too: an inter codel loop that never ends leaves the
interrupted service stuck."#;

/// [`no_termination`] in GenoM3's words: an activity whose state machine
/// cannot reach `ether` from some reachable state.
pub fn no_termination_genom3(
    activity: &str,
    first: (&str, Span),
    others: &[(&str, Span)],
) -> Diagnostic {
    let (name, span) = first;
    let d = Diagnostic::new(
        Code::NoTermination,
        format!("activity `{activity}` can never end by itself once in state `{name}`"),
        span,
        "no chain of yields from here reaches `ether`",
    );
    nor_from(d, others).with_help(
        "add `ether` to a yield of a state of the loop; as it is, only an interruption \
         (`interrupts`, `kill`, `abort_activity`) ends it, through its `stop` codel if it has one",
    )
}

/// A service that cannot end by itself from some reachable codels.
pub fn no_termination(
    service: &str,
    has_max_time: bool,
    first: (&str, Span),
    others: &[(&str, Span)],
) -> Diagnostic {
    let (name, span) = first;
    let help = if has_max_time {
        "only an interruption or the `max-time` watchdog can end it, never with success: add an \
         exit outcome (`end` or a report) to the `next` of a codel of the loop"
    } else {
        "add an exit outcome (`end` or a report) to the `next` of a codel of the loop, or give \
         the service a `max-time` so that the watchdog bounds it"
    };
    let d = Diagnostic::new(
        Code::NoTermination,
        format!("service `{service}` can never end by itself once at codel `{name}`"),
        span,
        "no chain of `next` outcomes from here reaches `end` or a report",
    );
    nor_from(d, others).with_help(help)
}

/// A label on each other stuck codel or state.
fn nor_from(mut d: Diagnostic, others: &[(&str, Span)]) -> Diagnostic {
    for &(other, span) in others {
        d = d.with_label(span, format!("nor from `{other}`"));
    }
    d
}

/// The codels of `graph` from which a codel with an `end` or report outcome
/// is reachable (along the graph's edges).
fn can_end(c: &Component, graph: &CodelGraph) -> BTreeSet<CodelId> {
    let reversed = Reversed(graph);
    let mut dfs = Dfs::empty(reversed);
    let mut out = BTreeSet::new();
    for id in graph.nodes() {
        let terminal = c.codels[id]
            .outcomes()
            .iter()
            .any(|o| matches!(o, Outcome::End | Outcome::Report(_)));
        if !terminal {
            continue;
        }
        dfs.move_to(id);
        while let Some(node) = dfs.next(reversed) {
            out.insert(node);
        }
    }
    out
}

/// The reachable codels of `service`, in codel order, that cannot end it.
fn stuck_codels(c: &Component, service: &Service, start: CodelId) -> Vec<CodelId> {
    let reached = reachable_from(&codel_graph(c, service, true), start);
    let ending = can_end(c, &codel_graph(c, service, false));
    service
        .codels
        .iter()
        .copied()
        .filter(|id| reached.contains(id) && !ending.contains(id))
        .collect()
}

/// The registry's entry ([`super::STATIC_CHECKS`]).
pub const CHECK: StaticCheck = StaticCheck {
    name: "termination",
    applies: Applies::Always,
    run: check,
    codes: &[(Code::NoTermination, EXPLANATION)],
};

/// Reports every non-`auto` service with a start codel that has reachable
/// codels from which it cannot end by itself.
pub fn check(c: &Component) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for service in c.services.values() {
        let Some(start) = service.start else { continue };
        if service.kind == ServiceKind::Auto {
            continue;
        }
        let stuck: Vec<(&str, Span)> = stuck_codels(c, service, start)
            .into_iter()
            .map(|id| (c.codels[id].name.name.as_str(), c.codels[id].name.span))
            .collect();
        let Some((&first, others)) = stuck.split_first() else {
            continue;
        };
        out.push(match c.dialect() {
            Dialect::Genom3 => no_termination_genom3(&service.name.name, first, others),
            Dialect::Gen => no_termination(
                &service.name.name,
                service.max_time.is_some(),
                first,
                others,
            ),
        });
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
            .filter(|d| d.code == Code::NoTermination)
            .collect()
    }

    fn labels(src: &str, d: &Diagnostic) -> Vec<(String, String)> {
        d.labels
            .iter()
            .map(|l| {
                let text = &src[l.span.start as usize..l.span.end as usize];
                (text.to_owned(), l.message.clone())
            })
            .collect()
    }

    const ENDLESS: &str = "service track {
  thread: main;
  start codel { exec: init(); next: follow; }
  exec codel follow { exec: go(); next: follow, adjust; }
  exec codel adjust { exec: adjust(); next: follow; }
}
";

    const WITH_EXIT: &str = "service track {
  thread: main;
  report: LOST;
  start codel { exec: init(); next: follow; }
  exec codel follow { exec: go(); next: follow, adjust; }
  exec codel adjust { exec: adjust(); next: follow, LOST; }
}
";

    #[test]
    fn a_loop_without_exit_cannot_end() {
        let s = src(ENDLESS);
        let d = found(&s);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(
            d[0].message,
            "service `track` can never end by itself once at codel `start`"
        );
        let l = labels(&s, &d[0]);
        assert_eq!(l.len(), 3);
        assert_eq!(l[0].0, "start");
        assert_eq!(
            l[0].1,
            "no chain of `next` outcomes from here reaches `end` or a report"
        );
        assert_eq!(l[1], ("follow".into(), "nor from `follow`".into()));
        assert_eq!(l[2], ("adjust".into(), "nor from `adjust`".into()));
        assert!(
            d[0].help
                .as_deref()
                .is_some_and(|h| h.contains("`max-time`"))
        );
    }

    #[test]
    fn a_report_outcome_in_the_loop_ends_it() {
        assert_eq!(testing::count(&src(WITH_EXIT), Code::NoTermination), 0);
    }

    #[test]
    fn only_the_codels_past_the_exit_are_reported() {
        let s = src("service track {
  thread: main;
  start codel { exec: init(); next: follow, end; }
  exec codel follow { exec: go(); next: follow; }
}
");
        let d = found(&s);
        assert_eq!(d.len(), 1);
        assert_eq!(labels(&s, &d[0]).len(), 1);
        assert_eq!(labels(&s, &d[0])[0].0, "follow");
    }

    #[test]
    fn an_absent_or_empty_next_ends_the_service() {
        let s = src("service once {
  thread: main;
  start codel { exec: init(); next: a, b; }
  exec codel a { exec: go(); }
  exec codel b { exec: go(); next: ; }
}
");
        assert_eq!(testing::count(&s, Code::NoTermination), 0);
    }

    #[test]
    fn an_endless_inter_codel_loop_is_reported_and_on_inter_alone_does_not_end() {
        let s = src("service track {
  thread: main;
  max-time: 1s;
  start codel { exec: init(); on-inter: stop; next: end; }
  inter codel stop { exec: halt(); next: stop; }
}
");
        let d = found(&s);
        assert_eq!(d.len(), 1);
        assert_eq!(labels(&s, &d[0])[0].0, "stop");
        assert!(
            d[0].help
                .as_deref()
                .is_some_and(|h| h.starts_with("only an interruption"))
        );
    }

    #[test]
    fn auto_services_and_unreachable_loops_are_not_reported() {
        let auto = src("auto service watch {
  thread: main;
  start codel { exec: init(); next: loop; }
  exec codel loop { exec: go(); next: loop; }
}
");
        assert_eq!(testing::count(&auto, Code::NoTermination), 0);
        let dead = src("service once {
  thread: main;
  start codel { exec: init(); next: end; }
  exec codel loop { exec: go(); next: loop; }
}
");
        assert_eq!(testing::count(&dead, Code::NoTermination), 0);
        assert_eq!(testing::count(&dead, Code::UnreachableCodel), 1);
    }

    #[test]
    fn report() {
        insta::assert_snapshot!(testing::render(&src(ENDLESS)));
    }
}
