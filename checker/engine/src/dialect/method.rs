//! The untimed exploration of a component ([`analyse`]: the pre-init
//! phase, then each cluster), which engine explores each cluster
//! (`--engine explicit|symbolic|auto`), and the record of what decided
//! each one, for the statistics.
//!
//! The explicit explorer, with its partial-order reduction and its part by
//! part exploration, is the default for every cluster: measured on the
//! generated components of issue 14 (docs/performance.md, "Engines") it is
//! faster than the symbolic (BDD) engine on every one of them. `auto` keeps
//! it, and explores symbolically a cluster the explicit explorer could not
//! finish within the state or memory limit (a cluster too large to store
//! explicitly may still have a small BDD). `symbolic` explores every
//! cluster with BDDs; a cluster the symbolic layout refuses is explored
//! explicitly, and the record says so.

use std::time::Instant;

use genom_model::behaviour::Behaviour;
use genom_model::component::{Component, ServiceId};
use genom_model::stats::Method as Decider;

use super::analysis::{
    Analysis, Decided, Whole, dead_services, explore_cluster, explore_parts, first_try_whole,
    pre_init,
};
use super::clusters::clusters;
use super::system::System;
use crate::kernel;
use crate::kernel::explore::{Limits, Stop};
use crate::symbolic::{Strategy, SymbolicLimits};

/// How the clusters are explored (every method gives the same verdicts).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Every interleaving of each whole cluster (`--no-reduction`).
    Exhaustive,
    /// `--engine auto`, the default: [`Method::Explicit`], then the
    /// symbolic engine for a cluster that stopped on the state or memory
    /// limit.
    Auto,
    /// `--engine explicit`: each cluster whole with the partial-order
    /// reduction within a share of the budget, then part by part, then
    /// whole.
    Explicit,
    /// `--engine symbolic`: each cluster with BDDs (explicitly, with the
    /// reduction, where the symbolic layout refuses it).
    Symbolic,
    /// Part by part first (compositional exploration), then whole with the
    /// partial-order reduction.
    PartsFirst,
    /// Whole, with the partial-order reduction only.
    Reduced,
    /// Whole, with the stubborn sets of the partial-order reduction alone:
    /// no probes, no stop once every fact is found (for tests).
    StubbornOnly,
}

/// Whether `auto` tries the symbolic engine on a cluster whose explicit
/// exploration stopped for `stop` ([`kernel::method::falls_back`]).
fn falls_back(method: Method, stop: Option<Stop>) -> bool {
    method == Method::Auto && kernel::method::falls_back(stop)
}

/// The explicit method that decided a cluster explored with `method`:
/// part by part (`parts`), or whole.
fn explicit_decider(method: Method, parts: bool) -> Decider {
    match (method, parts) {
        (_, true) => Decider::Compositional,
        (Method::Exhaustive, false) => Decider::Exhaustive,
        _ => Decider::Reduced,
    }
}

/// Explores the component and gathers every behavioural fact, with
/// partial-order reduction.
pub fn analyse(c: &Component, limits: Limits) -> Analysis {
    analyse_with(c, limits, true)
}

/// [`analyse`], with partial-order reduction (`reduce`) or exploring every
/// interleaving.
pub fn analyse_with(c: &Component, limits: Limits, reduce: bool) -> Analysis {
    let method = if reduce {
        Method::Auto
    } else {
        Method::Exhaustive
    };
    analyse_using(c, limits, method)
}

/// [`analyse`] with the given exploration method.
pub fn analyse_using(c: &Component, limits: Limits, method: Method) -> Analysis {
    let b = Behaviour::new(c);
    let all: Vec<ServiceId> = c.services.ids().collect();
    let global = System::new(c, &b, &all, false);
    let mut out = Analysis::default();
    let mut budget = limits;
    let (prefix, post_init) = match c.init_service() {
        Some(init) => pre_init(c, &b, init, &global, &mut budget, &mut out),

        None => (Vec::new(), Some(true)),
    };
    match post_init {
        Some(true) => {
            let whole = Whole {
                c,
                b: &b,
                prefix: &prefix,
                global: &global,
            };
            for cluster in clusters(c) {
                out.absorb(decide_cluster(&whole, &cluster, method, &mut budget));
            }
        }
        Some(false) => {}
        None => out.unproven.extend(all.iter().copied()),
    }
    dead_services(c, &global, post_init, &mut out);
    out
}

/// Explores one cluster with `method`: the result, with what decided it.
fn decide_cluster(
    w: &Whole<'_>,
    cluster: &[ServiceId],
    method: Method,
    budget: &mut Limits,
) -> Analysis {
    if method == Method::Symbolic {
        if let Some(out) = symbolic_cluster(w, cluster, budget.deadline, budget) {
            return out;
        }
    }
    let method = match method {
        Method::Symbolic => Method::Explicit,
        m => m,
    };
    let started = Instant::now();
    let mut out = Analysis::default();
    let parts = explicit_cluster(w, cluster, method, budget, &mut out);
    record(&mut out, cluster, explicit_decider(method, parts));
    if falls_back(method, out.stopped) {
        let deadline = kernel::method::fallback_deadline(budget, started.elapsed());
        if let Some(mut sym) = symbolic_cluster(w, cluster, Some(deadline), budget) {
            if sym.stopped.is_none() {
                // The explicit exploration's figures count too.
                sym.states += out.states;
                sym.transitions += out.transitions;
                sym.elapsed += out.elapsed;
                sym.decided.splice(0..0, out.decided);
                return sym;
            }
            out.decided.extend(sym.decided);
        }
    }
    out
}

/// Explores one cluster explicitly; whether it went part by part.
fn explicit_cluster(
    w: &Whole<'_>,
    cluster: &[ServiceId],
    method: Method,
    budget: &mut Limits,
    out: &mut Analysis,
) -> bool {
    let default = matches!(method, Method::Auto | Method::Explicit);
    if default && first_try_whole(w, cluster, budget, out) {
        return false;
    }
    if (default || method == Method::PartsFirst) && explore_parts(w, cluster, budget, out) {
        return true;
    }
    let sys = System::new(w.c, w.b, cluster, false);
    let sys = match method {
        Method::Exhaustive => sys,
        Method::StubbornOnly => sys.with_stubborn_sets_only(),
        _ => sys.with_reduction(),
    };
    explore_cluster(&sys, w.prefix, w.global, budget, out);
    false
}

/// Explores one cluster with BDDs until `deadline` (and `budget`'s memory
/// bound); `None` when the symbolic layout refuses the cluster.
fn symbolic_cluster(
    w: &Whole<'_>,
    cluster: &[ServiceId],
    deadline: Option<Instant>,
    budget: &Limits,
) -> Option<Analysis> {
    let sys = System::new(w.c, w.b, cluster, false);
    let limits = SymbolicLimits {
        strategy: Strategy::Chained,
        deadline,
        max_bytes: budget.max_bytes,
        ..SymbolicLimits::default()
    };
    let mut out = Analysis::default();
    crate::symbolic::analyse_cluster(&sys, w.prefix, w.global, limits, &mut out).ok()?;
    record(&mut out, cluster, Decider::Symbolic);
    Some(out)
}

/// Records that `method` decided `cluster`, with the states and the
/// completeness of `out`, the cluster's own analysis.
fn record(out: &mut Analysis, cluster: &[ServiceId], method: Decider) {
    out.decided.push(Decided {
        services: cluster.to_vec(),
        method,
        states: out.states,
        complete: out.stopped.is_none(),
    });
}
