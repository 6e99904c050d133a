//! WCET budgets (`genom-check budget`, cargo feature `smt`): for each codel,
//! the largest WCET that keeps the component free of errors with the other
//! WCETs as given, and the largest common scale factor of all WCETs.
//!
//! "Free of errors" is exactly what `genom-check check` decides: the static
//! checks (among them `codel-overrun`), then the timed engine's verdicts
//! (`thread-overrun`, `max-time-infeasible`, `max-time-exceeded`) and the
//! behavioural errors (`deadlock`, `starvation`, `dead-service`,
//! `unbounded-interrupt`, `incomplete`). Warnings and advice do not count.
//!
//! How a budget is found:
//!
//! 1. *Monotonicity.* A codel takes between 0 and its WCET, so a larger
//!    WCET only adds behaviours: a violation found at some WCET is still
//!    there above it. Every budget is the boundary of a monotone predicate,
//!    "clean at this value", and can be searched for.
//! 2. *A relaxation solved by z3.* From the component and one exploration of
//!    its timed model at the given WCETs, linear constraints over the WCET
//!    variables `w` that a clean component satisfies (necessary conditions,
//!    or close to it; see [`Relaxation`]): `w ≤ period` for every codel of a
//!    periodic thread; for every set of codels that some reachable state has
//!    to run in one period of a thread (its *period workload*), their sum ≤
//!    the period; for two codels of different threads (or a control codel)
//!    that conflict on a lock and can be pending together, the sum ≤ the
//!    period of the waiting thread (and the same for a lock holder that
//!    blocks two such codels); for a service with a `max-time` and no
//!    unbounded loop, the longest path from acknowledgment to its end ≤ the
//!    max-time. `z3::Optimize` maximizes each codel's WCET (the others
//!    fixed) and the scale factor under them: the *SMT bound*.
//! 3. *Verification by the zone engine, the ground truth.* The component is
//!    cloned with the candidate WCET and checked exactly as `check` does.
//!    The search starts at the SMT bound (clean there and a violation one
//!    unit above: done in two runs), and otherwise narrows the interval
//!    between the largest clean and the smallest violating value it knows:
//!    bisection over the component's *grid* (the GCD of its periods, WCETs
//!    and max-times, where boundaries usually lie), then one nanosecond
//!    above the clean end, then plain bisection; upward from a clean value
//!    with no violation known, it gallops (doubling steps).
//!
//! One time unit is **1 ns** (the language's resolution): a reported budget
//! `B` was checked clean at `B` ns, and a violation was found at `B + 1` ns
//! (its codes are reported as what *limits* the budget). A budget that
//! reaches the cap (default one hour) is reported unbounded: "no limit found
//! up to the cap" (the cap itself was checked clean).
//!
//! The scale factor `λ` is searched on a grid of 1/1000 ([`SCALE_STEPS`]):
//! at `λ = n/1000` every codel with a WCET `w` gets `⌊w·n/1000⌋` ns (codels
//! without a WCET keep none). The reported `λ` is clean and `λ + 1/1000` is
//! not; the cap is ×1000.
//!
//! Codels without a WCET get a budget too (the engine counts them as taking
//! no time): the largest WCET they could be given.

use std::collections::{BTreeMap, BTreeSet, HashSet};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration as StdDuration, Instant};

use genom_model::behaviour::Behaviour;
use genom_model::component::{CodelId, Component, Duration, Outcome, ServiceId, ThreadId};
use genom_model::kinds::CodelKind;
use genom_model::{Code, Severity};
use z3::ast::Int;
use z3::{Optimize, SatResult};

use crate::engine::explore::{Limits, explore};
use crate::timed::analyse_timed;
use crate::timed::clocks::gcd;
use crate::timed::model::TimedSystem;

/// Default cap of a codel budget: one hour, in nanoseconds.
pub const DEFAULT_CAP_NS: u64 = 3_600_000_000_000;
/// Steps of the scale factor per unit: `λ` is a multiple of 1/1000.
pub const SCALE_STEPS: u64 = 1000;
/// Default cap of the scale factor, in steps (×1000).
pub const DEFAULT_SCALE_CAP: u64 = 1000 * SCALE_STEPS;
/// At most this many period workloads and lock pairs are kept as
/// constraints (the relaxation only guides the search).
const MAX_CONSTRAINTS: usize = 20_000;

/// What to compute and with which resources.
#[derive(Debug, Clone)]
pub struct BudgetOptions {
    /// States per exploration (an exploration that stops is `incomplete`).
    pub max_states: usize,
    /// State storage per exploration, in bytes.
    pub max_memory: usize,
    /// No exploration goes on past this instant.
    pub deadline: Option<Instant>,
    /// Largest budget searched, in ns.
    pub cap_ns: u64,
    /// Largest scale factor searched, in 1/[`SCALE_STEPS`].
    pub scale_cap: u64,
    /// The codels whose budget to compute (`None`: all).
    pub codels: Option<Vec<CodelId>>,
    /// Compute the common scale factor.
    pub scale: bool,
    /// Searches run in parallel (at least 1).
    pub jobs: usize,
}

impl Default for BudgetOptions {
    fn default() -> Self {
        BudgetOptions {
            max_states: 10_000_000,
            max_memory: 8 << 30,
            deadline: None,
            cap_ns: DEFAULT_CAP_NS,
            scale_cap: DEFAULT_SCALE_CAP,
            codels: None,
            scale: true,
            jobs: std::thread::available_parallelism().map_or(1, usize::from),
        }
    }
}

