//! Runs the stages of a check in order (text → AST → model → verdicts) and
//! gathers their diagnostics and statistics.

use std::path::Path;
use std::time::{Duration, Instant};

use genom_model::component::Component;
use genom_model::{
    Code, Diagnostic, FileId, Severity, SourceMap, Span, Statistics, sort_diagnostics,
};
use genom_parser::{Ast, LoadError, Loader};

use crate::engine::Limits;

/// Options of a check, built with consuming setters (as stateright's
/// checker builder).
#[derive(Debug, Clone)]
pub struct CheckOptions {
    max_states: usize,
    timeout: Option<Duration>,
    max_memory: usize,
    behaviour: bool,
    reduction: bool,
}

impl Default for CheckOptions {
    fn default() -> Self {
        CheckOptions {
            max_states: 10_000_000,
            timeout: None,
            max_memory: 8 << 30,
            behaviour: true,
            reduction: true,
        }
    }
}

impl CheckOptions {
    /// The defaults: every check, at most ten million states, 8 GiB of
    /// state storage, no time limit.
    pub fn new() -> Self {
        Self::default()
    }

    /// Stops exploring after this many states (then `incomplete`).
    #[must_use]
    pub fn max_states(mut self, n: usize) -> Self {
        self.max_states = n.max(1);
        self
    }

    /// Stops exploring after this long (then `incomplete`).
    #[must_use]
    pub fn timeout(mut self, d: Option<Duration>) -> Self {
        self.timeout = d;
        self
    }

    /// Stops exploring when state storage exceeds this many bytes.
    #[must_use]
    pub fn max_memory(mut self, bytes: usize) -> Self {
        self.max_memory = bytes;
        self
    }

    /// Runs the behavioural engine (default) or only the static checks.
    #[must_use]
    pub fn behaviour(mut self, on: bool) -> Self {
        self.behaviour = on;
        self
    }

    /// Explores untimed models with partial-order reduction (default) or
    /// every interleaving.
    #[must_use]
    pub fn reduction(mut self, on: bool) -> Self {
        self.reduction = on;
        self
    }

    fn limits(&self, started: Instant) -> Limits {
        Limits {
            max_states: self.max_states,
            deadline: self.timeout.map(|t| started + t),
            max_bytes: self.max_memory,
        }
    }
}

/// Everything a check found about one file.
#[derive(Debug, Clone)]
pub struct CheckResult {
    /// The checked file and its includes.
    pub sources: SourceMap,
    /// The syntax trees.
    pub ast: Ast,
    /// All diagnostics, sorted by file and position.
    pub diagnostics: Vec<Diagnostic>,
    /// The resolved component, when the file parsed completely and has a
    /// `component` item.
    pub component: Option<Component>,
    /// Exploration figures, when the engines ran.
    pub statistics: Option<Statistics>,
}

/// Checks the file at `path`. Fails only when that file cannot be read.
pub fn check_file(
    path: &Path,
    loader: &dyn Loader,
    options: &CheckOptions,
) -> Result<CheckResult, LoadError> {
    let text = loader.load(path)?;
    Ok(check_source(path, text, loader, options))
}

/// Checks already-loaded text; includes are read through `loader`.
pub fn check_source(
    path: &Path,
    text: String,
    loader: &dyn Loader,
    options: &CheckOptions,
) -> CheckResult {
    let started = Instant::now();
    let parsed = genom_parser::parse_source(path, text, loader);
    let mut diagnostics = parsed.diagnostics.clone();
    let mut component = None;
    if parsed.is_complete() {
        let start = parsed
            .sources
            .file(FileId(0))
            .map_or(Span::default(), |f| Span::point(f.base));
        let resolved = crate::resolve::resolve(&parsed.ast, start);
        diagnostics.extend(resolved.diagnostics);
        diagnostics.extend(crate::checks::run(&resolved.component));
        component = resolved.has_component.then_some(resolved.component);
    }
    // A codel longer than its period leaves the model well formed: the
    // engines still run, to give that verdict its timed trace.
    let clean = !diagnostics
        .iter()
        .any(|d| d.severity == Severity::Error && d.code != Code::CodelOverrun);
    let mut statistics = None;
    if let (Some(c), true, true) = (&component, clean, options.behaviour) {
        let analysis = if c.gives_timing() {
            let (analysis, facts) = crate::timed::analyse_timed(c, options.limits(started));
            diagnostics.extend(crate::checks::timing(c, &facts));
            attach_codel_overrun_traces(c, &facts, &mut diagnostics);
            analysis
        } else {
            crate::engine::analyse_with(c, options.limits(started), options.reduction)
        };
        diagnostics.extend(crate::checks::behaviour(c, &analysis));
        statistics = Some(Statistics {
            states: analysis.states,
            transitions: analysis.transitions,
            time_ms: 0.0,
            complete: analysis.stopped.is_none(),
            bytes_per_state: Some(analysis.bytes_per_state),
        });
    }
    sort_diagnostics(&mut diagnostics);
    if let Some(s) = &mut statistics {
        s.time_ms = started.elapsed().as_secs_f64() * 1000.0;
    }
    CheckResult {
        sources: parsed.sources,
        ast: parsed.ast,
        diagnostics,
        component,
        statistics,
    }
}

/// Gives each `codel-overrun` (a static check, whose primary label is the
/// codel's WCET) the timed trace the timed engine found for that codel: it
/// starts, and its thread wakes up again before it can have finished. A
/// codel that no execution runs keeps no trace.
fn attach_codel_overrun_traces(
    c: &Component,
    facts: &crate::timed::TimedFacts,
    diagnostics: &mut [Diagnostic],
) {
    for d in diagnostics
        .iter_mut()
        .filter(|d| d.code == Code::CodelOverrun && d.trace.is_none())
    {
        let found = facts
            .codel_overruns
            .iter()
            .find(|o| c.codels[o.codel].wcet.is_some_and(|w| w.span == d.span()));
        if let Some(o) = found {
            d.trace = Some(o.trace.clone());
        }
    }
}
