//! The checker's stage of a whole file: what a front-end loaded in, every
//! verdict out. The one place that picks the engines by the language the
//! front-end read: LANGUAGE.md's untimed or timed engine ([`verify`]), or,
//! after the same static checks, GenoM3's engines ([`verify_genom3`]).

use std::time::Instant;

use genom_model::component::Component;
use genom_model::frontend::Loaded;
use genom_model::{
    Assumption, Code, Diagnostic, Dialect, Pragma, ResponseTime, Severity, SourceMap, Statistics,
    sort_diagnostics,
};

use crate::verify::{CheckOptions, Verdicts, verify};
use crate::verify_genom3::verify_genom3;

/// Everything a check found about one file.
#[derive(Debug, Clone)]
pub struct Checked {
    /// The language the file was read as.
    pub dialect: Dialect,
    /// The checked file and its includes (and side files).
    pub sources: SourceMap,
    /// The `#pragma` lines of a GenoM3 file, in preprocessor order.
    pub pragmas: Vec<Pragma>,
    /// All diagnostics, sorted by file and position.
    pub diagnostics: Vec<Diagnostic>,
    /// The resolved component, when the file parsed completely and has a
    /// component.
    pub component: Option<Component>,
    /// Exploration figures, when the engines ran.
    pub statistics: Option<Statistics>,
    /// Worst-case response times by service name, when an engine computed
    /// them.
    pub response_times: Vec<ResponseTime>,
}

/// Checks what a front-end loaded: the static checks, then (no errors, no
/// `--static-only`) the engines of its language. `started` is when the
/// whole check started (for its time limit and figures).
pub fn check(loaded: Loaded, options: &CheckOptions, started: Instant) -> Checked {
    let Loaded {
        dialect,
        sources,
        model,
        has_component,
        diagnostics,
        pragmas,
        assumptions,
    } = loaded;
    let verdicts = match dialect {
        Dialect::Gen => verify(model, has_component, diagnostics, options, started),
        Dialect::Genom3 => genom3(
            model,
            has_component,
            diagnostics,
            &assumptions,
            options,
            started,
        ),
    };
    Checked {
        dialect,
        sources,
        pragmas,
        diagnostics: verdicts.diagnostics,
        component: verdicts.component,
        statistics: verdicts.statistics,
        response_times: verdicts.response_times,
    }
}

/// The check of a GenoM3 model: the static checks, then (no
/// `--static-only`, no errors) the GenoM3 engine explores it under
/// GenoM3's semantics; with WCETs, the timed GenoM3 engine checks the
/// schedulability of every task. `assumptions` are the load's (the WCET
/// file), first among the exploration's.
fn genom3(
    model: Option<Component>,
    has_component: bool,
    diagnostics: Vec<Diagnostic>,
    assumptions: &[Assumption],
    options: &CheckOptions,
    started: Instant,
) -> Verdicts {
    let static_only = options.clone().behaviour(false);
    let mut verdicts = verify(model, has_component, diagnostics, &static_only, started);
    // A codel longer than its task's period (`codel-overrun`) is a timing
    // finding, not a broken model: the engines still run.
    let clean = !verdicts
        .diagnostics
        .iter()
        .any(|d| d.severity == Severity::Error && d.code != Code::CodelOverrun);
    // (The component stays in the verdicts: `--static-only` and unclean
    // checks keep it too.)
    let explored = match (options.runs_behaviour() && clean, &verdicts.component) {
        (true, Some(c)) => verify_genom3(c, options, started),
        _ => None,
    };
    if let Some(mut v) = explored {
        v.statistics
            .assumptions
            .splice(0..0, assumptions.iter().cloned());
        v.attach_codel_overrun_traces(&mut verdicts.diagnostics);
        verdicts.diagnostics.extend(v.diagnostics);
        sort_diagnostics(&mut verdicts.diagnostics);
        verdicts.statistics = Some(v.statistics);
        verdicts.response_times = v.response_times;
    }
    verdicts
}