impl BudgetOptions {
    fn limits(&self) -> Limits {
        Limits {
            max_states: self.max_states,
            deadline: self.deadline,
            max_bytes: self.max_memory,
        }
    }
}

/// The result of one search.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Limit {
    /// Clean at this value, a violation one unit above.
    Exact(u64),
    /// Clean at the cap: no limit found up to it.
    Unbounded,
    /// A violation even at 0 (the other WCETs, or something else, already
    /// break the component).
    NoCleanValue,
    /// An exploration stopped on a limit; the largest value known clean.
    Incomplete {
        /// Known clean, when some value was.
        at_least: Option<u64>,
    },
}

/// The budget of one codel.
#[derive(Debug, Clone)]
pub struct CodelBudget {
    /// The codel.
    pub codel: CodelId,
    /// Its WCET as given, in ns.
    pub given: Option<u64>,
    /// The z3 optimum of the relaxation (`None`: the relaxation is
    /// unsatisfiable with the other WCETs as given).
    pub smt: Option<u64>,
    /// The budget, in ns.
    pub limit: Limit,
    /// The error codes one unit above the budget (at 0 for
    /// [`Limit::NoCleanValue`]).
    pub limited_by: Vec<Code>,
    /// Explorations run for this search.
    pub runs: usize,
}

/// The common scale factor, in 1/[`SCALE_STEPS`].
#[derive(Debug, Clone)]
pub struct ScaleBudget {
    /// The z3 optimum of the relaxation.
    pub smt: Option<u64>,
    /// The factor, in steps.
    pub limit: Limit,
    /// The error codes one step above.
    pub limited_by: Vec<Code>,
    /// Explorations run for this search.
    pub runs: usize,
}

/// Everything `budget` computed.
#[derive(Debug, Clone)]
pub struct Budgets {
    /// The error codes of the component as given (empty: clean).
    pub as_given: Vec<Code>,
    /// One entry per requested codel, in codel order.
    pub codels: Vec<CodelBudget>,
    /// The scale factor, when asked for and some codel has a WCET.
    pub scale: Option<ScaleBudget>,
    /// Constraints of the relaxation.
    pub constraints: usize,
    /// The grid of the searches, in ns.
    pub grid_ns: u64,
    /// The cap of the codel budgets, in ns (an unbounded budget was checked
    /// clean there).
    pub cap_ns: u64,
    /// The cap of the scale factor, in 1/[`SCALE_STEPS`].
    pub scale_cap: u64,
    /// Explorations run in all (the baseline and the observation
    /// included).
    pub runs: usize,
    /// Wall-clock time.
    pub elapsed: StdDuration,
}

/// Why no budget could be computed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum BudgetError {
    /// The component as given could not be explored completely.
    Incomplete,
}

impl std::fmt::Display for BudgetError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BudgetError::Incomplete => f.write_str(
                "the exploration of the component as given stopped on a limit (raise --max-states, --max-memory or --timeout)",
            ),
        }
    }
}

impl std::error::Error for BudgetError {}

/// Computes the budgets of `c` (a component whose resolution has no
/// errors).
pub fn budgets(c: &Component, options: &BudgetOptions) -> Result<Budgets, BudgetError> {
    let started = Instant::now();
    let limits = options.limits();
    let given: Vec<Option<u64>> = c.codels.values().map(|k| k.wcet.map(|w| w.ns)).collect();
    let base = verdict(c, limits);
    let as_given = match &base.eval {
        Eval::Incomplete => return Err(BudgetError::Incomplete),
        Eval::Clean => Vec::new(),
        Eval::Violation(codes) => codes.clone(),
    };
    let clean = as_given.is_empty();
    let seen = observe(c, limits);
    let relaxation = Relaxation::build(c, &seen, &base.reached);
    let fixed: Vec<u64> = given.iter().map(|g| g.unwrap_or(0)).collect();
    let selected: Vec<CodelId> = options
        .codels
        .clone()
        .unwrap_or_else(|| c.codels.ids().collect());
    let smt: Vec<Option<u64>> = selected
        .iter()
        .map(|&k| relaxation.maximize_codel(k, &fixed, options.cap_ns))
        .collect();
    let has_wcet = given.iter().any(|g| g.is_some_and(|w| w > 0));
    let scale_smt = (options.scale && has_wcet)
        .then(|| relaxation.maximize_scale(&given, options.scale_cap))
        .flatten();
    let grid = grid_ns(c);
    let mut tasks: Vec<Task> = selected
        .iter()
        .zip(&smt)
        .map(|(&k, &s)| Task::Codel(k, s))
        .collect();
    if options.scale && has_wcet {
        tasks.insert(0, Task::Scale(scale_smt));
    }
    let results: Vec<Mutex<Option<Done>>> = tasks.iter().map(|_| Mutex::new(None)).collect();
    let next = AtomicUsize::new(0);
    let ctx = SearchContext {
        c,
        given: &given,
        clean,
        limits,
        cap_ns: options.cap_ns,
        scale_cap: options.scale_cap,
        grid,
    };
    std::thread::scope(|scope| {
        for _ in 0..options.jobs.clamp(1, tasks.len().max(1)) {
            scope.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&task) = tasks.get(i) else {
                        break;
                    };
                    let done = ctx.run(task);
                    if let Ok(mut slot) = results[i].lock() {
                        *slot = Some(done);
                    }
                }
            });
        }
    });
    let mut out = Budgets {
        as_given,
        codels: Vec::new(),
        scale: None,
        constraints: relaxation.constraints.len(),
        grid_ns: grid,
        cap_ns: options.cap_ns,
        scale_cap: options.scale_cap,
        runs: 1 + usize::from(seen.explored),
        elapsed: StdDuration::ZERO,
    };
    for (task, slot) in tasks.iter().zip(results) {
        let Some(done) = slot.into_inner().ok().flatten() else {
            continue;
        };
        out.runs += done.runs;
        match *task {
            Task::Codel(k, s) => out.codels.push(CodelBudget {
                codel: k,
                given: given[k.0 as usize],
                smt: s,
                limit: done.limit,
                limited_by: done.limited_by,
                runs: done.runs,
            }),
            Task::Scale(s) => {
                out.scale = Some(ScaleBudget {
                    smt: s,
                    limit: done.limit,
                    limited_by: done.limited_by,
                    runs: done.runs,
                });
            }
        }
    }
    out.elapsed = started.elapsed();
    Ok(out)
}

