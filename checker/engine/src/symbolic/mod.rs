//! Symbolic (BDD) reachability of one cluster's untimed [`System`]: the
//! configurations are sets of valuations of a few bits per member
//! ([`layout`]), the transitions guarded set transformers written from the
//! rules of `system::steps` ([`image`]), and the reachable set is computed
//! breadth-first, one layer per distance from the initial configuration,
//! so that every witness has a shortest trace.
//!
//! The reachability verdicts (deadlocks, starvations, unbounded interrupts,
//! services started or pending, codels reached) are read off the reachable
//! set ([`verdicts`]); each witness configuration is walked back layer by
//! layer to a concrete path of explicit [`Action`]s that `System::apply`
//! replays, so every trace is checked by the explicit semantics. Cycle
//! properties beyond these state predicates are not computed here.
//!
//! Measured (example `symbolic_figures`), this engine is exact but slower
//! than the explicit explorer on the issue-14 components: `--engine auto`
//! (the default) calls it only for a cluster the explicit explorer could
//! not finish within its state or memory limit, `--engine symbolic` for
//! every cluster ([`analyse_cluster`], `engine::method`).
//!
//! The BDD library is `biodivine-lib-bdd`: pure Rust (no system library,
//! no `unsafe` in our code), maintained, with the operations needed here
//! (quantification, exact model counting, witnesses). Each BDD owns its
//! nodes, so the node counts reported are those of the reachable set.

mod analysis;
mod image;
mod layout;
#[cfg(test)]
mod tests;
mod trace;
mod verdicts;

use std::time::{Duration, Instant};

use biodivine_lib_bdd::Bdd;

use crate::dialect::system::{Action, Config, System};
use crate::kernel::explore::{Model, Stop};

pub(crate) use analysis::analyse_cluster;
pub use layout::Refusal;
pub use verdicts::{SymbolicDeadlock, Verdicts};

/// How the reachable set is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strategy {
    /// Breadth-first: one image of the whole frontier per layer; traces
    /// are shortest.
    Breadth,
    /// Chained: each step in turn is applied to everything reached so far
    /// (fewer, cheaper iterations); traces are valid but not shortest.
    Chained,
}

/// Resource limits and strategy of a symbolic exploration.
#[derive(Debug, Clone, Copy)]
pub struct SymbolicLimits {
    /// How to compute the reachable set.
    pub strategy: Strategy,
    /// Stop at this instant.
    pub deadline: Option<Instant>,
    /// Stop when the reachable set's BDD has more nodes than this.
    pub max_nodes: usize,
    /// `--max-memory`: stop when the process's heap reaches its soft bound
    /// ([`genom_model::limits::soft_bound`]).
    pub max_bytes: usize,
}

impl Default for SymbolicLimits {
    fn default() -> Self {
        SymbolicLimits {
            strategy: Strategy::Breadth,
            deadline: None,
            max_nodes: 50_000_000,
            max_bytes: 8 << 30,
        }
    }
}

/// A system prepared for symbolic exploration.
#[derive(Debug)]
pub struct Symbolic<'s, 'a> {
    sys: &'s System<'a>,
    layout: layout::Layout,
    steps: image::Steps,
    init: Config,
}

/// Configurations first reached together: by one step from the earlier
/// layers (by `step`, or by any step from the previous layer when `None`).
#[derive(Debug)]
struct Layer {
    set: Bdd,
    step: Option<usize>,
}

/// The reachable configurations, in the layers they were found in.
#[derive(Debug)]
pub struct Reach {
    layers: Vec<Layer>,
    /// Every reached configuration.
    reached: Bdd,
    /// Why exploration stopped early, if it did: then the set is only
    /// part of the reachable one, and a verdict it does not show is
    /// unproven.
    pub stopped: Option<Stop>,
    /// Time spent.
    pub elapsed: Duration,
    /// Largest BDD node count met (reachable set or frontier).
    pub peak_nodes: usize,
}

impl Reach {
    /// Number of reached configurations (exact; saturates at `u128::MAX`).
    pub fn states(&self) -> u128 {
        self.reached
            .exact_cardinality()
            .to_string()
            .parse()
            .unwrap_or(u128::MAX)
    }

    /// Nodes of the reachable set's BDD.
    pub fn nodes(&self) -> usize {
        self.reached.size()
    }

    /// The number of layers after the initial one (breadth-first: the
    /// depth).
    pub fn depth(&self) -> usize {
        self.layers.len().saturating_sub(1)
    }
}

