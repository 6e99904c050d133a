//! Symbolic sets: breadth-first reachability of any untimed [`Model`]
//! with the states kept as BDDs over the bits of their packed form
//! ([`Model::encode`], [`Model::bits`]), the kernel's symbolic method and
//! the fallback of an explicit exploration that stopped on its state or
//! memory limit.
//!
//! Each layer (the states first reached at one distance from the initial
//! ones) is a BDD; the reached set is their union. A layer's image is
//! computed by the model's own step rules: its states are enumerated in
//! the BDD's order, each is visited (the analysis reads its facts, as on
//! the explicit explorer) and expanded, and the successors are packed
//! into a BDD built bottom-up from their sorted keys ([`build`]). So the
//! memory held is the BDDs' nodes and one chunk of successors, not a
//! table of every state: a part too large to store explicitly may still
//! have small sets. The time is still that of every state once.
//!
//! Only models whose states have no zone and that do not reduce
//! ([`Model::reduce`] is ignored: every action is fired). Paths are found
//! again layer by layer, so they are shortest, and a state's id is its
//! rank in the order of visits (layer by layer, each layer in the BDD's
//! order), which is the order [`SetExploration::path`] reads again.

mod build;

use std::time::{Duration, Instant};

use biodivine_lib_bdd::{Bdd, BddValuation};

use super::explore::{Found, Model, Stop};
use super::store::StateId;

/// Successors packed into a BDD at once, at most (then the next chunk).
const CHUNK: usize = 1 << 20;

/// How often (in states visited) time and memory are looked at.
const PERIOD: u64 = 256;

/// Resource limits of a symbolic exploration.
#[derive(Debug, Clone, Copy)]
pub struct SetLimits {
    /// Stop at this instant.
    pub deadline: Option<Instant>,
    /// `--max-memory`: stop when the process's heap reaches its soft bound
    /// ([`genom_model::limits::soft_bound`]).
    pub max_bytes: usize,
    /// Stop when the reached set's BDD has more nodes than this.
    pub max_nodes: usize,
}

impl Default for SetLimits {
    fn default() -> Self {
        SetLimits {
            deadline: None,
            max_bytes: 8 << 30,
            max_nodes: 50_000_000,
        }
    }
}

/// The result of a symbolic exploration.
#[derive(Debug)]
pub struct SetExploration {
    /// Bits of a packed state (the BDD variables).
    bits: usize,
    /// Words of a packed state.
    width: usize,
    /// The states first reached at each distance.
    layers: Vec<Bdd>,
    /// The id of the first state of each layer visited.
    starts: Vec<u64>,
    /// States reached (visited or not).
    pub states: u64,
    /// States visited (and expanded).
    pub visited: u64,
    /// Transitions fired (including those to known states).
    pub transitions: u64,
    /// `None` when the whole reachable state space was explored.
    pub stopped: Option<Stop>,
    /// Time spent.
    pub elapsed: Duration,
    /// Largest node count of the reached set.
    pub peak_nodes: usize,
}

/// Explores `model` breadth-first with BDD sets, calling `visit` once per
/// state (in the order of ids), and stopping (complete) as soon as it
/// answers [`Found::All`].
pub fn explore_sets_until<M: Model<Zone = ()>>(
    model: &M,
    limits: SetLimits,
    mut visit: impl FnMut(StateId, &M::State) -> Found,
) -> SetExploration {
    let started = Instant::now();
    let (bits, width) = (model.bits(), model.width());
    let mut keys = build::Keys::new(width, bits);
    let mut words = Vec::with_capacity(width);
    for s in model.init_states() {
        words.clear();
        model.encode(&s, &mut words);
        keys.push(&words);
    }
    let first = keys.take_bdd();
    let mut out = SetExploration {
        bits,
        width,
        states: count(&first),
        peak_nodes: first.size(),
        layers: vec![first.clone()],
        starts: Vec::new(),
        visited: 0,
        transitions: 0,
        stopped: None,
        elapsed: Duration::ZERO,
    };
    let mut reached = first;
    let mut run = Run {
        model,
        limits,
        keys,
        next: build::empty(bits),
        actions: Vec::new(),
        successor: None,
        words,
    };
    loop {
        let layer = out.layers[out.layers.len() - 1].clone();
        out.starts.push(out.visited);
        match run.expand_layer(&layer, &mut out, &mut visit) {
            Ok(true) => {}
            Ok(false) => break,
            Err(stop) => {
                out.stopped = Some(stop);
                break;
            }
        }
        let next = run.take_next();
        let new = next.and_not(&reached);
        if new.is_false() {
            break;
        }
        reached = reached.or(&new);
        out.states += count(&new);
        out.peak_nodes = out.peak_nodes.max(reached.size());
        out.layers.push(new);
        if reached.size() > limits.max_nodes {
            out.stopped = Some(Stop::Memory);
            break;
        }
    }
    out.elapsed = started.elapsed();
    out
}

/// Number of states of a set (saturates at `u64::MAX`).
fn count(set: &Bdd) -> u64 {
    set.exact_cardinality()
        .to_string()
        .parse()
        .unwrap_or(u64::MAX)
}

/// The buffers of one exploration.
struct Run<'m, M: Model> {
    model: &'m M,
    limits: SetLimits,
    /// Successors not yet packed into [`Run::next`].
    keys: build::Keys,
    /// Successors of the layer packed so far.
    next: Bdd,
    actions: Vec<M::Action>,
    successor: Option<M::State>,
    words: Vec<u64>,
}

