//! Compositional exploration of one cluster: its services split into the
//! strongly connected components (*parts*) of the *depends-on* relation,
//! explored one part at a time, upstream first, each with an automaton of
//! what its upstream can show it instead of the upstream services
//! themselves.
//!
//! A service depends on another when the other `delays` or `forbids` it, or
//! when one of them `stops` the other (an interrupt goes one way, the wait
//! for the interrupted instance the other way). A part is therefore only
//! influenced by its upstream parts, and only through whether their
//! services have an instance and whether that instance may never end (the
//! starvation verdict reads it). Threads and locks only delay codels that
//! always finish, as between clusters.
//!
//! The parts are explored in a topological order. The first is explored on
//! its own; after each, its reachable graph, labelled with the *interface*
//! (the instance bits of the services later parts read), is projected to a
//! minimal deterministic automaton ([`Env`]) of the sequences of interface
//! values it can show; the next part is explored in product with it. The
//! automaton accepts exactly the sequences of the upstream's executions, so
//! the part reaches exactly the states it reaches in the whole cluster.
//! A witness found in a part is made concrete by a search in the real
//! semantics of the part and its upstream services ([`concretize`]), guided
//! by the witness: the part's steps in order, and upstream steps that show
//! the interface values in the witness's order. `docs/semantics.md`
//! ("Compositional exploration") states the argument; tests/verdicts/compose.rs
//! compares it with the exploration of whole clusters.

use std::collections::{BTreeMap, BTreeSet};

use genom_model::component::{Component, ServiceId};
use petgraph::algo::tarjan_scc;
use petgraph::graph::DiGraph;

use super::system::{Action, Config, System};
use crate::kernel::explore::{Exploration, Model};
use crate::kernel::store::{StateId, Store};

/// The parts of a cluster (sorted services each), upstream first.
pub fn parts(c: &Component, cluster: &[ServiceId]) -> Vec<Vec<ServiceId>> {
    let mut g: DiGraph<ServiceId, ()> = DiGraph::new();
    let nodes: BTreeMap<ServiceId, _> = cluster.iter().map(|&s| (s, g.add_node(s))).collect();
    for &s in cluster {
        let svc = &c.services[s];
        let edges = svc
            .stops
            .iter()
            .flat_map(|r| [(s, r.id), (r.id, s)])
            .chain(svc.delays.iter().chain(&svc.forbids).map(|r| (r.id, s)));
        for (from, to) in edges.filter(|(a, b)| a != b) {
            if let (Some(&a), Some(&b)) = (nodes.get(&from), nodes.get(&to)) {
                g.update_edge(a, b, ());
            }
        }
    }
    // Edges go from the dependent service to what it depends on: Tarjan's
    // post-order lists those first.
    tarjan_scc(&g)
        .into_iter()
        .map(|scc| {
            let mut part: Vec<ServiceId> = scc.into_iter().map(|n| g[n]).collect();
            part.sort();
            part
        })
        .collect()
}

/// How a cluster is explored part by part: its parts, upstream first, and
/// for each part its inputs, its cone and the interface it leaves to the
/// later parts.
#[derive(Debug, Clone)]
pub struct Plan {
    /// The parts, upstream first.
    pub parts: Vec<Vec<ServiceId>>,
    /// The inputs of each part.
    pub inputs: Vec<Vec<ServiceId>>,
    /// For each part, the earlier parts it depends on, directly or not.
    upstream: Vec<BTreeSet<usize>>,
    /// For each part, the services of it and of earlier parts that later
    /// parts read.
    interface: Vec<Vec<ServiceId>>,
}

impl Plan {
    /// The plan of `cluster`.
    pub fn new(c: &Component, cluster: &[ServiceId]) -> Plan {
        let parts = parts(c, cluster);
        let inputs: Vec<Vec<ServiceId>> = parts.iter().map(|p| inputs(c, cluster, p)).collect();
        let part_of: BTreeMap<ServiceId, usize> = parts
            .iter()
            .enumerate()
            .flat_map(|(k, p)| p.iter().map(move |&s| (s, k)))
            .collect();
        let mut upstream: Vec<BTreeSet<usize>> = Vec::with_capacity(parts.len());
        for needs in &inputs {
            let mut up = BTreeSet::new();
            for j in needs.iter().filter_map(|t| part_of.get(t).copied()) {
                up.insert(j);
                up.extend(upstream.get(j).into_iter().flatten().copied());
            }
            upstream.push(up);
        }
        let mut read_later: BTreeSet<ServiceId> = BTreeSet::new();
        let mut interface = vec![Vec::new(); parts.len()];
        for k in (0..parts.len()).rev() {
            interface[k] = read_later
                .iter()
                .copied()
                .filter(|s| part_of.get(s).is_some_and(|&j| j <= k))
                .collect();
            read_later.extend(inputs[k].iter().copied());
        }
        Plan {
            parts,
            inputs,
            upstream,
            interface,
        }
    }

