//! The linear relaxation of "clean" over the WCET variables, built from one
//! exploration of the timed model and maximized by z3 (the *SMT bound*).

use std::collections::{BTreeMap, BTreeSet, HashSet};

use genom_model::behaviour::Behaviour;
use genom_model::component::{CodelId, Component, Outcome, ServiceId, ThreadId};
use genom_model::kinds::CodelKind;
use z3::ast::Int;
use z3::{Optimize, SatResult};

use crate::kernel::explore::{Limits, explore};
use crate::timed::model::TimedSystem;

use super::wcets::{SCALE_STEPS, period_of};

/// At most this many period workloads and lock pairs are kept as
/// constraints (the relaxation only guides the search).
const MAX_CONSTRAINTS: usize = 20_000;

/// What one exploration of the timed model at the given WCETs showed.
#[derive(Debug, Default)]
pub(super) struct Observed {
    /// Per periodic thread: sets of codels some reachable state still has
    /// to run in the current period (two or more).
    pub(super) workloads: BTreeSet<(ThreadId, Vec<CodelId>)>,
    /// Pairs of codels (control codels included) that are ready or running
    /// together in some reachable state.
    pub(super) together: HashSet<(CodelId, CodelId)>,
    /// Whether the exploration ran.
    pub(super) explored: bool,
}

/// Explores the timed model of every cluster (as the timed engine does) to
/// collect period workloads and the codels that can be pending together.
pub(super) fn observe(c: &Component, limits: Limits) -> Observed {
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
pub(super) enum Var {
    /// The WCET of a codel, in ns.
    Wcet(CodelId),
    /// An auxiliary variable (longest remaining time of a max-time path).
    Aux(usize),
}

/// `Σ coefficient · variable ≤ bound`.
#[derive(Debug, Clone)]
pub(super) struct Linear {
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
    pub(super) constraints: Vec<Linear>,
    aux: usize,
}

pub(super) fn ns_i64(ns: u64) -> i64 {
    i64::try_from(ns).unwrap_or(i64::MAX / 4)
}

/// Where a codel runs: a thread, or the control thread (`None`).
pub(super) fn runner(c: &Component, k: CodelId) -> Option<Option<ThreadId>> {
    let codel = &c.codels[k];
    if codel.kind == CodelKind::Control {
        return Some(None);
    }
    c.services[codel.service].thread.map(|t| Some(t.id))
}

impl Relaxation {
    pub(super) fn build(c: &Component, seen: &Observed, reached: &BTreeSet<CodelId>) -> Relaxation {
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

pub(super) fn optimum(o: &Optimize, x: &Int) -> Option<u64> {
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
pub(super) fn path_graph(
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

pub(super) fn has_cycle(graph: &BTreeMap<CodelId, (Vec<CodelId>, bool)>) -> bool {
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
