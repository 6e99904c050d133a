//! The checks, one file per check with its explanation, its diagnostic
//! constructors and its pass/fail tests. Static model checks ([`run`]) run
//! on the resolved component; behavioural verdicts ([`behaviour`]) read the
//! explorer's [`Analysis`]. Resolution checks belong to the front-end
//! (`genom_parser::checks`); their files here hold only their tests, which
//! run the whole check.

pub mod auto_terminates;
pub mod codel_overrun;
#[cfg(test)]
mod codel_transitions;
pub mod dead_service;
pub mod deadlock;
#[cfg(test)]
mod duplicate_definition;
pub mod incomplete;
#[cfg(test)]
mod invalid_attribute;
pub mod livelock;
pub mod max_time;
#[cfg(test)]
mod missing_component;
pub mod missing_on_inter;
pub mod missing_wcet;
pub mod no_termination;
pub mod privilege_escalation;
pub mod prototype_mismatch;
pub mod recursive_type;
pub mod response_time;
#[cfg(test)]
mod service_structure;
pub mod starvation;
pub mod thread_overrun;
#[cfg(test)]
mod type_mismatch;
pub mod unbounded_interrupt;
#[cfg(test)]
mod unknown_name;
pub mod unreachable_codel;
pub mod unused_report;
pub mod update_rules;

use genom_model::Diagnostic;
use genom_model::component::Component;
use genom_model::limits::Watch;

use crate::engine::Analysis;
use crate::timed::TimedFacts;

/// A static check: the model in, its findings out.
type StaticCheck = fn(&Component) -> Vec<Diagnostic>;

/// Which components a static check applies to: the one place that says it
/// (a check never tests the component's language itself to skip it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Applies {
    /// Every component.
    Always,
    /// LANGUAGE.md components only (the reason is in the check's docs).
    DialectOnly,
}

/// The static checks, in the order they run, with the words that name
/// them when a limit stops the phase before them and the components they
/// apply to.
const STATIC_CHECKS: [(&str, Applies, StaticCheck); 11] = [
    ("recursive types", Applies::Always, recursive_type::check),
    (
        "codel prototypes",
        Applies::Always,
        prototype_mismatch::check,
    ),
    ("update rules", Applies::Always, update_rules::check),
    (
        "codel reachability",
        Applies::Always,
        unreachable_codel::check,
    ),
    ("termination", Applies::Always, no_termination::check),
    ("auto services", Applies::Always, auto_terminates::check),
    ("unused reports", Applies::DialectOnly, unused_report::check),
    (
        "on-inter cleanup",
        Applies::DialectOnly,
        missing_on_inter::check,
    ),
    (
        "privilege escalation",
        Applies::Always,
        privilege_escalation::check,
    ),
    ("codel overruns", Applies::Always, codel_overrun::check),
    ("missing WCETs", Applies::Always, missing_wcet::check),
];

/// Runs every check that applies to the resolved model. Each is linear in
/// the model (plus what it reports); `watch` is looked at between two
/// checks, and a limit passed ends the phase with `incomplete` naming the
/// checks left.
pub fn run(component: &Component, watch: &Watch) -> Vec<Diagnostic> {
    let is_genom3 = component.genom3.is_some();
    let applying: Vec<&(&str, Applies, StaticCheck)> = STATIC_CHECKS
        .iter()
        .filter(|(_, applies, _)| !(is_genom3 && *applies == Applies::DialectOnly))
        .collect();
    let mut out = Vec::new();
    for (i, (_, _, check)) in applying.iter().enumerate() {
        if let Some(limit) = watch.exceeded() {
            let left: Vec<&str> = applying[i..].iter().map(|(name, _, _)| *name).collect();
            out.push(genom_model::limits::static_stopped(
                component.name.span,
                limit,
                &left,
            ));
            break;
        }
        out.extend(check(component));
    }
    out
}

/// The behavioural verdicts of an exploration.
pub fn behaviour(component: &Component, analysis: &Analysis) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    out.extend(deadlock::check(component, analysis));
    out.extend(starvation::check(component, analysis));
    out.extend(dead_service::check(component, analysis));
    out.extend(unbounded_interrupt::check(component, analysis));
    out.extend(unreachable_codel::dynamic(component, analysis));
    out.extend(incomplete::check(component, analysis));
    out
}

/// The timing verdicts of the timed explorations.
pub fn timing(component: &Component, facts: &TimedFacts) -> Vec<Diagnostic> {
    let mut out = thread_overrun::check(component, facts);
    out.extend(max_time::check(component, facts));
    out
}

#[cfg(test)]
mod watch_tests {
    use super::*;
    use genom_model::Code;

    #[test]
    fn a_limit_passed_stops_the_static_phase_naming_what_is_left() {
        let c = Component::default();
        let watch = Watch {
            deadline: Some(std::time::Instant::now()),
            max_memory: usize::MAX,
        };
        let found = run(&c, &watch);
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].code, Code::Incomplete);
        assert!(found[0].message.contains("during the static checks"));
        let help = found[0].help.as_deref().unwrap_or_default();
        assert!(
            help.contains("recursive types") && help.contains("missing WCETs"),
            "{help}"
        );
        assert!(
            run(&c, &Watch::unlimited())
                .iter()
                .all(|d| d.code != Code::Incomplete)
        );
    }

    /// The registry, not the check, leaves the dialect-only checks out of a
    /// GenoM3 component: `missing-on-inter` would fire on this activity
    /// (interrupted, without a `stop` codel), and `run` does not run it.
    #[test]
    fn dialect_only_checks_are_left_out_of_genom3_components_by_the_registry() {
        let text = "component c {
  exception oops;
  task t { period 10 ms; };
  activity a() { task t; throw oops; codel<start> go() yield pause::start, ether; };
  activity b() { task t; interrupts a; codel<start> h() yield ether; };
};
";
        let c = genom_genom3::load_clean(text, None).unwrap_or_default();
        assert!(c.genom3.is_some(), "a GenoM3 component");
        assert!(!missing_on_inter::check(&c).is_empty(), "the check fires");
        let found = run(&c, &Watch::unlimited());
        let skipped = [Code::MissingOnInter, Code::UnusedReport];
        assert!(
            found.iter().all(|d| !skipped.contains(&d.code)),
            "{found:?}"
        );
    }
}