    /// Part `k` and every service upstream of it, sorted.
    pub fn cone(&self, k: usize) -> Vec<ServiceId> {
        let mut cone: Vec<ServiceId> = self.upstream[k]
            .iter()
            .flat_map(|&j| self.parts[j].iter().copied())
            .chain(self.parts[k].iter().copied())
            .collect();
        cone.sort();
        cone
    }

    /// The services of parts up to `k` that later parts read.
    pub fn interface(&self, k: usize) -> &[ServiceId] {
        &self.interface[k]
    }

    /// Whether every interface fits an environment value (two bits per
    /// service in a `u64`: at most [`MAX_INTERFACE`] services).
    pub fn fits(&self) -> bool {
        self.interface.iter().all(|i| i.len() <= MAX_INTERFACE)
    }
}

/// The services outside `part` whose instances it reads (`delays` or
/// `forbids` one of its services), sorted.
pub fn inputs(c: &Component, cluster: &[ServiceId], part: &[ServiceId]) -> Vec<ServiceId> {
    let mut out: Vec<ServiceId> = cluster
        .iter()
        .copied()
        .filter(|t| !part.contains(t))
        .filter(|&t| {
            let ts = &c.services[t];
            ts.delays
                .iter()
                .chain(&ts.forbids)
                .any(|r| part.contains(&r.id))
        })
        .collect();
    out.sort();
    out
}

/// Most services an interface holds (an environment value has two bits per
/// service in a `u64`).
pub const MAX_INTERFACE: usize = 32;

/// A deterministic automaton of the interface values an upstream can show:
/// each state has the current value (two bits per service of `layout`:
/// has an instance, may never end) and one successor per next value.
#[derive(Debug, Clone)]
pub struct Env {
    /// The services whose bits the values hold.
    pub layout: Vec<ServiceId>,
    /// The value of each state.
    pub value: Vec<u64>,
    /// The successors of each state.
    pub succ: Vec<Vec<u32>>,
    /// The initial state.
    pub init: u32,
}

impl Env {
    /// The environment of the first part: nothing upstream.
    pub fn empty() -> Env {
        Env {
            layout: Vec::new(),
            value: vec![0],
            succ: vec![Vec::new()],
            init: 0,
        }
    }

    /// The instance of `layout[pos]` in `value`: none, or whether it may
    /// never end.
    pub fn instance(value: u64, pos: usize) -> Option<bool> {
        if pos >= MAX_INTERFACE {
            return None;
        }
        (value >> (2 * pos) & 1 == 1).then_some(value >> (2 * pos + 1) & 1 == 1)
    }

    /// Number of states.
    pub fn len(&self) -> usize {
        self.value.len()
    }

    /// True without states (never: there is always an initial state).
    pub fn is_empty(&self) -> bool {
        self.value.is_empty()
    }
}

/// A step of a part in product with its environment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Step {
    /// A step of the part's services.
    Sys(Action),
    /// The upstream moves to this environment state.
    Env(u32),
}

/// A part (with its inputs as members) in product with its environment.
pub struct Composed<'a> {
    /// The part's system; its inputs are the upstream services it reads.
    pub sys: System<'a>,
    env: &'a Env,
    /// Each input's member index and position in the environment's layout.
    inputs: Vec<(usize, usize)>,
}

impl<'a> Composed<'a> {
    /// The product of `sys` (whose inputs must all be in `env.layout`) and
    /// `env`.
    pub fn new(sys: System<'a>, env: &'a Env) -> Option<Self> {
        let mut inputs = Vec::new();
        for i in (0..sys.len()).filter(|&i| sys.is_input(i)) {
            let pos = env.layout.iter().position(|&s| s == sys.service(i))?;
            inputs.push((i, pos));
        }
        Some(Composed { sys, env, inputs })
    }

    fn show(&self, cfg: &mut Config, d: u32) {
        let value = self.env.value[d as usize];
        for &(i, pos) in &self.inputs {
            System::set_input(cfg, i, Env::instance(value, pos));
        }
    }

