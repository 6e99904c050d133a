//! The reachability verdicts of the explicit analysis (`analysis::visit`)
//! as sets of configurations, intersected with the reachable set, each
//! witness with a shortest explicit trace ([`Symbolic::trace_to`]).
//!
//! Deadlocks are configurations where pending instances without watchdog
//! delay each other in a cycle: the members that can reach such a cycle
//! are computed as a fixpoint over the `delays` graph (a pending member
//! stays when some pending member delaying it stays). Each reported
//! deadlock names the cycle of one witness configuration, as the explicit
//! engine does; configurations where that cycle's services are all
//! pending are not searched again, so a larger cycle that always contains
//! a reported one is not listed separately.

use std::collections::{BTreeMap, BTreeSet};

use std::time::Instant;

use biodivine_lib_bdd::Bdd;
use genom_model::behaviour::{IDLE, PosId};
use genom_model::component::{CodelId, ServiceId};
use genom_model::limits::out_of_time;

use super::{Reach, Symbolic};
use crate::dialect::system::{Action, Config};

/// A deadlock: services of the cycle, sorted, and a trace to it.
#[derive(Debug, Clone)]
pub struct SymbolicDeadlock {
    /// The services of the cycle.
    pub services: Vec<ServiceId>,
    /// Explicit actions from the initial configuration.
    pub path: Vec<Action>,
}

/// What the reachable set establishes.
#[derive(Debug, Clone, Default)]
pub struct Verdicts {
    /// Codels some execution runs (control codels: some request reaches
    /// them).
    pub reached: BTreeSet<CodelId>,
    /// Services some execution starts (or, without start codel, accepts).
    pub started: BTreeSet<ServiceId>,
    /// Services with a pending instance in some reachable configuration.
    pub pending: BTreeSet<ServiceId>,
    /// Services whose interrupted instance can loop forever, with a trace.
    pub unbounded: BTreeMap<ServiceId, Vec<Action>>,
    /// `(waiter, blocker)`: a pending instance waiting on an instance that
    /// may never end, with a trace.
    pub starvations: BTreeMap<(ServiceId, ServiceId), Vec<Action>>,
    /// Deadlocks, with traces.
    pub deadlocks: Vec<SymbolicDeadlock>,
}

impl Symbolic<'_, '_> {
    /// The verdicts over `reach`. Traces are built when `traces` is set
    /// (else the paths are empty).
    pub fn verdicts(&self, reach: &Reach, traces: bool) -> Verdicts {
        self.verdicts_until(reach, traces, None).unwrap_or_default()
    }

    /// [`Self::verdicts`], or `None` when `deadline` passes first (reading
    /// a large reachable set takes time of its own).
    pub fn verdicts_until(
        &self,
        reach: &Reach,
        traces: bool,
        deadline: Option<Instant>,
    ) -> Option<Verdicts> {
        let r = &reach.reached;
        let l = &self.layout;
        let mut out = Verdicts::default();
        let path = |w: &Bdd| {
            if traces {
                self.trace_to(reach, w).map(|(p, _)| p).unwrap_or_default()
            } else {
                Vec::new()
            }
        };
        for i in 0..self.sys.len() {
            if out_of_time(deadline) {
                return None;
            }
            let s = self.sys.service(i);
            let m = self.sys.machine_of(i);
            for &(q, codel) in &l.facts[i].running {
                if meets(r, &l.pos_eq(i, q)) {
                    out.reached.insert(codel);
                }
            }
            let requested = meets(r, &self.steps.request[i]);
            if requested {
                out.reached.extend(self.sys.component().services[s].control);
            }
            if meets(r, &l.pos_eq(i, IDLE).not()) || (requested && m.start.is_none()) {
                out.started.insert(s);
            }
            if meets(r, &l.pend(i)) {
                out.pending.insert(s);
            }
            let looping = self.positions(i, |q| m.stop_loops[usize::from(q)]);
            if meets(r, &looping) {
                out.unbounded.insert(s, path(&r.and(&looping)));
            }
            if !m.watchdog {
                for (t, w) in self.starving(i) {
                    let w = r.and(&w);
                    if !w.is_false() {
                        out.starvations.insert((s, self.sys.service(t)), path(&w));
                    }
                }
            }
        }
        if out_of_time(deadline) {
            return None;
        }
        out.deadlocks = self.deadlocks(reach, traces);
        Some(out)
    }

    /// A shortest explicit path to a reached configuration where member
    /// `i` has a pending instance, and that configuration.
    pub fn pending_witness(&self, reach: &Reach, i: usize) -> Option<(Vec<Action>, Config)> {
        self.trace_to(reach, &self.layout.pend(i))
    }

