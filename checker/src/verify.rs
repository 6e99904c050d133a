//! The checker's stage of a check: the static checks on the model a
//! front-end lowered, then (when the model is a clean component) the
//! untimed or timed engine and the verdicts of its exploration.

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use genom_model::component::{Component, ServiceId};
use genom_model::limits::Watch;
use genom_model::{Code, Diagnostic, ResponseTime, Severity, Statistics, sort_diagnostics};

use genom_model::stats::{Decision, Method as Decider};

use crate::dialect::{Limits, Method};

/// `--engine`: which engine explores the untimed clusters and GenoM3's
/// untimed parts (`engine::dialect::method`, `engine::kernel::method`;
/// timed models always use the zone engine).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Engine {
    /// The explicit explorer, and the symbolic one for a cluster it could
    /// not finish within the state or memory limit.
    #[default]
    Auto,
    /// The explicit explorer only.
    Explicit,
    /// The symbolic (BDD) engine for every cluster it accepts.
    Symbolic,
}

/// The default of `--max-instances`: one instance of each activity at a
/// time, which gives the untimed GenoM3 verdicts exactly (instances of one
/// activity only interrupt or delay each other: see
/// `docs/genom3-semantics.md` section 14).
pub const DEFAULT_MAX_INSTANCES: usize = 1;

/// Options of a check, built with consuming setters (as stateright's
/// checker builder).
#[derive(Debug, Clone)]
pub struct CheckOptions {
    max_states: usize,
    timeout: Option<Duration>,
    max_memory: usize,
    behaviour: bool,
    reduction: bool,
    engine: Engine,
    max_instances: usize,
    deadlines: BTreeMap<String, u64>,
    response_times: bool,
}