    /// The value of the input bits alone (a projection of an environment
    /// value) in a configuration.
    pub fn input_value(&self, cfg: &Config) -> u64 {
        interface_value(&self.sys, cfg, &self.inputs_layout(), None)
    }

    fn inputs_layout(&self) -> Vec<ServiceId> {
        self.inputs
            .iter()
            .map(|&(i, _)| self.sys.service(i))
            .collect()
    }
}

impl Model for Composed<'_> {
    type State = (Config, u32);
    type Action = Step;
    type Zone = ();

    fn width(&self) -> usize {
        self.sys.width() + 1
    }

    fn init_states(&self) -> Vec<(Config, u32)> {
        let d = self.env.init;
        let cfg = self
            .sys
            .initial_with(true, |cfg| self.show(cfg, d), &mut None);
        vec![(cfg, d)]
    }

    fn actions(&self, (cfg, d): &(Config, u32), out: &mut Vec<Step>) {
        let mut own = Vec::new();
        self.sys.actions(cfg, &mut own);
        out.extend(own.into_iter().map(Step::Sys));
        out.extend(self.env.succ[*d as usize].iter().map(|&e| Step::Env(e)));
    }

    fn next_state(&self, (cfg, d): &(Config, u32), step: Step) -> Option<(Config, u32)> {
        match step {
            Step::Sys(a) => self.sys.apply(cfg, a, &mut None).map(|c| (c, *d)),
            Step::Env(e) => {
                let mut next = cfg.clone();
                self.show(&mut next, e);
                self.sys.closure(&mut next, &mut None);
                Some((next, e))
            }
        }
    }

    fn reduce(&self, (cfg, _): &(Config, u32), actions: &mut [Step]) -> usize {
        self.sys.note_facts(cfg);
        actions.len()
    }

    fn finished(&self) -> bool {
        self.sys.all_found()
    }

    fn encode(&self, (cfg, d): &(Config, u32), out: &mut Vec<u64>) {
        self.sys.encode(cfg, out);
        out.push(u64::from(*d));
    }

    fn decode(&self, words: &[u64], (): &()) -> (Config, u32) {
        let w = self.sys.width();
        let d = words.get(w).copied().unwrap_or(0);
        (
            self.sys.decode(&words[..w], &()),
            u32::try_from(d).unwrap_or(0),
        )
    }

    fn zone(&self, _: &(Config, u32)) {}
}

/// The interface value of a configuration: for each service of `layout`,
/// its instance bits, read from the system (members) or from the
/// environment value `upstream` (services of earlier parts).
pub fn interface_value(
    sys: &System<'_>,
    cfg: &Config,
    layout: &[ServiceId],
    upstream: Option<(&Env, u32)>,
) -> u64 {
    let mut value = 0;
    for (pos, &s) in layout.iter().enumerate().take(MAX_INTERFACE) {
        let instance = match sys.member_index(s).filter(|&i| !sys.is_input(i)) {
            Some(i) => System::has_instance(cfg, i).then(|| sys.may_never_end(cfg, i)),
            None => match sys.member_index(s) {
                // An input: its slot holds what the environment shows.
                Some(i) => cfg.pending[i].map(|v| v == 1),
                None => upstream.and_then(|(env, d)| {
                    let p = env.layout.iter().position(|&t| t == s)?;
                    Env::instance(env.value[d as usize], p)
                }),
            },
        };
        if let Some(never) = instance {
            value |= 1 << (2 * pos);
            value |= u64::from(never) << (2 * pos + 1);
        }
    }
    value
}

/// The successors of every state of a complete exploration, as ids.
fn edges(model: &Composed<'_>, e: &Exploration<Step>) -> Option<Vec<Vec<StateId>>> {
    let mut out = Vec::with_capacity(e.store.len());
    let (mut actions, mut key) = (Vec::new(), Vec::new());
    for id in 0..e.store.len() {
        let st = model.decode(&e.store.get(StateId::try_from(id).ok()?), &());
        actions.clear();
        model.actions(&st, &mut actions);
        let mut succ = Vec::with_capacity(actions.len());
        for &a in &actions {
            let Some(next) = model.next_state(&st, a) else {
                continue;
            };
            key.clear();
            model.encode(&next, &mut key);
            succ.push(e.store.find(&key)?);
        }
        out.push(succ);
    }
    Some(out)
}

