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

/// The static checks, in the order they run, with the words that name
/// them when a limit stops the phase before them.
const STATIC_CHECKS: [(&str, StaticCheck); 11] = [
    ("recursive types", recursive_type::check),
    ("codel prototypes", prototype_mismatch::check),
    ("update rules", update_rules::check),
    ("codel reachability", unreachable_codel::check),
    ("termination", no_termination::check),
    ("auto services", auto_terminates::check),
    ("unused reports", unused_report::check),
    ("on-inter cleanup", missing_on_inter::check),
    ("privilege escalation", privilege_escalation::check),
    ("codel overruns", codel_overrun::check),
    ("missing WCETs", missing_wcet::check),
];

/// Runs every check on the resolved model. Each is linear in the model
/// (plus what it reports); `watch` is looked at between two checks, and a
/// limit passed ends the phase with `incomplete` naming the checks left.
pub fn run(component: &Component, watch: &Watch) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for (i, (_, check)) in STATIC_CHECKS.iter().enumerate() {
        if let Some(limit) = watch.exceeded() {
            let left: Vec<&str> = STATIC_CHECKS[i..].iter().map(|(name, _)| *name).collect();
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
}
