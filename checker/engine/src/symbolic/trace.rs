//! Concrete traces from the breadth-first layers: a target configuration
//! at the first layer that meets the witness set, then, layer by layer
//! back to the initial configuration, a predecessor found by halving the
//! previous layer (keeping a half whose image holds the current
//! configuration) until it is small enough to try each configuration with
//! the explicit `System::apply`. The configurations are then joined by
//! explicit actions, so the path is one the explicit semantics takes.

use biodivine_lib_bdd::{Bdd, BddVariable};

use super::{Reach, Symbolic, action_between};
use crate::engine::system::{Action, Config};

/// Below this many configurations a layer is searched explicitly.
const EXPLICIT_BELOW: f64 = 64.0;

impl Symbolic<'_, '_> {
    /// A shortest path of explicit actions from the initial configuration
    /// to a reached configuration of `target`, and that configuration.
    /// `None` when no reached configuration is in `target`, or (a bug) the
    /// symbolic and explicit semantics disagree on a step.
    pub fn trace_to(&self, reach: &Reach, target: &Bdd) -> Option<(Vec<Action>, Config)> {
        let d = reach
            .layers
            .iter()
            .position(|layer| !layer.and(target).is_false())?;
        let last = self.layout.pick(&reach.layers[d].and(target))?;
        let mut configs = vec![last.clone()];
        for k in (0..d).rev() {
            let after = configs.last()?;
            let before = self.predecessor(&reach.layers[k], after)?;
            configs.push(before);
        }
        configs.reverse();
        let path = configs
            .windows(2)
            .map(|w| action_between(self.sys, &w[0], &w[1]))
            .collect::<Option<Vec<Action>>>()?;
        Some((path, last))
    }

    /// A configuration of `layer` with an explicit step to `after`.
    fn predecessor(&self, layer: &Bdd, after: &Config) -> Option<Config> {
        let target = self.layout.encode(after);
        let mut x = layer.clone();
        while x.cardinality() > EXPLICIT_BELOW {
            let v = split_variable(&x)?;
            let low = x.var_select(v, false);
            let high = x.var_select(v, true);
            let image = self.steps.image(&self.layout, &low);
            x = if image.and(&target).is_false() {
                high
            } else {
                low
            };
        }
        x.sat_valuations()
            .map(|v| self.layout.decode(&v))
            .find(|c| action_between(self.sys, c, after).is_some())
    }
}

/// A variable on which the set's configurations differ: the first node,
/// from the root, with two non-empty branches; else (the rest is free) the
/// first free variable.
fn split_variable(x: &Bdd) -> Option<BddVariable> {
    let mut node = x.root_pointer();
    while !node.is_terminal() {
        let (low, high) = (x.low_link_of(node), x.high_link_of(node));
        if !low.is_zero() && !high.is_zero() {
            return Some(x.var_of(node));
        }
        node = if low.is_zero() { high } else { low };
    }
    let n = usize::from(x.num_vars());
    (0..n)
        .map(BddVariable::from_index)
        .find(|&v| !x.var_select(v, false).is_false() && !x.var_select(v, true).is_false())
}
