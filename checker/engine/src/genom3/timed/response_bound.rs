//! A static bound on the response time of a function or attribute
//! (docs/genom3-semantics.md 16.8), for when the response-time
//! exploration stops on a limit: each of its control codels runs at most
//! its WCET after waiting, if it waits for locks at all, at most for one
//! contended codel of every task.
//!
//! The wait is the *share* argument of the static wake-up bound (15.12)
//! without its periods: a control codel that cannot begin takes a ticket
//! in GenoM3's resource FIFO; from then on no codel begins before it but
//! those running or queued ahead, at most one per task, each a contended
//! codel that runs at most its WCET. That holds whether tasks overrun or
//! not (the response-time exploration coalesces overrunning ticks, 16.4),
//! so no share is capped at a period here.

use genom_model::component::ServiceId;

use super::bound::longest_contended;
use super::locks::Locks;
use super::unit_ns;
use crate::genom3::machine::Machine;

/// The most service `sid`'s control codels can take, in nanoseconds, in
/// the timed model of `m` (`locks` in the units of [`unit_ns`]): per
/// codel its WCET, plus, for one that waits for some lock, the sum of
/// every task's longest contended codel. `None` when it overflows.
pub fn control_bound(m: &Machine<'_>, locks: &Locks, sid: ServiceId) -> Option<u64> {
    let Some(codels) = m.control_codels.get(&sid) else {
        return Some(0);
    };
    let shares = longest_contended(m, locks);
    let tasks = shares
        .get(..m.tasks.len())?
        .iter()
        .try_fold(0i64, |a, &w| a.checked_add(w))?;
    let mut total = 0i64;
    for i in 0..codels.len() {
        let k = locks.ctl_key(sid, i)?;
        let wait = if locks.waits_for(k).is_empty() {
            0
        } else {
            tasks
        };
        total = total.checked_add(locks.wcet_of(k)?)?.checked_add(wait)?;
    }
    u64::try_from(total).ok()?.checked_mul(unit_ns(m))
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::*;
    use crate::genom3::timed::response::analyse_responses;
    use crate::kernel::explore::Limits;
    use crate::timed::Worst;

    /// Every function's and attribute's worst case that a finished
    /// exploration computes, beside its static bound and its codels' own
    /// WCETs: `(exact, bound, own)` in ns.
    fn pairs(c: &genom_model::component::Component) -> Vec<(u64, u64, u64)> {
        let m = Machine::new(c, 1).expect("GenoM3");
        let locks = Locks::new(&m, unit_ns(&m));
        let limits = Limits {
            max_states: 50_000,
            ..Limits::default()
        };
        let Some(r) = analyse_responses(&m, limits, &BTreeMap::new()) else {
            return Vec::new();
        };
        if r.stopped.is_some() {
            return Vec::new();
        }
        r.found
            .iter()
            .filter(|s| {
                m.controls
                    .iter()
                    .any(|k| k.service == s.service && !k.builtin)
            })
            .filter_map(|s| {
                let (Worst::Exact(exact) | Worst::Above(exact)) = s.worst else {
                    return None;
                };
                let own = m.control_codels.get(&s.service).into_iter().flatten();
                let own = own.map(|st| st.wcet_ns.unwrap_or(0)).sum();
                Some((exact, control_bound(&m, &locks, s.service)?, own))
            })
            .collect()
    }

    #[test]
    fn the_static_bound_is_never_below_the_explored_worst_case() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/fixtures/genom3");
        let mut components = Vec::new();
        for sub in ["response", "timing"] {
            let mut files: Vec<_> = std::fs::read_dir(format!("{dir}/{sub}"))
                .unwrap()
                .map(|e| e.unwrap().path())
                .filter(|p| p.extension().is_some_and(|x| x == "gen"))
                .collect();
            files.sort();
            for f in files {
                let text = std::fs::read_to_string(&f).unwrap();
                let wcet = std::fs::read_to_string(f.with_extension("wcet")).unwrap();
                components.push(crate::testing::load_genom3_wcet(&text, &wcet));
            }
        }
        for seed in 0..100 {
            let mut cfg = genom_generate::Genom3Config::small(seed);
            cfg.timed = true;
            let g = genom_generate::generate_genom3(&cfg);
            let wcet = g.wcet.clone().unwrap_or_default();
            components.push(crate::testing::load_genom3_wcet(&g.r#gen, &wcet));
        }
        let (mut compared, mut waited) = (0, 0);
        for c in &components {
            for (exact, bound, own) in pairs(c) {
                assert!(bound >= exact, "{}: bound {bound} < {exact}", c.name.name);
                compared += 1;
                // A worst case above the codels' own WCETs waited for locks.
                waited += usize::from(exact > own);
            }
        }
        assert!(compared >= 30, "{compared} worst cases compared");
        assert!(waited >= 5, "{waited} of them waited for locks");
    }
}
