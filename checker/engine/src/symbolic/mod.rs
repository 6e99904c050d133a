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
//! The BDD library is `biodivine-lib-bdd`: pure Rust (no system library,
//! no `unsafe` in our code), maintained, with the operations needed here
//! (quantification, exact model counting, witnesses). Each BDD owns its
//! nodes, so the node counts reported are those of the reachable set.

mod image;
mod layout;
#[cfg(test)]
mod tests;
mod trace;
mod verdicts;

use std::time::{Duration, Instant};

use biodivine_lib_bdd::Bdd;

use crate::engine::explore::{Model, Stop};
use crate::engine::system::{Action, Config, System};

pub use layout::Refusal;
pub use verdicts::{SymbolicDeadlock, Verdicts};

/// Resource limits of a symbolic exploration.
#[derive(Debug, Clone, Copy)]
pub struct SymbolicLimits {
    /// Stop at this instant.
    pub deadline: Option<Instant>,
    /// Stop when the reachable set's BDD has more nodes than this.
    pub max_nodes: usize,
}

impl Default for SymbolicLimits {
    fn default() -> Self {
        SymbolicLimits {
            deadline: None,
            max_nodes: 50_000_000,
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

/// The reachable configurations, by distance from the initial one.
#[derive(Debug)]
pub struct Reach {
    /// `layers[d]`: the configurations first reached after `d` steps.
    layers: Vec<Bdd>,
    /// Every reached configuration.
    reached: Bdd,
    /// Why exploration stopped early, if it did.
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

    /// Breadth-first depth: the number of layers after the initial one.
    pub fn depth(&self) -> usize {
        self.layers.len().saturating_sub(1)
    }
}

impl<'s, 'a> Symbolic<'s, 'a> {
    /// Prepares `sys` (a whole cluster, after initialisation).
    pub fn new(sys: &'s System<'a>) -> Result<Self, Refusal> {
        let layout = layout::Layout::new(sys)?;
        let init = sys
            .init_states()
            .into_iter()
            .next()
            .ok_or(Refusal::PreInit)?;
        if !init.init_done || !sys.expand(&init) {
            return Err(Refusal::PreInit);
        }
        let steps = image::Steps::new(sys, &layout);
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

    /// The reachable configurations, breadth-first.
    pub fn reach(&self, limits: SymbolicLimits) -> Reach {
        let started = Instant::now();
        let first = self.layout.encode(&self.init);
        let mut reached = first.clone();
        let mut layers = vec![first.clone()];
        let mut frontier = first;
        let mut peak = reached.size();
        let mut stopped = None;
        loop {
            if genom_model::limits::out_of_time(limits.deadline) {
                stopped = Some(Stop::Time);
                break;
            }
            let next = self.steps.image(&self.layout, &frontier).and_not(&reached);
            if next.is_false() {
                break;
            }
            reached = reached.or(&next);
            peak = peak.max(reached.size()).max(next.size());
            layers.push(next.clone());
            frontier = next;
            if peak > limits.max_nodes {
                stopped = Some(Stop::Memory);
                break;
            }
        }
        Reach {
            layers,
            reached,
            stopped,
            elapsed: started.elapsed(),
            peak_nodes: peak,
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