/// The grid of the searches: the GCD of every duration of the component.
pub fn grid_ns(c: &Component) -> u64 {
    let mut g = 0;
    for t in c.threads.values() {
        g = gcd(g, t.period.map_or(0, |p| p.ns));
    }
    for s in c.services.values() {
        g = gcd(g, s.max_time.map_or(0, |m| m.ns));
    }
    for k in c.codels.values() {
        g = gcd(g, k.wcet.map_or(0, |w| w.ns));
    }
    g.max(1)
}

/// `c` with the WCETs of `set` changed (`None`: no WCET).
pub fn with_wcets(c: &Component, set: &[(CodelId, Option<u64>)]) -> Component {
    let mut out = c.clone();
    for &(k, ns) in set {
        let codel = &mut out.codels[k];
        let span = codel.wcet.map_or(codel.name.span, |w| w.span);
        codel.wcet = ns.map(|ns| Duration { ns, span });
    }
    out
}

/// `c` with every WCET multiplied by `steps`/[`SCALE_STEPS`] and rounded
/// down to whole nanoseconds.
pub fn scaled(c: &Component, steps: u64) -> Component {
    let set: Vec<(CodelId, Option<u64>)> = c
        .codels
        .iter()
        .map(|(k, codel)| (k, codel.wcet.map(|w| scale_ns(w.ns, steps))))
        .collect();
    with_wcets(c, &set)
}

fn scale_ns(ns: u64, steps: u64) -> u64 {
    let v = u128::from(ns) * u128::from(steps) / u128::from(SCALE_STEPS);
    u64::try_from(v).unwrap_or(u64::MAX)
}

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
    let mut diagnostics = crate::checks::run(c);
    let mut explored = false;
    let mut reached = BTreeSet::new();
    if !diagnostics.iter().any(|d| d.severity == Severity::Error) {
        explored = true;
        let analysis = if c.gives_timing() {
            let (analysis, facts) = analyse_timed(c, limits);
            diagnostics.extend(crate::checks::timing(c, &facts));
            analysis
        } else {
            crate::engine::analyse(c, limits)
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

#[derive(Debug, Clone, Copy)]
enum Task {
    Codel(CodelId, Option<u64>),
    Scale(Option<u64>),
}

#[derive(Debug)]
struct Done {
    limit: Limit,
    limited_by: Vec<Code>,
    runs: usize,
}

struct SearchContext<'a> {
    c: &'a Component,
    given: &'a [Option<u64>],
    clean: bool,
    limits: Limits,
    cap_ns: u64,
    scale_cap: u64,
    grid: u64,
}

impl SearchContext<'_> {
    fn run(&self, task: Task) -> Done {
        match task {
            Task::Codel(k, hint) => {
                let eval = |v: u64| verdict(&with_wcets(self.c, &[(k, Some(v))]), self.limits);
                let mut s = Search::new(&eval);
                if self.clean {
                    s.lo = Some(self.given[k.0 as usize].unwrap_or(0));
                }
                let period = period_of(self.c, k);
                s.run(hint, period, self.cap_ns, self.grid)
            }
            Task::Scale(hint) => {
                let eval = |v: u64| verdict(&scaled(self.c, v), self.limits);
                let mut s = Search::new(&eval);
                if self.clean {
                    s.lo = Some(SCALE_STEPS);
                }
                // The smallest factor at which some codel exceeds its period
                // (a static `codel-overrun`, free to check).
                let overrun = self
                    .c
                    .codels
                    .ids()
                    .filter_map(|k| {
                        let (w, p) = (self.given[k.0 as usize]?, period_of(self.c, k)?);
                        let need = u128::from(p + 1) * u128::from(SCALE_STEPS);
                        let w = u128::from(w.max(1));
                        u64::try_from(need.div_ceil(w)).ok()
                    })
                    .min()
                    .map(|l| l.saturating_sub(1));
                s.run(hint, overrun, self.scale_cap, 1)
            }
        }
    }
}

