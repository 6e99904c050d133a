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

/// The WCET file: every entry gets between half and all of its share of
/// `load` times the shortest period (at least 1 us), so the WCETs sum to
/// at most `load` shortest periods.
pub(crate) fn wcet_file(plan: &Plan, cfg: &Genom3Config) -> String {
    let mut r = SplitMix::new(cfg.seed ^ 0x3C37_3C37_3C37_3C37);
    let shortest = plan
        .tasks
        .iter()
        .filter_map(|t| t.period_ms)
        .min()
        .unwrap_or(10);
    let entries = entries(plan);
    #[allow(clippy::cast_precision_loss)]
    let share = (shortest * 1000) as f64 * cfg.load.max(0.0) / entries.len().max(1) as f64;
    let mut out = format!(
        "# WCETs of the generated component `{}` (seed {}, load {}): OWNER.STATE DURATION\n",
        plan.name, cfg.seed, cfg.load
    );
    for (owner, state) in entries {
        #[allow(clippy::cast_precision_loss)]
        let scale = (50 + r.below(51)) as f64 / 100.0;
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let us = ((share * scale) as u64).max(1);
        let _ = writeln!(out, "{owner}.{state} {us}us");
    }
    out
}