impl Default for CheckOptions {
    fn default() -> Self {
        CheckOptions {
            max_states: 10_000_000,
            timeout: None,
            max_memory: 8 << 30,
            behaviour: true,
            reduction: true,
            engine: Engine::Auto,
            max_instances: DEFAULT_MAX_INSTANCES,
            deadlines: BTreeMap::new(),
            response_times: false,
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

    /// `--engine`: which engine explores the untimed clusters.
    #[must_use]
    pub fn engine(mut self, engine: Engine) -> Self {
        self.engine = engine;
        self
    }

    /// The exploration method of the untimed analysis: `--no-reduction`
    /// makes the explicit engine explore every interleaving (and leaves the
    /// symbolic one as it is).
    pub fn method(&self) -> Method {
        match (self.engine, self.reduction) {
            (Engine::Symbolic, _) => Method::Symbolic,
            (_, false) => Method::Exhaustive,
            (Engine::Auto, true) => Method::Auto,
            (Engine::Explicit, true) => Method::Explicit,
        }
    }

    /// The method of an engine that has no reduction to turn off (GenoM3's
    /// untimed parts): `--engine` alone.
    pub fn kernel_method(&self) -> crate::kernel::method::Method {
        use crate::kernel::method::Method as M;
        match self.engine {
            Engine::Auto => M::Auto,
            Engine::Explicit => M::Explicit,
            Engine::Symbolic => M::Symbolic,
        }
    }

    /// GenoM3: the most instances of one activity explored at once (then
    /// the verdicts say they hold up to that many).
    #[must_use]
    pub fn max_instances(mut self, n: usize) -> Self {
        self.max_instances = n.max(1);
        self
    }

    /// `--deadline SERVICE=DURATION`: a worst-case response time of the
    /// service later than `ns` nanoseconds is a `deadline-miss` error
    /// (services the component does not have are ignored here: the CLI
    /// reports them).
    #[must_use]
    pub fn deadline_for(mut self, service: &str, ns: u64) -> Self {
        self.deadlines.insert(service.to_owned(), ns);
        self
    }

    /// `--response-times`: computes every service's worst-case response
    /// time (one more timed exploration, 2-3 times the cost of the timing
    /// checks; always done for the services given a deadline).
    #[must_use]
    pub fn response_times(mut self, on: bool) -> Self {
        self.response_times = on;
        self
    }

    /// The deadlines of [`CheckOptions::deadline_for`] that name services
    /// of `c`, by service.
    pub fn deadline_ids(&self, c: &Component) -> BTreeMap<ServiceId, u64> {
        self.deadlines
            .iter()
            .filter_map(|(name, &ns)| {
                let s = c.services.iter().find(|(_, s)| &s.name.name == name)?.0;
                Some((s, ns))
            })
            .collect()
    }

    /// Whether response times are asked for (`--response-times`, or some
    /// `--deadline`).
    pub fn wants_response_times(&self) -> bool {
        self.response_times || !self.deadlines.is_empty()
    }

    /// The deadlines of [`CheckOptions::deadline_for`], by service name.
    pub fn deadlines(&self) -> &BTreeMap<String, u64> {
        &self.deadlines
    }

    /// The instance bound of [`CheckOptions::max_instances`].
    pub fn instance_bound(&self) -> usize {
        self.max_instances
    }

    /// When a check started at `started` must stop (`--timeout`), if ever.
    pub fn deadline(&self, started: Instant) -> Option<Instant> {
        // A timeout past what the clock can represent is no deadline.
        self.timeout.and_then(|t| started.checked_add(t))
    }

    /// The limits of a check started at `started`, as every phase looks at
    /// them.
    pub fn watch(&self, started: Instant) -> Watch {
        Watch {
            deadline: self.deadline(started),
            max_memory: self.max_memory,
        }
    }

    /// Whether the behavioural engines run (not `--static-only`).
    pub fn runs_behaviour(&self) -> bool {
        self.behaviour
    }

    /// The state limit and the time limit, as people read them
    /// (`10,000,000 states` or `10,000,000 states or 30s`).
    pub fn describe_limits(&self) -> String {
        let states =
            genom_model::limits::grouped(u64::try_from(self.max_states).unwrap_or(u64::MAX));
        match self.timeout {
            Some(t) => format!(
                "{states} states or {}",
                genom_model::duration::format_ns(u64::try_from(t.as_nanos()).unwrap_or(u64::MAX))
            ),
            None => format!("{states} states"),
        }
    }

    pub(crate) fn limits(&self, started: Instant) -> Limits {
        Limits {
            max_states: self.max_states,
            deadline: self.deadline(started),
            max_bytes: self.max_memory,
        }
    }
}

/// What the checker found about a model.
#[derive(Debug, Clone)]
pub struct Verdicts {
    /// All diagnostics (the front-end's and the checker's), sorted by file
    /// and position.
    pub diagnostics: Vec<Diagnostic>,
    /// The checked component, when the model is a component's.
    pub component: Option<Component>,
    /// Exploration figures, when the engines ran.
    pub statistics: Option<Statistics>,
    /// Worst-case response times by service name, when the timed engine
    /// ran (the component gives timing).
    pub response_times: Vec<ResponseTime>,
}

/// Checks the model a front-end lowered. `model` is the resolved model
/// (`None` when the text did not parse completely), `has_component` whether
/// the file has a `component` item, `diagnostics` the front-end's, and
/// `started` when the whole check started (for its time limit and
/// figures).
pub fn verify(
    model: Option<Component>,
    has_component: bool,
    mut diagnostics: Vec<Diagnostic>,
    options: &CheckOptions,
    started: Instant,
) -> Verdicts {
    let mut component = None;
    if let Some(model) = model {
        diagnostics.extend(crate::checks::run(&model, &options.watch(started)));
        component = has_component.then_some(model);
    }
    // A codel longer than its period leaves the model well formed: the
    // engines still run, to give that verdict its timed trace.
    let clean = !diagnostics
        .iter()
        .any(|d| d.severity == Severity::Error && d.code != Code::CodelOverrun);
    // With errors the timing checks do not run: `missing-wcet` would name
    // properties "left unproven" that nothing tried to prove.
    if !clean {
        diagnostics.retain(|d| d.code != Code::MissingWcet);
    }
    let mut statistics = None;
    let mut response_times = Vec::new();
    if let (Some(c), true, true) = (&component, clean, options.behaviour) {
        let timed = c.gives_timing();
        let analysis = if timed {
            let (analysis, facts) = crate::timed::analyse_timed(c, options.limits(started));
            diagnostics.extend(crate::checks::timing(c, &facts));
            attach_codel_overrun_traces(c, &facts, &mut diagnostics);
            if options.wants_response_times() {
                let (times, found) = responses(c, options, started, &analysis);
                response_times = times;
                diagnostics.extend(found);
            }
            analysis
        } else {
            crate::dialect::analyse_using(c, options.limits(started), options.method())
        };
        diagnostics.extend(crate::checks::behaviour(c, &analysis));
        statistics = Some(Statistics {
            states: analysis.states,
            transitions: analysis.transitions,
            time_ms: 0.0,
            complete: analysis.stopped.is_none(),
            bytes_per_state: Some(analysis.footprint.bytes_per_state),
            decided_by: decisions(c, &analysis, timed),
            // Instances need no bound: LANGUAGE.md allows one per service
            // (section 3); durations are the codels' `max-time`s.
            assumptions: if timed {
                vec![genom_model::Assumption::max_times()]
            } else {
                Vec::new()
            },
        });
    }
    sort_diagnostics(&mut diagnostics);
    if let Some(s) = &mut statistics {
        s.time_ms = started.elapsed().as_secs_f64() * 1000.0;
    }
    Verdicts {
        diagnostics,
        component,
        statistics,
        response_times,
    }
}

/// What decided each part: one zone exploration of the whole component
/// when `timed` (the timed engine explores its clusters with zones alike),
/// else the untimed analysis's record.
fn decisions(c: &Component, analysis: &crate::dialect::Analysis, timed: bool) -> Vec<Decision> {
    let names = |services: &[ServiceId]| -> Vec<String> {
        services
            .iter()
            .map(|&s| c.services[s].name.name.clone())
            .collect()
    };
    if timed {
        let all: Vec<ServiceId> = c.services.ids().collect();
        let complete = analysis.stopped.is_none();
        return vec![Decision::new(
            names(&all),
            Decider::Zones,
            analysis.states,
            complete,
        )];
    }
    analysis
        .decided
        .iter()
        .map(|d| Decision::new(names(&d.services), d.method, d.states, d.complete))
        .collect()
}

/// The worst-case response times and the deadline verdicts, computed by
/// one more timed exploration per cluster (with what is left of the state
/// limit after `analysis`).
fn responses(
    c: &Component,
    options: &CheckOptions,
    started: Instant,
    analysis: &crate::dialect::Analysis,
) -> (Vec<ResponseTime>, Vec<Diagnostic>) {
    let mut limits = options.limits(started);
    limits.max_states = limits
        .max_states
        .saturating_sub(usize::try_from(analysis.states).unwrap_or(usize::MAX))
        .max(1);
    let deadlines = options.deadline_ids(c);
    let found = crate::timed::response_times(c, limits, &deadlines);
    let times = crate::checks::response_time::response_times(c, &found);
    let diagnostics = crate::checks::response_time::check(c, &found, &times, &deadlines);
    (times, diagnostics)
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
    let traces: Vec<_> = facts
        .codel_overruns
        .iter()
        .filter_map(|o| Some((c.codels[o.codel].wcet?.span, o.trace.clone())))
        .collect();
    crate::checks::codel_overrun::attach_traces(&traces, diagnostics);
}