/// The period of the thread that runs codel `k` (not for control codels).
fn period_of(c: &Component, k: CodelId) -> Option<u64> {
    let codel = &c.codels[k];
    if codel.kind == CodelKind::Control {
        return None;
    }
    let t = c.services[codel.service].thread?;
    c.threads[t.id].period.map(|p| p.ns)
}

/// A search for the boundary of a monotone predicate over `0..=cap`.
struct Search<'e> {
    eval: &'e dyn Fn(u64) -> Verdict,
    /// Largest value known clean.
    lo: Option<u64>,
    /// Smallest value known violating, with its codes.
    hi: Option<(u64, Vec<Code>)>,
    probed: BTreeSet<u64>,
    runs: usize,
}

impl<'e> Search<'e> {
    fn new(eval: &'e dyn Fn(u64) -> Verdict) -> Self {
        Search {
            eval,
            lo: None,
            hi: None,
            probed: BTreeSet::new(),
            runs: 0,
        }
    }

    fn hi_value(&self) -> Option<u64> {
        self.hi.as_ref().map(|h| h.0)
    }

    /// `v` is strictly between what is known.
    fn open(&self, v: u64, cap: u64) -> bool {
        v <= cap && self.lo.is_none_or(|l| v > l) && self.hi_value().is_none_or(|h| v < h)
    }

    /// Checks `v`; `false` when the exploration was incomplete.
    fn probe(&mut self, v: u64) -> bool {
        self.probed.insert(v);
        let verdict = (self.eval)(v);
        self.runs += usize::from(verdict.explored);
        match verdict.eval {
            Eval::Clean => {
                self.lo = Some(self.lo.map_or(v, |l| l.max(v)));
                true
            }
            Eval::Violation(codes) => {
                if self.hi_value().is_none_or(|h| v < h) {
                    self.hi = Some((v, codes));
                }
                true
            }
            Eval::Incomplete => false,
        }
    }

    fn incomplete(&self) -> Done {
        self.done(Limit::Incomplete { at_least: self.lo })
    }

    fn done(&self, limit: Limit) -> Done {
        let limited_by = match limit {
            Limit::Exact(_) | Limit::NoCleanValue => {
                self.hi.as_ref().map(|h| h.1.clone()).unwrap_or_default()
            }
            _ => Vec::new(),
        };
        Done {
            limit,
            limited_by,
            runs: self.runs,
        }
    }

    /// Searches from the hint; `bound` is a value known (statically) to be
    /// the last before a violation is certain (the period for a codel of a
    /// periodic thread): `bound + 1` is checked first, for free.
    fn run(&mut self, hint: Option<u64>, bound: Option<u64>, cap: u64, grid: u64) -> Done {
        let grid = grid.max(1);
        if let Some(b) = bound
            .and_then(|b| b.checked_add(1))
            .filter(|&b| self.open(b, cap))
            && !self.probe(b)
        {
            return self.incomplete();
        }
        if let Some(u) = hint.map(|u| u.min(cap)) {
            if self.open(u, cap) && !self.probe(u) {
                return self.incomplete();
            }
            if self.lo == Some(u) && u < cap && self.open(u + 1, cap) && !self.probe(u + 1) {
                return self.incomplete();
            }
        }
        let mut step = grid;
        loop {
            let next = match (self.lo, self.hi_value()) {
                (Some(l), Some(h)) if h <= l + 1 => return self.done(Limit::Exact(l)),
                (Some(l), None) if l >= cap => return self.done(Limit::Unbounded),
                (None, Some(0)) => return self.done(Limit::NoCleanValue),
                (None, _) => 0,
                (Some(l), None) => {
                    let v = l.saturating_add(step).min(cap);
                    step = step.saturating_mul(2);
                    v
                }
                (Some(l), Some(h)) => self.between(l, h, grid),
            };
            if !self.probe(next) {
                return self.incomplete();
            }
        }
    }

    /// The next value to check strictly between `l` (clean) and `h`
    /// (violating), `h > l + 1`: the middle grid point; with none left, the
    /// value just above `l` (boundaries usually lie on the grid), then the
    /// middle.
    fn between(&self, l: u64, h: u64, grid: u64) -> u64 {
        let (a, b) = (l / grid + 1, (h - 1) / grid);
        if a <= b {
            return (a + (b - a) / 2) * grid;
        }
        if h % grid == 0 && !self.probed.contains(&(h - 1)) {
            return h - 1;
        }
        if l % grid == 0 && !self.probed.contains(&(l + 1)) {
            return l + 1;
        }
        l + (h - l) / 2
    }
}

/// What one exploration of the timed model at the given WCETs showed.
#[derive(Debug, Default)]
struct Observed {
    /// Per periodic thread: sets of codels some reachable state still has
    /// to run in the current period (two or more).
    workloads: BTreeSet<(ThreadId, Vec<CodelId>)>,
    /// Pairs of codels (control codels included) that are ready or running
    /// together in some reachable state.
    together: HashSet<(CodelId, CodelId)>,
    /// Whether the exploration ran.
    explored: bool,
}

