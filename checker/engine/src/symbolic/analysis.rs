//! The symbolic engine as a method of the analysis: one cluster's
//! reachable set is computed with BDDs, and its verdicts are handed to the
//! explicit analysis's own reading (`engine::analysis::visit` and
//! `collect`), so that the diagnostics, their wording and their traces are
//! the explicit engine's.
//!
//! Each verdict of the reachable set comes with a witness configuration
//! and a shortest explicit path to it ([`Symbolic::trace_to`]); the
//! explicit reading is run on those configurations only (the initial one,
//! one per deadlock, starvation, unbounded interrupt and never-started
//! pending service), and the codels reached and services started are the
//! reachable set's. Every trace is then replayed in the whole component,
//! after the initialisation prefix, as the explicit engine's are.

use super::{Refusal, Symbolic, SymbolicLimits};
use crate::dialect::analysis::{Analysis, Found, collect_cluster, visit};
use crate::dialect::system::{Action, Config, System};
use crate::kernel::explore::Stop;
use crate::kernel::store::StateId;

/// Explores the cluster `sys` (after initialisation, reached by `prefix`
/// in the whole component `global`) symbolically within `limits`, and adds
/// its verdicts and figures to `out`. A limit (during the exploration or
/// the reading of its verdicts) leaves the cluster's services unproven and
/// establishes nothing about them. `Err` when the symbolic layout refuses
/// the cluster (nothing is added).
pub(crate) fn analyse_cluster(
    sys: &System<'_>,
    prefix: &[Action],
    global: &System<'_>,
    limits: SymbolicLimits,
    out: &mut Analysis,
) -> Result<(), Refusal> {
    let sym = match Symbolic::new_until(sys, limits.deadline) {
        Ok(sym) => sym,
        Err(Refusal::OutOfTime) => {
            unproven(sys, Stop::Time, out);
            return Ok(());
        }
        Err(refusal) => return Err(refusal),
    };
    let reach = sym.reach(limits);
    out.states += u64::try_from(reach.states()).unwrap_or(u64::MAX);
    out.elapsed += reach.elapsed;
    let verdicts = match reach.stopped {
        None => sym.verdicts_until(&reach, true, limits.deadline),
        // Reading a part of the reachable set costs as much as reading it
        // all, and proves nothing negative: the cluster stays unproven.
        Some(_) => None,
    };
    let Some(verdicts) = verdicts else {
        unproven(sys, reach.stopped.unwrap_or(Stop::Time), out);
        return Ok(());
    };
    let mut paths: Vec<Vec<Action>> = vec![Vec::new()];
    paths.extend(verdicts.deadlocks.iter().map(|d| d.path.clone()));
    paths.extend(verdicts.starvations.values().cloned());
    paths.extend(verdicts.unbounded.values().cloned());
    let mut witnesses: Vec<(Vec<Action>, Config)> = paths
        .into_iter()
        .filter_map(|p| Some((p.clone(), walk(sys, &sym.init, &p)?)))
        .collect();
    for i in 0..sys.len() {
        let s = sys.service(i);
        if verdicts.pending.contains(&s) && !verdicts.started.contains(&s) {
            witnesses.extend(sym.pending_witness(&reach, i));
        }
    }
    let mut found = Found::default();
    for (id, (_, cfg)) in (0..).zip(&witnesses) {
        visit(sys, id, cfg, &mut found);
    }
    found.reached.extend(verdicts.reached.iter().copied());
    found.started.extend(verdicts.started.iter().copied());
    let at = |id: StateId| witnesses.get(id as usize);
    let config = |id: StateId| at(id).map_or_else(|| sym.init.clone(), |w| w.1.clone());
    let path = |id: StateId| at(id).map(|w| w.0.clone()).unwrap_or_default();
    collect_cluster(sys, (prefix, global), (&config, &path), &found, out);
    Ok(())
}

/// A limit (`stop`) left the cluster `sys` unproven: nothing is established
/// about its services.
fn unproven(sys: &System<'_>, stop: Stop, out: &mut Analysis) {
    out.stopped = out.stopped.or(Some(stop));
    out.unproven.extend(sys.services());
}

/// The configuration `path` leads to from `init`, by the explicit rules.
fn walk(sys: &System<'_>, init: &Config, path: &[Action]) -> Option<Config> {
    path.iter()
        .try_fold(init.clone(), |cfg, &a| sys.apply(&cfg, a, &mut None))
}