impl<M: Model<Zone = ()>> Run<'_, M> {
    /// Visits and expands every state of `layer`: `Ok(false)` when the
    /// visits found everything or the model is finished (complete),
    /// `Err` when a limit stopped it.
    fn expand_layer(
        &mut self,
        layer: &Bdd,
        out: &mut SetExploration,
        visit: &mut impl FnMut(StateId, &M::State) -> Found,
    ) -> Result<bool, Stop> {
        let model = self.model;
        for valuation in layer.sat_valuations() {
            let id = StateId::try_from(out.visited).map_err(|_| Stop::States)?;
            out.visited += 1;
            if out.visited % PERIOD == 0 {
                self.check_limits(out.visited)?;
            }
            unpack(&valuation, out.width, &mut self.words);
            let state = model.decode(&self.words, &());
            if visit(id, &state) == Found::All || model.finished() {
                return Ok(false);
            }
            if !model.expand(&state) {
                continue;
            }
            self.actions.clear();
            model.actions(&state, &mut self.actions);
            for k in 0..self.actions.len() {
                if !model.step_into(&state, self.actions[k], &mut self.successor) {
                    continue;
                }
                let Some(succ) = self.successor.as_ref() else {
                    continue;
                };
                out.transitions += 1;
                self.words.clear();
                model.encode(succ, &mut self.words);
                self.keys.push(&self.words);
            }
            if self.keys.len() >= CHUNK {
                self.next = self.next.or(&self.keys.take_bdd());
            }
        }
        Ok(true)
    }

    /// The successors of the layer, as one set.
    fn take_next(&mut self) -> Bdd {
        let rest = self.keys.take_bdd();
        let next = std::mem::replace(&mut self.next, build::empty(rest.num_vars().into()));
        next.or(&rest)
    }

    fn check_limits(&self, visited: u64) -> Result<(), Stop> {
        genom_model::limits::report_explored(usize::try_from(visited).unwrap_or(usize::MAX));
        if genom_model::limits::out_of_time(self.limits.deadline) {
            return Err(Stop::Time);
        }
        let heap = genom_model::limits::heap::in_use();
        if heap >= genom_model::limits::soft_bound(self.limits.max_bytes) {
            return Err(Stop::Memory);
        }
        Ok(())
    }
}

/// The packed words of a valuation: variable `k` is bit `k % 64` of word
/// `k / 64`.
fn unpack(valuation: &BddValuation, width: usize, out: &mut Vec<u64>) {
    out.clear();
    out.resize(width, 0);
    for (k, &bit) in valuation.as_vector().iter().enumerate() {
        if bit {
            out[k / 64] |= 1 << (k % 64);
        }
    }
}

impl SetExploration {
    /// The layer of state `id` and its rank in it.
    fn locate(&self, id: StateId) -> Option<(usize, usize)> {
        let id = u64::from(id);
        let layer = self.starts.partition_point(|&s| s <= id).checked_sub(1)?;
        let rank = usize::try_from(id - self.starts[layer]).ok()?;
        Some((layer, rank))
    }

    /// The packed words of state `id` (`None` for an id never visited).
    fn words(&self, id: StateId) -> Option<(usize, Vec<u64>)> {
        let (layer, rank) = self.locate(id)?;
        let valuation = self.layers.get(layer)?.sat_valuations().nth(rank)?;
        let mut words = Vec::new();
        unpack(&valuation, self.width, &mut words);
        Some((layer, words))
    }

    /// The decoded state `id`.
    pub fn state<M: Model<Zone = ()>>(&self, model: &M, id: StateId) -> Option<M::State> {
        self.words(id).map(|(_, w)| model.decode(&w, &()))
    }

    /// The actions from an initial state to `id`: a shortest path, each
    /// step the first action (in [`Model::actions`] order) of the first
    /// state (in the previous layer's order) that leads to the next one.
    pub fn path<M: Model<Zone = ()>>(&self, model: &M, id: StateId) -> Vec<M::Action> {
        let Some((layer, mut target)) = self.words(id) else {
            return Vec::new();
        };
        let mut out = Vec::with_capacity(layer);
        let (mut words, mut actions, mut next) = (Vec::new(), Vec::new(), None);
        let mut key = Vec::with_capacity(self.width);
        for j in (0..layer).rev() {
            let found = self.layers[j].sat_valuations().find_map(|valuation| {
                unpack(&valuation, self.width, &mut words);
                let state = model.decode(&words, &());
                actions.clear();
                model.actions(&state, &mut actions);
                let a = actions.iter().copied().find(|&a| {
                    if !model.step_into(&state, a, &mut next) {
                        return false;
                    }
                    next.as_ref().is_some_and(|succ| {
                        key.clear();
                        model.encode(succ, &mut key);
                        key == target
                    })
                })?;
                Some((a, words.clone()))
            });
            // Every state of a layer has a predecessor in the one before.
            debug_assert!(found.is_some(), "no predecessor in layer {j}");
            let Some((a, from)) = found else { break };
            out.push(a);
            target = from;
        }
        out.reverse();
        out
    }

    /// Bits of a packed state: the BDD variables.
    pub fn bits(&self) -> usize {
        self.bits
    }

    /// The number of layers (the greatest distance from the initial
    /// states, plus one).
    pub fn depth(&self) -> usize {
        self.layers.len()
    }
}

#[cfg(test)]
mod tests;