/// Explores the timed model of every cluster (as the timed engine does) to
/// collect period workloads and the codels that can be pending together.
fn observe(c: &Component, limits: Limits) -> Observed {
    let mut seen = Observed::default();
    if !c.threads.values().any(|t| t.period.is_some()) {
        return seen;
    }
    seen.explored = true;
    let b = Behaviour::new(c);
    for (members, frozen) in crate::timed::timed_explorations(c) {
        let ts = TimedSystem::new(c, &b, &members, frozen);
        let mut codels: Vec<CodelId> = Vec::new();
        let _ = explore(&ts, limits, |_, st| {
            for (k, t) in ts.threads.iter().enumerate() {
                if t.period.is_none() || seen.workloads.len() >= MAX_CONSTRAINTS {
                    continue;
                }
                let mut set: Vec<CodelId> = t
                    .members
                    .iter()
                    .enumerate()
                    .filter(|&(slot, _)| st.eligible[k] & (1u64 << slot) != 0)
                    .filter_map(|(_, &i)| ts.sys.position(&st.cfg, i).codel())
                    .collect();
                if set.len() >= 2 {
                    set.sort();
                    seen.workloads.insert((t.id, set));
                }
            }
            codels.clear();
            codels.extend((0..ts.sys.len()).filter_map(|i| ts.sys.position(&st.cfg, i).codel()));
            if let Some(r) = st.ctl {
                codels.extend(c.services[ts.sys.service(usize::from(r))].control);
            }
            if seen.together.len() < MAX_CONSTRAINTS * 10 {
                for (n, &x) in codels.iter().enumerate().take(64) {
                    for &y in &codels[n + 1..] {
                        seen.together.insert((x.min(y), x.max(y)));
                    }
                }
            }
        });
    }
    seen
}

/// A variable of the relaxation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Var {
    /// The WCET of a codel, in ns.
    Wcet(CodelId),
    /// An auxiliary variable (longest remaining time of a max-time path).
    Aux(usize),
}

/// `Σ coefficient · variable ≤ bound`.
#[derive(Debug, Clone)]
struct Linear {
    terms: Vec<(i64, Var)>,
    bound: i64,
}

/// The linear relaxation of "clean" over the WCET variables (see the module
/// documentation). Its constraints are necessary conditions whenever the
/// situations they describe are reachable: the workloads are; lock pairs are
/// pending together in some reachable state but need not be able to start
/// at the same instant. The engine decides in the end, so a constraint that
/// is too strict only costs searching.
#[derive(Debug, Default)]
pub struct Relaxation {
    constraints: Vec<Linear>,
    aux: usize,
}

fn ns_i64(ns: u64) -> i64 {
    i64::try_from(ns).unwrap_or(i64::MAX / 4)
}

/// Where a codel runs: a thread, or the control thread (`None`).
fn runner(c: &Component, k: CodelId) -> Option<Option<ThreadId>> {
    let codel = &c.codels[k];
    if codel.kind == CodelKind::Control {
        return Some(None);
    }
    c.services[codel.service].thread.map(|t| Some(t.id))
}

impl Relaxation {
    fn build(c: &Component, seen: &Observed, reached: &BTreeSet<CodelId>) -> Relaxation {
        let mut r = Relaxation::default();
        for k in c.codels.ids() {
            if let Some(p) = period_of(c, k) {
                r.push(vec![(1, Var::Wcet(k))], ns_i64(p));
            }
        }
        for (t, set) in &seen.workloads {
            let Some(p) = c.threads[*t].period else {
                continue;
            };
            r.push(
                set.iter().map(|&k| (1, Var::Wcet(k))).collect(),
                ns_i64(p.ns),
            );
        }
        r.locks(c, seen);
        r.paths(c, reached);
        r
    }

    fn push(&mut self, terms: Vec<(i64, Var)>, bound: i64) {
        if self.constraints.len() < MAX_CONSTRAINTS * 4 {
            self.constraints.push(Linear { terms, bound });
        }
    }

    /// Lock waits: a codel `d` of a periodic thread that conflicts with a
    /// codel `x` of another thread (or a control codel) pending with it may
    /// have to wait for all of `x` in its period; a holder `h` conflicting
    /// with both may make it wait for `h` and then `x`.
    fn locks(&mut self, c: &Component, seen: &Observed) {
        let together = |a: CodelId, b: CodelId| seen.together.contains(&(a.min(b), a.max(b)));
        let ids: Vec<CodelId> = c.codels.ids().collect();
        let mut pairs: Vec<(CodelId, CodelId)> = Vec::new();
        for &d in &ids {
            let Some(p) = period_of(c, d) else {
                continue;
            };
            for &x in &ids {
                if x == d || runner(c, x) == runner(c, d) || !together(x, d) {
                    continue;
                }
                if c.conflicts(x, d) {
                    pairs.push((x, d));
                    self.push(vec![(1, Var::Wcet(x)), (1, Var::Wcet(d))], ns_i64(p));
                }
            }
        }
        if pairs.len() > 2_000 {
            return;
        }
        for &(x, d) in &pairs {
            let Some(p) = period_of(c, d) else {
                continue;
            };
            for &h in &ids {
                let distinct = runner(c, h) != runner(c, x) && runner(c, h) != runner(c, d);
                if h == x || h == d || !distinct || !together(h, x) || !together(h, d) {
                    continue;
                }
                if c.conflicts(h, x) && c.conflicts(h, d) {
                    self.push(
                        vec![(1, Var::Wcet(h)), (1, Var::Wcet(x)), (1, Var::Wcet(d))],
                        ns_i64(p),
                    );
                }
            }
        }
    }

