//! The checks, one file per check with its explanation, its diagnostic
//! constructors and its pass/fail tests. Static model checks ([`run`]) run
//! on the resolved component; behavioural verdicts ([`behaviour`]) read the
//! explorer's [`Analysis`]. Resolution checks belong to the front-end
//! (`gen_frontend::checks`); their files here hold only their tests, which
//! run the whole check.
//!
//! The registry: a static check is its file (its `CHECK`: name, the
//! components it applies to, the function, its codes and explanations)
//! and one line in [`STATIC_CHECKS`]; a verdict of the engines lists its
//! codes in [`VERDICTS`]. `genom-check explain` reads the explanations
//! from here ([`explanation`]).

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
pub mod registry;
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

use genom_model::component::Component;
use genom_model::limits::Watch;
use genom_model::{Code, Diagnostic};

use crate::dialect::Analysis;
use crate::timed::TimedFacts;

pub use registry::{Applies, Explained, StaticCheck};

/// The static checks, in the order they run: the one place a static check
/// is registered. Each check file describes itself in its `CHECK` (the
/// words naming it, the components it applies to, its codes and their
/// explanations).
pub const STATIC_CHECKS: &[&StaticCheck] = &[
    &recursive_type::CHECK,
    &prototype_mismatch::CHECK,
    &update_rules::CHECK,
    &unreachable_codel::CHECK,
    &no_termination::CHECK,
    &auto_terminates::CHECK,
    &unused_report::CHECK,
    &missing_on_inter::CHECK,
    &privilege_escalation::CHECK,
    &codel_overrun::CHECK,
    &missing_wcet::CHECK,
];

/// The codes of the verdicts the engines' explorations give (each file's
/// `CODES`), with their explanations: [`behaviour`], [`timing`], the
/// response times and the GenoM3 engines call these checks themselves.
pub const VERDICTS: &[&[Explained]] = &[
    deadlock::CODES,
    starvation::CODES,
    dead_service::CODES,
    unbounded_interrupt::CODES,
    incomplete::CODES,
    thread_overrun::CODES,
    max_time::CODES,
    response_time::CODES,
    livelock::CODES,
];

/// Every code the checker reports, with its explanation: the registered
/// static checks', then the verdicts'.
pub fn codes() -> impl Iterator<Item = Explained> {
    STATIC_CHECKS
        .iter()
        .flat_map(|c| c.codes.iter())
        .chain(VERDICTS.iter().flat_map(|v| v.iter()))
        .copied()
}

/// The explanation (`genom-check explain`) of a code the checker reports;
/// `None` for the front-ends' codes.
pub fn explanation(code: Code) -> Option<&'static str> {
    codes().find(|&(c, _)| c == code).map(|(_, text)| text)
}

/// Runs every check that applies to the resolved model. Each is linear in
/// the model (plus what it reports); `watch` is looked at between two
/// checks, and a limit passed ends the phase with `incomplete` naming the
/// checks left.
pub fn run(component: &Component, watch: &Watch) -> Vec<Diagnostic> {
    let dialect = component.dialect();
    let applying: Vec<&StaticCheck> = STATIC_CHECKS
        .iter()
        .copied()
        .filter(|c| c.applies.to(dialect))
        .collect();
    let mut out = Vec::new();
    for (i, check) in applying.iter().enumerate() {
        if let Some(limit) = watch.exceeded() {
            let left: Vec<&str> = applying[i..].iter().map(|c| c.name).collect();
            out.push(genom_model::limits::static_stopped(
                component.name.span,
                limit,
                &left,
            ));
            break;
        }
        out.extend((check.run)(component));
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
        let c = genom3_frontend::load_clean(text, None).unwrap_or_default();
        assert_eq!(c.dialect(), genom_model::Dialect::Genom3);
        assert!(!missing_on_inter::check(&c).is_empty(), "the check fires");
        let found = run(&c, &Watch::unlimited());
        let skipped = [Code::MissingOnInter, Code::UnusedReport];
        assert!(
            found.iter().all(|d| !skipped.contains(&d.code)),
            "{found:?}"
        );
    }
}

#[cfg(test)]
mod registry_tests {
    use std::collections::BTreeSet;

    use super::*;

    /// A check's code is registered once, with a long explanation (a
    /// static check's shows an example); a static check's name is unique.
    #[test]
    fn every_registered_code_is_explained_once() {
        let mut seen = BTreeSet::new();
        for (code, text) in codes() {
            assert!(seen.insert(code), "`{code}` is registered twice");
            assert!(!text.trim().is_empty(), "`{code}` has no explanation");
        }
        for &(code, text) in STATIC_CHECKS.iter().flat_map(|c| c.codes) {
            assert!(
                text.matches("```").count() >= 2,
                "the explanation of `{code}` has no fenced example"
            );
        }
        let names: BTreeSet<&str> = STATIC_CHECKS.iter().map(|c| c.name).collect();
        assert_eq!(names.len(), STATIC_CHECKS.len(), "two checks share a name");
        assert!(STATIC_CHECKS.iter().all(|c| !c.codes.is_empty()));
    }

    /// A registered check's findings carry only the codes it registered
    /// (`incomplete` aside, which a limit may add): a code it reports
    /// without registering would have no explanation.
    #[test]
    fn static_checks_report_only_their_registered_codes() {
        let src = format!(
            "{}service s {{ thread: main; start codel {{ exec: f(); next: s; }}
  exec codel s {{ exec: g(); next: s; }} report r; }}\n",
            crate::testing::HEADER
        );
        let c = crate::testing::check(&src).component.unwrap_or_default();
        for check in STATIC_CHECKS {
            for d in (check.run)(&c) {
                assert!(
                    check.codes.iter().any(|&(code, _)| code == d.code),
                    "{} reports `{}`, which it does not register",
                    check.name,
                    d.code
                );
            }
        }
    }
}
