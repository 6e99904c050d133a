//! One candidate checked as `genom-check check` does, down to its error
//! codes.

use std::collections::BTreeSet;

use genom_model::component::{CodelId, Component};
use genom_model::{Code, Severity};

use crate::kernel::explore::Limits;
use crate::timed::analyse_timed;

/// The outcome of checking one candidate.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Eval {
    /// No error.
    Clean,
    /// These error codes (sorted, without duplicates).
    Violation(Vec<Code>),
    /// An exploration stopped on a limit.
    Incomplete,
}

/// A candidate's evaluation with what it cost.
#[derive(Debug, Clone)]
pub struct Verdict {
    /// Clean or not.
    pub eval: Eval,
    /// Whether an exploration ran (else the static checks decided).
    pub explored: bool,
    /// Codels some execution runs (empty when not explored).
    pub reached: BTreeSet<CodelId>,
}

/// Checks `c` as `genom-check check` does and keeps its error codes: the
/// static checks, then (when they have no error) the timed engine (or the
/// untimed one for a component without timing) with the timing and
/// behavioural verdicts.
pub fn verdict(c: &Component, limits: Limits) -> Verdict {
    let watch = genom_model::limits::Watch {
        deadline: limits.deadline,
        max_memory: limits.max_bytes,
    };
    let mut diagnostics = crate::checks::run(c, &watch);
    let mut explored = false;
    let mut reached = BTreeSet::new();
    if !diagnostics.iter().any(|d| d.severity == Severity::Error) {
        explored = true;
        let analysis = if c.gives_timing() {
            let (analysis, facts) = analyse_timed(c, limits);
            diagnostics.extend(crate::checks::timing(c, &facts));
            analysis
        } else {
            crate::dialect::analyse(c, limits)
        };
        diagnostics.extend(crate::checks::behaviour(c, &analysis));
        if analysis.stopped.is_some() {
            return Verdict {
                eval: Eval::Incomplete,
                explored,
                reached,
            };
        }
        reached = analysis.reached;
    }
    let codes: BTreeSet<Code> = diagnostics
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .map(|d| d.code)
        .collect();
    let eval = if codes.is_empty() {
        Eval::Clean
    } else if codes.contains(&Code::Incomplete) {
        Eval::Incomplete
    } else {
        Eval::Violation(codes.into_iter().collect())
    };
    Verdict {
        eval,
        explored,
        reached,
    }
}