    /// Max-time paths of the services with a `max-time` and no unbounded
    /// loop, over their reached codels: with `d_k` the longest time from
    /// the wake-up that runs codel `k` to the end of the instance,
    /// `d_k ≥ w_k` when `k` can end it, `d_k ≥ P + d_n` for a next codel
    /// `n` on a periodic thread (`w_k + d_n` on an aperiodic one), and
    /// `P + d_start ≤ max-time` (`d_start` alone on an aperiodic thread):
    /// acknowledged just at a wake-up, a service may wait a whole period.
    fn paths(&mut self, c: &Component, reached: &BTreeSet<CodelId>) {
        let b = Behaviour::new(c);
        let stopped: BTreeSet<ServiceId> = c
            .services
            .values()
            .flat_map(|s| s.stops.iter().map(|r| r.id))
            .collect();
        for (s, svc) in c.services.iter() {
            let (Some(m), Some(start), Some(t)) = (svc.max_time, svc.start, svc.thread) else {
                continue;
            };
            if b.machine(s).active_loop || !reached.contains(&start) {
                continue;
            }
            let period = c.threads[t.id].period.map(|p| ns_i64(p.ns));
            let interruptible = stopped.contains(&s);
            let graph = path_graph(c, start, interruptible, reached);
            if has_cycle(&graph) {
                continue;
            }
            let base = self.aux;
            self.aux += graph.len();
            let var = |k: CodelId| {
                graph
                    .keys()
                    .position(|&x| x == k)
                    .map(|i| Var::Aux(base + i))
            };
            for (&k, (succ, terminal)) in &graph {
                let Some(dk) = var(k) else {
                    continue;
                };
                if *terminal {
                    self.push(vec![(1, Var::Wcet(k)), (-1, dk)], 0);
                }
                for &n in succ {
                    let Some(dn) = var(n) else {
                        continue;
                    };
                    match period {
                        Some(p) => self.push(vec![(1, dn), (-1, dk)], -p),
                        None => self.push(vec![(1, Var::Wcet(k)), (1, dn), (-1, dk)], 0),
                    }
                }
            }
            if let Some(ds) = var(start) {
                let slack = ns_i64(m.ns) - period.unwrap_or(0);
                self.push(vec![(1, ds)], slack);
            }
        }
    }

    fn solve(&self, o: &Optimize, w: &[Int]) {
        let aux: Vec<Int> = (0..self.aux)
            .map(|i| Int::new_const(format!("d{i}")))
            .collect();
        let zero = Int::from_i64(0);
        for x in w {
            o.assert(x.ge(&zero));
        }
        for l in &self.constraints {
            let terms: Vec<Int> = l
                .terms
                .iter()
                .map(|&(a, v)| {
                    let x = match v {
                        Var::Wcet(k) => w[k.0 as usize].clone(),
                        Var::Aux(i) => aux[i].clone(),
                    };
                    if a == 1 {
                        x
                    } else {
                        Int::mul(&[Int::from_i64(a), x])
                    }
                })
                .collect();
            o.assert(Int::add(&terms).le(Int::from_i64(l.bound)));
        }
    }

    /// The z3 maximum of codel `k`'s WCET with the others at `fixed`
    /// (`None` when unsatisfiable or unknown).
    pub fn maximize_codel(&self, k: CodelId, fixed: &[u64], cap: u64) -> Option<u64> {
        let o = Optimize::new();
        let w: Vec<Int> = (0..fixed.len())
            .map(|i| Int::new_const(format!("w{i}")))
            .collect();
        self.solve(&o, &w);
        for (i, x) in w.iter().enumerate() {
            if i != k.0 as usize {
                o.assert(x.eq(Int::from_u64(fixed[i])));
            }
        }
        let target = w.get(k.0 as usize)?;
        o.assert(target.le(Int::from_u64(cap)));
        o.maximize(target);
        optimum(&o, target)
    }

    /// The z3 maximum of the scale factor (in steps) with every WCET `g`
    /// scaled to `⌊g·λ⌋` (codels without a WCET stay at 0).
    pub fn maximize_scale(&self, given: &[Option<u64>], cap: u64) -> Option<u64> {
        let o = Optimize::new();
        let w: Vec<Int> = (0..given.len())
            .map(|i| Int::new_const(format!("w{i}")))
            .collect();
        self.solve(&o, &w);
        let lambda = Int::new_const("lambda");
        let steps = Int::from_u64(SCALE_STEPS);
        o.assert(lambda.ge(Int::from_i64(0)));
        o.assert(lambda.le(Int::from_u64(cap)));
        for (x, g) in w.iter().zip(given) {
            match g {
                Some(g) if *g > 0 => {
                    // SCALE_STEPS·w ≤ g·λ < SCALE_STEPS·(w + 1)
                    let gl = Int::mul(&[Int::from_u64(*g), lambda.clone()]);
                    let sw = Int::mul(&[steps.clone(), x.clone()]);
                    o.assert(sw.le(&gl));
                    o.assert(gl.lt(Int::add(&[sw, steps.clone()])));
                }
                _ => o.assert(x.eq(Int::from_i64(0))),
            }
        }
        o.maximize(&lambda);
        optimum(&o, &lambda)
    }
}

fn optimum(o: &Optimize, x: &Int) -> Option<u64> {
    if o.check(&[]) != SatResult::Sat {
        return None;
    }
    let model = o.get_model()?;
    let v = model.eval(x, true)?.as_i64()?;
    u64::try_from(v).ok()
}

