//! The WCET side file of a timed component: one `OWNER.STATE DURATION`
//! line per codel (docs/genom3.md, "WCET side file").

use std::fmt::Write as _;

use super::config::Genom3Config;
use super::plan::Plan;
use crate::rng::SplitMix;

/// Every codel the WCET file names, as (owner, state): the permanent
/// codels of each task, then per service its `validate`, its function
/// codels (`codel`, `codel2`, ...) and its activity states.
pub(crate) fn entries(plan: &Plan) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for t in &plan.tasks {
        if let Some(fsm) = &t.fsm {
            out.extend(fsm.states.iter().map(|s| (t.name.clone(), s.clone())));
        }
    }
    for s in &plan.services {
        if s.validate.is_some() {
            out.push((s.name.clone(), "validate".into()));
        }
        for k in 0..s.codels.len() {
            let state = if k == 0 {
                "codel".to_owned()
            } else {
                format!("codel{}", k + 1)
            };
            out.push((s.name.clone(), state));
        }
        if let Some(fsm) = &s.fsm {
            out.extend(fsm.states.iter().map(|st| (s.name.clone(), st.clone())));
        }
    }
    out
}

/// Every entry with the task that runs it (`None`: the control thread).
fn owners(plan: &Plan) -> Vec<((String, String), Option<usize>)> {
    let task_of = |owner: &str| {
        plan.tasks.iter().position(|t| t.name == owner).or_else(|| {
            plan.services
                .iter()
                .find(|s| s.name == owner)
                .and_then(|s| s.task)
        })
    };
    entries(plan)
        .into_iter()
        .map(|(owner, state)| {
            let control = state == "validate" || state.starts_with("codel");
            let task = if control { None } else { task_of(&owner) };
            ((owner, state), task)
        })
        .collect()
}

/// The WCET file. Each entry gets between half and all of its share (at
/// least 1 us). With `load` at most 1, the share is `load` times the
/// shortest period divided among all entries, so the WCETs sum to at most
/// `load` shortest periods. Above 1, a task's codels share `load` times
/// the task's own period, each capped at 9/10 of that period (no codel
/// longer than its period, which would be `codel-overrun` rather than
/// `thread-overrun`), and control codels keep the first rule.
pub(crate) fn wcet_file(plan: &Plan, cfg: &Genom3Config) -> String {
    let mut r = SplitMix::new(cfg.seed ^ 0x3C37_3C37_3C37_3C37);
    let period_us = |t: usize| plan.tasks[t].period_ms.unwrap_or(10) * 1000;
    let shortest = (0..plan.tasks.len()).map(period_us).min().unwrap_or(10_000);
    let owners = owners(plan);
    let load = cfg.load.max(0.0);
    let per_task = |t: usize| owners.iter().filter(|(_, o)| *o == Some(t)).count().max(1);
    let mut out = format!(
        "# WCETs of the generated component `{}` (seed {}, load {}): OWNER.STATE DURATION\n",
        plan.name, cfg.seed, cfg.load
    );
    for ((owner, state), task) in &owners {
        #[allow(clippy::cast_precision_loss)]
        let (share, cap) = match task {
            Some(t) if load > 1.0 => (
                period_us(*t) as f64 * load / per_task(*t) as f64,
                period_us(*t) as f64 * 0.9,
            ),
            _ => (
                shortest as f64 * load / owners.len().max(1) as f64,
                f64::INFINITY,
            ),
        };
        #[allow(clippy::cast_precision_loss)]
        let scale = (50 + r.below(51)) as f64 / 100.0;
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let us = ((share * scale).min(cap) as u64).max(1);
        let _ = writeln!(out, "{owner}.{state} {us}us");
    }
    out
}