impl<'s, 'a> Symbolic<'s, 'a> {
    /// Prepares `sys` (a whole cluster, after initialisation).
    pub fn new(sys: &'s System<'a>) -> Result<Self, Refusal> {
        Self::new_until(sys, None)
    }

    /// [`Self::new`], refused with [`Refusal::OutOfTime`] once `deadline`
    /// has passed.
    pub fn new_until(sys: &'s System<'a>, deadline: Option<Instant>) -> Result<Self, Refusal> {
        let layout = layout::Layout::new(sys)?;
        let init = sys
            .init_states()
            .into_iter()
            .next()
            .ok_or(Refusal::PreInit)?;
        if !init.init_done || !sys.expand(&init) {
            return Err(Refusal::PreInit);
        }
        let steps = image::Steps::new(sys, &layout, deadline).ok_or(Refusal::OutOfTime)?;
        Ok(Symbolic {
            sys,
            layout,
            steps,
            init,
        })
    }

    /// Number of BDD variables.
    pub fn variables(&self) -> usize {
        self.layout.num_vars()
    }

    /// Number of guarded steps (the partitioned transition relation).
    pub fn steps(&self) -> usize {
        self.steps.list.len()
    }

    /// The reachable configurations.
    pub fn reach(&self, limits: SymbolicLimits) -> Reach {
        let started = Instant::now();
        let first = self.layout.encode(&self.init);
        let mut r = Reach {
            layers: vec![Layer {
                set: first.clone(),
                step: None,
            }],
            peak_nodes: first.size(),
            reached: first,
            stopped: None,
            elapsed: Duration::ZERO,
        };
        r.stopped = match limits.strategy {
            Strategy::Breadth => self.breadth(&mut r, limits),
            Strategy::Chained => self.chained(&mut r, limits),
        };
        r.elapsed = started.elapsed();
        r
    }

    /// Adds `new` (disjoint from what is reached) as a layer; `Some` when a
    /// limit is reached.
    fn grow(r: &mut Reach, new: Bdd, step: Option<usize>, limits: SymbolicLimits) -> Option<Stop> {
        r.reached = r.reached.or(&new);
        r.peak_nodes = r.peak_nodes.max(r.reached.size()).max(new.size());
        r.layers.push(Layer { set: new, step });
        let heap = genom_model::limits::heap::in_use();
        if r.peak_nodes > limits.max_nodes
            || heap >= genom_model::limits::soft_bound(limits.max_bytes)
        {
            return Some(Stop::Memory);
        }
        genom_model::limits::out_of_time(limits.deadline).then_some(Stop::Time)
    }

    fn breadth(&self, r: &mut Reach, limits: SymbolicLimits) -> Option<Stop> {
        loop {
            let frontier = &r.layers.last()?.set;
            let Some(image) = self
                .steps
                .image_until(&self.layout, frontier, limits.deadline)
            else {
                return Some(Stop::Time);
            };
            let next = image.and_not(&r.reached);
            if next.is_false() {
                return None;
            }
            if let Some(stop) = Self::grow(r, next, None, limits) {
                return Some(stop);
            }
        }
    }

    fn chained(&self, r: &mut Reach, limits: SymbolicLimits) -> Option<Stop> {
        loop {
            let mut grew = false;
            for k in (0..self.steps.list.len()).rev() {
                if genom_model::limits::out_of_time(limits.deadline) {
                    return Some(Stop::Time);
                }
                let Some(image) =
                    self.steps
                        .step_image_until(&self.layout, &r.reached, k, limits.deadline)
                else {
                    return Some(Stop::Time);
                };
                let next = image.and_not(&r.reached);
                if next.is_false() {
                    continue;
                }
                grew = true;
                if let Some(stop) = Self::grow(r, next, Some(k), limits) {
                    return Some(stop);
                }
            }
            if !grew {
                return None;
            }
        }
    }

    /// The system.
    pub fn system(&self) -> &'s System<'a> {
        self.sys
    }
}

/// The explicit actions from `from` to `to`: the first enabled action
/// whose successor is `to`.
fn action_between(sys: &System<'_>, from: &Config, to: &Config) -> Option<Action> {
    let mut actions = Vec::new();
    sys.actions(from, &mut actions);
    actions
        .into_iter()
        .find(|&a| sys.apply(from, a, &mut None).as_ref() == Some(to))
}