    /// Member `i`'s positions satisfying `keep` (idle excluded).
    fn positions(&self, i: usize, keep: impl Fn(PosId) -> bool) -> Bdd {
        let l = &self.layout;
        let n = self.sys.machine_of(i).positions.len();
        (1..n)
            .filter_map(|q| PosId::try_from(q).ok())
            .filter(|&q| keep(q))
            .fold(l.vars.mk_false(), |acc, q| acc.or(&l.pos_eq(i, q)))
    }

    /// For pending member `i`, each blocker `t` with the configurations
    /// where `t` blocks it (delays it, or is waited for) and may never end.
    fn starving(&self, i: usize) -> Vec<(usize, Bdd)> {
        let l = &self.layout;
        let f = &l.facts[i];
        let mut blockers: BTreeMap<usize, Bdd> = BTreeMap::new();
        for &t in &f.delayers {
            let b = blockers.entry(t).or_insert_with(|| l.vars.mk_false());
            *b = b.or(&l.has_instance(t));
        }
        for (bit, &t) in f.stops.iter().enumerate() {
            let b = blockers.entry(t).or_insert_with(|| l.vars.mk_false());
            *b = b.or(&l.vars.mk_var(l.slots[i].mask[bit]));
        }
        blockers
            .into_iter()
            .map(|(t, b)| {
                let m = self.sys.machine_of(t);
                let never = self.positions(t, |q| m.may_never_end[usize::from(q)]);
                (t, b.and(&l.pend(i)).and(&never))
            })
            .collect()
    }

    /// Members that are nodes of the deadlock graph: can stay pending and
    /// have no watchdog.
    fn nodes(&self) -> Vec<bool> {
        (0..self.sys.len())
            .map(|i| self.layout.slots[i].pend.is_some() && !self.sys.machine_of(i).watchdog)
            .collect()
    }

    /// The reachable configurations with a cycle of pending instances
    /// delaying each other.
    fn deadlocked(&self, reach: &Reach) -> Bdd {
        let l = &self.layout;
        let nodes = self.nodes();
        let mut alive: Vec<Bdd> = (0..nodes.len())
            .map(|i| {
                if nodes[i] {
                    l.pend(i)
                } else {
                    l.vars.mk_false()
                }
            })
            .collect();
        loop {
            let mut changed = false;
            for i in (0..alive.len()).filter(|&i| nodes[i]) {
                let next = l.facts[i]
                    .delayers
                    .iter()
                    .fold(l.vars.mk_false(), |acc, &t| acc.or(&alive[t]));
                let next = alive[i].and(&next);
                if next != alive[i] {
                    alive[i] = next;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        let any = alive.iter().fold(l.vars.mk_false(), |acc, a| acc.or(a));
        reach.reached.and(&any)
    }

    fn deadlocks(&self, reach: &Reach, traces: bool) -> Vec<SymbolicDeadlock> {
        let l = &self.layout;
        let mut left = self.deadlocked(reach);
        let mut out = Vec::new();
        while let Some(cfg) = l.pick(&left) {
            let Some(cycle) = self.cycle(&cfg) else {
                break;
            };
            let all = cycle
                .iter()
                .fold(l.vars.mk_true(), |acc, &i| acc.and(&l.pend(i)));
            let witnesses = left.and(&all);
            let path = if traces {
                self.trace_to(reach, &witnesses)
                    .map(|(p, _)| p)
                    .unwrap_or_default()
            } else {
                Vec::new()
            };
            let mut services: Vec<ServiceId> = cycle.iter().map(|&i| self.sys.service(i)).collect();
            services.sort();
            out.push(SymbolicDeadlock { services, path });
            left = left.and_not(&all);
        }
        out.sort_by(|a, b| a.services.cmp(&b.services));
        out
    }

    /// The cycle of pending members of `cfg` that the explicit analysis
    /// reports: the strongly connected part of the first member on a cycle.
    fn cycle(&self, cfg: &Config) -> Option<Vec<usize>> {
        let nodes = self.nodes();
        let n = nodes.len();
        let node = |i: usize| nodes[i] && cfg.pending[i].is_some();
        let reach = |from: usize| {
            let mut seen = vec![false; n];
            let mut stack = vec![from];
            while let Some(x) = stack.pop() {
                for &t in self.layout.facts[x].delayers.iter().filter(|&&t| node(t)) {
                    if !std::mem::replace(&mut seen[t], true) {
                        stack.push(t);
                    }
                }
            }
            seen
        };
        let closure: Vec<Vec<bool>> = (0..n)
            .map(|i| if node(i) { reach(i) } else { vec![false; n] })
            .collect();
        let first = (0..n).find(|&i| closure[i][i])?;
        Some(
            (0..n)
                .filter(|&j| closure[first][j] && closure[j][first])
                .collect(),
        )
    }
}

/// Whether two sets meet.
fn meets(a: &Bdd, b: &Bdd) -> bool {
    !a.and(b).is_false()
}
