//! Concrete traces from the layers of the reachable set: a target
//! configuration in the first layer that meets the witness set, then, back
//! to the initial configuration, a predecessor found by halving the
//! earlier layers (the previous one, breadth-first; all earlier ones,
//! chained) and keeping a half whose image holds the current configuration,
//! until it is small enough to try each configuration with the explicit
//! `System::apply`. The configurations are then joined by
//! explicit actions, so the path is one the explicit semantics takes.

use biodivine_lib_bdd::{Bdd, BddVariable};

use super::{Reach, Symbolic, action_between};
use crate::dialect::system::{Action, Config};

/// Below this many configurations a layer is searched explicitly.
const EXPLICIT_BELOW: f64 = 64.0;

impl Symbolic<'_, '_> {
    /// A shortest path of explicit actions from the initial configuration
    /// to a reached configuration of `target`, and that configuration.
    /// `None` when no reached configuration is in `target`, or (a bug) the
    /// symbolic and explicit semantics disagree on a step.
    pub fn trace_to(&self, reach: &Reach, target: &Bdd) -> Option<(Vec<Action>, Config)> {
        let mut m = reach
            .layers
            .iter()
            .position(|layer| !layer.set.and(target).is_false())?;
        let last = self.layout.pick(&reach.layers[m].set.and(target))?;
        let mut configs = vec![last.clone()];
        while m > 0 {
            let after = configs.last()?;
            let layer = reach.layers.get(m)?;
            let candidates = match layer.step {
                None => reach.layers[m - 1].set.clone(),
                Some(_) => reach.layers[..m]
                    .iter()
                    .fold(self.layout.vars.mk_false(), |acc, l| acc.or(&l.set)),
            };
            let before = self.predecessor(&candidates, after, layer.step)?;
            let here = self.layout.encode(&before);
            m = reach.layers[..m]
                .iter()
                .position(|l| !l.set.and(&here).is_false())?;
            configs.push(before);
        }
        configs.reverse();
        let path = configs
            .windows(2)
            .map(|w| action_between(self.sys, &w[0], &w[1]))
            .collect::<Option<Vec<Action>>>()?;
        Some((path, last))
    }

    /// A configuration of `candidates` with an explicit step to `after`
    /// (found by halving with the image of `step`, or of every step).
    fn predecessor(&self, candidates: &Bdd, after: &Config, step: Option<usize>) -> Option<Config> {
        let target = self.layout.encode(after);
        let image = |x: &Bdd| match step {
            Some(k) => self.steps.step_image(&self.layout, x, k),
            None => self.steps.image(&self.layout, x),
        };
        let mut x = match step.and_then(|k| self.steps.list.get(k)) {
            Some(s) => candidates.and(&s.guard),
            None => candidates.clone(),
        };
        while x.cardinality() > EXPLICIT_BELOW {
            let v = split_variable(&x)?;
            let low = x.var_select(v, false);
            let high = x.var_select(v, true);
            x = if image(&low).and(&target).is_false() {
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
