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

use crate::engine::Analysis;
use crate::timed::TimedFacts;

/// Runs every check on the resolved model.
pub fn run(component: &Component) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    out.extend(recursive_type::check(component));
    out.extend(prototype_mismatch::check(component));
    out.extend(update_rules::check(component));
    out.extend(unreachable_codel::check(component));
    out.extend(no_termination::check(component));
    out.extend(auto_terminates::check(component));
    out.extend(unused_report::check(component));
    out.extend(missing_on_inter::check(component));
    out.extend(privilege_escalation::check(component));
    out.extend(codel_overrun::check(component));
    out.extend(missing_wcet::check(component));
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