/// The environment of the next parts: the minimal deterministic automaton
/// of the `layout` values the explored product shows, or `None` when it
/// would have more than `max` states.
pub fn project(
    model: &Composed<'_>,
    e: &Exploration<Step>,
    layout: &[ServiceId],
    max: usize,
) -> Option<Env> {
    let values: Vec<u64> = (0..e.store.len())
        .map(|id| {
            let (cfg, d) = model.decode(&e.store.get(id as StateId), &());
            interface_value(&model.sys, &cfg, layout, Some((model.env, d)))
        })
        .collect();
    let succ = edges(model, e)?;
    let (value, next) = determinize(&values, &succ, max)?;
    let (value, next) = minimize(&value, &next);
    Some(Env {
        layout: layout.to_vec(),
        value,
        succ: next,
        init: 0,
    })
}

/// Subset construction over value changes (steps that keep the value are
/// silent); state 0 is the closure of the initial state 0.
fn determinize(
    values: &[u64],
    succ: &[Vec<StateId>],
    max: usize,
) -> Option<(Vec<u64>, Vec<Vec<u32>>)> {
    let mut mark = vec![false; values.len()];
    let mut closure = |seeds: Vec<StateId>| silent_closure(values, succ, &mut mark, seeds);
    let mut index: BTreeMap<Vec<StateId>, u32> = BTreeMap::new();
    let mut sets: Vec<Vec<StateId>> = vec![closure(vec![0])];
    index.insert(sets[0].clone(), 0);
    let (mut value, mut next) = (Vec::new(), Vec::new());
    let mut k = 0;
    while k < sets.len() {
        let set = sets[k].clone();
        k += 1;
        let v = values[set[0] as usize];
        let mut by_value: BTreeMap<u64, Vec<StateId>> = BTreeMap::new();
        for &p in &set {
            for &q in &succ[p as usize] {
                if values[q as usize] != v {
                    by_value.entry(values[q as usize]).or_default().push(q);
                }
            }
        }
        let mut out = Vec::new();
        for (_, seeds) in by_value {
            let target = closure(seeds);
            let id = match index.get(&target) {
                Some(&id) => id,
                None => {
                    let id = u32::try_from(sets.len()).ok()?;
                    index.insert(target.clone(), id);
                    sets.push(target);
                    id
                }
            };
            out.push(id);
        }
        if sets.len() > max {
            return None;
        }
        value.push(v);
        next.push(out);
    }
    Some((value, next))
}

/// The states reachable from `seeds` by steps that keep the value, sorted
/// (`mark` is all `false` before and after).
fn silent_closure(
    values: &[u64],
    succ: &[Vec<StateId>],
    mark: &mut [bool],
    mut seeds: Vec<StateId>,
) -> Vec<StateId> {
    seeds.sort_unstable();
    seeds.dedup();
    for &p in &seeds {
        mark[p as usize] = true;
    }
    let mut stack = seeds.clone();
    while let Some(p) = stack.pop() {
        for &q in &succ[p as usize] {
            if values[q as usize] == values[p as usize] && !mark[q as usize] {
                mark[q as usize] = true;
                seeds.push(q);
                stack.push(q);
            }
        }
    }
    for &p in &seeds {
        mark[p as usize] = false;
    }
    seeds.sort_unstable();
    seeds
}

/// Moore's partition refinement: states with the same value whose
/// successors fall in the same blocks are merged.
fn minimize(value: &[u64], next: &[Vec<u32>]) -> (Vec<u64>, Vec<Vec<u32>>) {
    let n = value.len();
    let mut block: Vec<usize> = renumber(&value.iter().map(|&v| vec![v]).collect::<Vec<_>>());
    loop {
        let signatures: Vec<Vec<u64>> = (0..n)
            .map(|p| {
                let mut sig: Vec<u64> = next[p].iter().map(|&q| block[q as usize] as u64).collect();
                sig.sort_unstable();
                sig.dedup();
                sig.insert(0, block[p] as u64);
                sig
            })
            .collect();
        let refined = renumber(&signatures);
        let stable = refined.iter().max() == block.iter().max();
        block = refined;
        if stable {
            break;
        }
    }
    let blocks = block.iter().max().map_or(0, |m| m + 1);
    let mut out_value = vec![0; blocks];
    let mut out_next: Vec<Vec<u32>> = vec![Vec::new(); blocks];
    for p in 0..n {
        out_value[block[p]] = value[p];
        let mut succ: Vec<u32> = next[p]
            .iter()
            .map(|&q| u32::try_from(block[q as usize]).unwrap_or(0))
            .collect();
        succ.sort_unstable();
        succ.dedup();
        out_next[block[p]] = succ;
    }
    (out_value, out_next)
}