/// The codels of a max-time path graph from `start`: successors (next
/// codels, and the `on-inter` codel when the service can be interrupted)
/// and whether the codel can end the instance. Only reached codels.
fn path_graph(
    c: &Component,
    start: CodelId,
    interruptible: bool,
    reached: &BTreeSet<CodelId>,
) -> BTreeMap<CodelId, (Vec<CodelId>, bool)> {
    let mut graph = BTreeMap::new();
    let mut stack = vec![start];
    while let Some(k) = stack.pop() {
        if graph.contains_key(&k) {
            continue;
        }
        let codel = &c.codels[k];
        let mut succ = Vec::new();
        let mut terminal = false;
        for o in codel.outcomes() {
            match o {
                Outcome::Codel(n) if reached.contains(&n) => succ.push(n),
                Outcome::Codel(_) => {}
                Outcome::End | Outcome::Report(_) => terminal = true,
            }
        }
        if interruptible && codel.kind != CodelKind::Inter {
            match codel.on_inter {
                Some(i) if reached.contains(&i.id) => succ.push(i.id),
                Some(_) => {}
                None => terminal = true,
            }
        }
        succ.sort();
        succ.dedup();
        stack.extend(succ.iter().copied());
        graph.insert(k, (succ, terminal));
    }
    graph
}

fn has_cycle(graph: &BTreeMap<CodelId, (Vec<CodelId>, bool)>) -> bool {
    // 0: unvisited, 1: on the stack, 2: done.
    let mut state: BTreeMap<CodelId, u8> = BTreeMap::new();
    for &root in graph.keys() {
        if state.contains_key(&root) {
            continue;
        }
        let mut stack = vec![(root, 0usize)];
        state.insert(root, 1);
        while let Some(&mut (k, ref mut i)) = stack.last_mut() {
            let succ = graph.get(&k).map_or(&[][..], |g| &g.0[..]);
            if let Some(&n) = succ.get(*i) {
                *i += 1;
                match state.get(&n) {
                    Some(1) => return true,
                    Some(_) => {}
                    None => {
                        state.insert(n, 1);
                        stack.push((n, 0));
                    }
                }
            } else {
                state.insert(k, 2);
                stack.pop();
            }
        }
    }
    false
}

#[cfg(all(test, feature = "smt"))]
mod tests {
    use super::*;
    use crate::testing::check;

    /// The component of `src`, whose only errors are timing ones.
    fn component(src: &str) -> Component {
        let r = check(src);
        let timing = [
            Code::ThreadOverrun,
            Code::CodelOverrun,
            Code::MaxTimeExceeded,
            Code::MaxTimeInfeasible,
        ];
        let errors: Vec<_> = r
            .diagnostics
            .iter()
            .filter(|d| d.severity == Severity::Error && !timing.contains(&d.code))
            .map(|d| d.code)
            .collect();
        assert!(errors.is_empty(), "{errors:?}");
        r.component.unwrap_or_default()
    }

    fn codel(c: &Component, name: &str) -> CodelId {
        let (s, k) = name.split_once("::").unwrap_or((name, "start"));
        c.service_named(s)
            .and_then(|s| c.codel_named(s, k))
            .unwrap_or(CodelId(u32::MAX))
    }

    fn options(codels: Vec<CodelId>, scale: bool) -> BudgetOptions {
        BudgetOptions {
            codels: Some(codels),
            scale,
            cap_ns: 10_000_000_000,
            ..BudgetOptions::default()
        }
    }

    fn eval_at(c: &Component, k: CodelId, ns: u64) -> Eval {
        verdict(&with_wcets(c, &[(k, Some(ns))]), Limits::default()).eval
    }

    /// Budget `ns` of `name`: clean at it, a violation 1 ns above.
    fn assert_budget(c: &Component, b: &Budgets, name: &str, ns: u64) {
        let k = codel(c, name);
        let got = b.codels.iter().find(|x| x.codel == k).map(|x| x.limit);
        assert_eq!(got, Some(Limit::Exact(ns)), "{name}: {b:?}");
        assert_eq!(eval_at(c, k, ns), Eval::Clean, "{name} at {ns}");
        assert!(
            matches!(eval_at(c, k, ns + 1), Eval::Violation(_)),
            "{name} at {ns} + 1"
        );
    }

    const SHARED: &str = r#"
component c { category: default; lang: C; }
thread t { period: 10ms; }
auto service A { thread: t; start codel { exec: fa(); max-time: 3ms; next: start; } }
auto service B { thread: t; start codel { exec: fb(); max-time: 2ms; next: start; } }
"#;

    #[test]
    fn two_services_in_one_period_share_it() {
        let c = component(SHARED);
        let (a, b) = (codel(&c, "A"), codel(&c, "B"));
        let out = budgets(&c, &options(vec![a, b], true)).unwrap_or_else(|e| panic!("{e}"));
        assert!(out.as_given.is_empty());
        assert_budget(&c, &out, "B", 7_000_000);
        assert_budget(&c, &out, "A", 8_000_000);
        let bx = out.codels.iter().find(|x| x.codel == b).map(|x| x.smt);
        assert_eq!(bx, Some(Some(7_000_000)), "the relaxation is exact here");
        assert!(
            out.codels
                .iter()
                .all(|x| x.limited_by == [Code::ThreadOverrun])
        );
        // 3 ms + 2 ms scale to the 10 ms period: λ = 2.000.
        let scale = out.scale.unwrap_or_else(|| panic!("no scale"));
        assert_eq!(scale.limit, Limit::Exact(2 * SCALE_STEPS));
        let at = |steps| verdict(&scaled(&c, steps), Limits::default()).eval;
        assert_eq!(at(2000), Eval::Clean);
        assert!(matches!(at(2001), Eval::Violation(_)));
    }

