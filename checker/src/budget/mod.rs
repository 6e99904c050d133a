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

mod relaxation;
mod search;
mod verdict;
mod wcets;

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration as StdDuration, Instant};

use genom_model::Code;
use genom_model::component::{CodelId, Component};

use crate::kernel::explore::Limits;

pub use relaxation::Relaxation;
use relaxation::observe;
pub use search::Limit;
use search::{Done, SearchContext, Task};
pub use verdict::{Eval, Verdict, verdict};
pub use wcets::{SCALE_STEPS, grid_ns, scaled, with_wcets};

/// Default cap of a codel budget: one hour, in nanoseconds.
pub const DEFAULT_CAP_NS: u64 = 3_600_000_000_000;
/// Default cap of the scale factor, in steps (×1000).
pub const DEFAULT_SCALE_CAP: u64 = 1000 * SCALE_STEPS;

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

#[cfg(all(test, feature = "smt"))]
mod tests {
    use std::collections::BTreeSet;

    use genom_model::Severity;

    use super::search::Search;
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