/// Numbers distinct keys in order of first appearance (so that the block
/// of state 0 is block 0).
fn renumber(keys: &[Vec<u64>]) -> Vec<usize> {
    let mut ids: BTreeMap<&[u64], usize> = BTreeMap::new();
    keys.iter()
        .map(|k| {
            let n = ids.len();
            *ids.entry(k.as_slice()).or_insert(n)
        })
        .collect()
}

/// What a concrete execution must do, read off a witness path of a part.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Goal {
    /// The part takes this step.
    Act(Action),
    /// The part's inputs change to this value.
    See(u64),
}

/// Turns a witness path of a composed part into steps of the real
/// semantics of `cone` (the part and every service upstream of it, post
/// initialisation): the part's steps in order, and upstream steps whose
/// input values change as in the witness. `None` when the guided search
/// finds no such execution within `max_states`.
pub fn concretize(
    model: &Composed<'_>,
    cone: &System<'_>,
    path: &[Step],
    max_states: usize,
) -> Option<Vec<Action>> {
    let goals = goals(model, path);
    let part: Vec<ServiceId> = model.sys.services().collect();
    let layout = model.inputs_layout();
    let guided = Guided {
        cone,
        part: &part,
        layout: &layout,
        goals: &goals,
    };
    let init = cone.initial(true, &mut None);
    let mut store: Store<Action> = Store::new(cone.width() + 1);
    let mut key = Vec::new();
    guided.encode(&init, 0, &mut key);
    store.insert(&key, (), None);
    let mut next = 0;
    while next < store.len() && store.len() <= max_states {
        let id = StateId::try_from(next).ok()?;
        next += 1;
        let words = store.get(id);
        let (cfg, k) = (
            cone.decode(&words[..cone.width()], &()),
            words[cone.width()],
        );
        let k = usize::try_from(k).ok()?;
        if k == goals.len() {
            return Some(store.path(id));
        }
        for (a, succ, k2) in guided.moves(&cfg, k) {
            key.clear();
            guided.encode(&succ, k2, &mut key);
            store.insert(&key, (), Some((id, a)));
        }
    }
    None
}

/// The goals of a witness path: its part's steps, and each change of the
/// inputs' value.
fn goals(model: &Composed<'_>, path: &[Step]) -> Vec<Goal> {
    let mut out = Vec::new();
    let mut st = model.init_states().remove(0);
    let mut seen = model.input_value(&st.0);
    for &step in path {
        let Some(next) = model.next_state(&st, step) else {
            break;
        };
        st = next;
        match step {
            Step::Sys(a) => out.push(Goal::Act(a)),
            Step::Env(_) => {
                let v = model.input_value(&st.0);
                if v != seen {
                    out.push(Goal::See(v));
                    seen = v;
                }
            }
        }
    }
    out
}

/// The guided search's moves.
struct Guided<'g> {
    cone: &'g System<'g>,
    part: &'g [ServiceId],
    layout: &'g [ServiceId],
    goals: &'g [Goal],
}

impl Guided<'_> {
    fn encode(&self, cfg: &Config, k: usize, out: &mut Vec<u64>) {
        self.cone.encode(cfg, out);
        out.push(k as u64);
    }

    fn value(&self, cfg: &Config) -> u64 {
        interface_value(self.cone, cfg, self.layout, None)
    }

    /// Upstream steps that keep the inputs' value, or change it to the next
    /// goal's; and the part's next step when it is the goal.
    fn moves(&self, cfg: &Config, k: usize) -> Vec<(Action, Config, usize)> {
        let mut actions = Vec::new();
        self.cone.actions(cfg, &mut actions);
        let before = self.value(cfg);
        let mut out = Vec::new();
        for a in actions {
            let own = self.part.contains(&a.service());
            if own && self.goals.get(k) != Some(&Goal::Act(a)) {
                continue;
            }
            let Some(next) = self.cone.apply(cfg, a, &mut None) else {
                continue;
            };
            let after = self.value(&next);
            let k2 = if own {
                (after == before).then_some(k + 1)
            } else if after == before {
                Some(k)
            } else {
                (self.goals.get(k) == Some(&Goal::See(after))).then_some(k + 1)
            };
            if let Some(k2) = k2 {
                out.push((a, next, k2));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests;
