//! The search for a budget: the boundary of a monotone predicate ("clean at
//! this value"), from the SMT bound, over the grid, then galloping or
//! bisecting (see the module documentation of `budget`).

use std::collections::BTreeSet;

use genom_model::Code;
use genom_model::component::{CodelId, Component};

use crate::kernel::explore::Limits;

use super::verdict::{Eval, Verdict, verdict};
use super::wcets::{SCALE_STEPS, period_of, scaled, with_wcets};

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

#[derive(Debug, Clone, Copy)]
pub(super) enum Task {
    Codel(CodelId, Option<u64>),
    Scale(Option<u64>),
}

#[derive(Debug)]
pub(super) struct Done {
    pub(super) limit: Limit,
    pub(super) limited_by: Vec<Code>,
    pub(super) runs: usize,
}

pub(super) struct SearchContext<'a> {
    pub(super) c: &'a Component,
    pub(super) given: &'a [Option<u64>],
    pub(super) clean: bool,
    pub(super) limits: Limits,
    pub(super) cap_ns: u64,
    pub(super) scale_cap: u64,
    pub(super) grid: u64,
}

impl SearchContext<'_> {
    pub(super) fn run(&self, task: Task) -> Done {
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

/// A search for the boundary of a monotone predicate over `0..=cap`.
pub(super) struct Search<'e> {
    pub(super) eval: &'e dyn Fn(u64) -> Verdict,
    /// Largest value known clean.
    pub(super) lo: Option<u64>,
    /// Smallest value known violating, with its codes.
    pub(super) hi: Option<(u64, Vec<Code>)>,
    pub(super) probed: BTreeSet<u64>,
    pub(super) runs: usize,
}

impl<'e> Search<'e> {
    pub(super) fn new(eval: &'e dyn Fn(u64) -> Verdict) -> Self {
        Search {
            eval,
            lo: None,
            hi: None,
            probed: BTreeSet::new(),
            runs: 0,
        }
    }

    pub(super) fn hi_value(&self) -> Option<u64> {
        self.hi.as_ref().map(|h| h.0)
    }

    /// `v` is strictly between what is known.
    pub(super) fn open(&self, v: u64, cap: u64) -> bool {
        v <= cap && self.lo.is_none_or(|l| v > l) && self.hi_value().is_none_or(|h| v < h)
    }

    /// Checks `v`; `false` when the exploration was incomplete.
    pub(super) fn probe(&mut self, v: u64) -> bool {
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

    pub(super) fn incomplete(&self) -> Done {
        self.done(Limit::Incomplete { at_least: self.lo })
    }

    pub(super) fn done(&self, limit: Limit) -> Done {
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
    pub(super) fn run(
        &mut self,
        hint: Option<u64>,
        bound: Option<u64>,
        cap: u64,
        grid: u64,
    ) -> Done {
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
    pub(super) fn between(&self, l: u64, h: u64, grid: u64) -> u64 {
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