    #[test]
    fn a_codel_alone_gets_the_period() {
        let src = r#"
component c { category: default; lang: C; }
thread t { period: 10ms; }
auto service A { thread: t; start codel { exec: fa(); max-time: 3ms; next: start; } }
"#;
        let c = component(src);
        let a = codel(&c, "A");
        let out = budgets(&c, &options(vec![a], true)).unwrap_or_else(|e| panic!("{e}"));
        assert_budget(&c, &out, "A", 10_000_000);
        assert_eq!(out.codels[0].limited_by, [Code::CodelOverrun]);
        // 3 ms × 3.333 = 9.999 ms; × 3.334 = 10.002 ms.
        assert_eq!(out.scale.map(|s| s.limit), Some(Limit::Exact(3333)));
    }

    #[test]
    fn max_time_paths_bound_the_last_codel() {
        // Acknowledged at a wake-up, `start` runs one period later, `b` one
        // period after that: 10 + 10 + w(b) ≤ 25 ms.
        let src = r#"
component c { category: default; lang: C; }
thread t { period: 10ms; }
service S {
  thread: t; max-time: 25ms;
  start codel { exec: fa(); max-time: 1ms; next: b; }
  exec codel b { exec: fb(); max-time: 2ms; next: end; }
}
"#;
        let c = component(src);
        let b = codel(&c, "S::b");
        let out = budgets(&c, &options(vec![b], false)).unwrap_or_else(|e| panic!("{e}"));
        assert_budget(&c, &out, "S::b", 5_000_000);
        assert_eq!(out.codels[0].smt, Some(5_000_000));
        assert_eq!(out.codels[0].limited_by, [Code::MaxTimeExceeded]);
    }

    #[test]
    fn a_codel_that_influences_nothing_is_unbounded() {
        // An aperiodic thread, no max-time, no lock shared with anything.
        let src = r#"
component c { category: default; lang: C; }
thread t { priority: 0; }
service S { thread: t; start codel { exec: fa(); max-time: 1ms; next: end; } }
"#;
        let c = component(src);
        let s = codel(&c, "S");
        let out = budgets(&c, &options(vec![s], true)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(out.codels[0].limit, Limit::Unbounded);
        assert_eq!(out.scale.map(|s| s.limit), Some(Limit::Unbounded));
    }

    #[test]
    fn a_control_codel_holding_a_lock_delays_a_thread() {
        // `set` writes `d` while `S::start` reads it every 10 ms period.
        let src = r#"
component c { category: default; lang: C; }
ids d { double x; }
thread t { period: 10ms; }
auto service S { thread: t; start codel { exec: fa(const d.x); max-time: 4ms; next: start; } }
service Set { input: d.x; control codel { exec: fs(d.x); max-time: 1ms; } }
"#;
        let c = component(src);
        let (s, set) = (codel(&c, "S"), codel(&c, "Set::control"));
        let out = budgets(&c, &options(vec![s, set], false)).unwrap_or_else(|e| panic!("{e}"));
        assert_budget(&c, &out, "S", 9_000_000);
        assert_budget(&c, &out, "Set::control", 6_000_000);
    }

    #[test]
    fn a_component_that_is_not_clean_is_reported() {
        let src = r#"
component c { category: default; lang: C; }
thread t { period: 10ms; }
auto service A { thread: t; start codel { exec: fa(); max-time: 6ms; next: start; } }
auto service B { thread: t; start codel { exec: fb(); max-time: 6ms; next: start; } }
"#;
        let c = component(src);
        let (a, b) = (codel(&c, "A"), codel(&c, "B"));
        let out = budgets(&c, &options(vec![a, b], true)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(out.as_given, [Code::ThreadOverrun]);
        assert_budget(&c, &out, "A", 4_000_000);
        // 12 ms of codels in 10 ms: λ = 0.833 (2 × 4.998 ms).
        assert_eq!(out.scale.map(|s| s.limit), Some(Limit::Exact(833)));
    }

    #[test]
    fn the_search_finds_boundaries_off_the_grid() {
        let eval = |v: u64| Verdict {
            eval: if v <= 12_345 {
                Eval::Clean
            } else {
                Eval::Violation(vec![Code::ThreadOverrun])
            },
            explored: true,
            reached: BTreeSet::new(),
        };
        for hint in [None, Some(0), Some(12_345), Some(20_000), Some(1_000_000)] {
            let mut s = Search::new(&eval);
            s.lo = Some(1_000);
            let done = s.run(hint, None, 1 << 40, 1_000);
            assert_eq!(done.limit, Limit::Exact(12_345), "{hint:?}");
        }
        let mut s = Search::new(&eval);
        let done = s.run(Some(12_345), None, 1 << 40, 1_000);
        assert_eq!((done.limit, done.runs), (Limit::Exact(12_345), 2));
    }
}
