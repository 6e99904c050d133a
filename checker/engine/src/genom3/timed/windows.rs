//! Per codel of a periodic task, the latest end of its execution after
//! the tick of its wake-up, as the timed exploration reaches it: the
//! largest value the task's period clock takes while the codel runs, over
//! every reachable state (stored zones are closed under the passing of
//! time, so the largest value is the latest instant the codel still runs,
//! its end at the latest). A functional layer's chains
//! (`genom-system`, docs/functional-layer.md) use these windows instead of
//! whole periods.
//!
//! Sound only for tasks that never overrun (then a running codel belongs
//! to the wake-up whose tick last reset the clock); the exploration is
//! the timed model's without the reductions that merge requests, group by
//! group, and gives nothing when a group does not finish or some task can
//! overrun.

use std::collections::BTreeMap;

use super::groups::groups;
use super::locks::Locks;
use super::{TG3State, TimedEngine, unit_ns};
use crate::genom3::machine::{Machine, Owner};
use crate::kernel::explore::{Found, Limits, explore_until};
use crate::zones::dbm::{INF, constant};

/// The latest end after its tick, in nanoseconds, of each codel (its
/// owner and state in [`Machine::fsm`]) of the periodic tasks of `m` that
/// runs in some reachable state; `None` when an exploration stops early,
/// a task can overrun, or a running codel's clock is unbounded.
pub fn codel_windows(m: &Machine<'_>, limits: Limits) -> Option<BTreeMap<(Owner, u8), u64>> {
    if m.tasks.len() > super::MAX_TASKS {
        return None;
    }
    let unit = unit_ns(m);
    let locks = Locks::new(m, unit);
    let mut latest: BTreeMap<(Owner, u8), i64> = BTreeMap::new();
    for group in groups(m, &locks) {
        let te = TimedEngine::with_locks(m.clone(), &group, locks.clone())?;
        let periodic: Vec<(usize, usize)> = te
            .periodic_tasks()
            .filter_map(|t| te.period_clock[t].map(|c| (t, c)))
            .collect();
        let mut broken = false;
        let e = explore_until(&te, limits, |_, st: &TG3State| {
            if st.violation.is_some() {
                broken = true;
                return Found::All;
            }
            for &(t, clock) in &periodic {
                let Some((who, inst)) = te.running(&st.g, t) else {
                    continue;
                };
                let upper = st.zone.get(clock, 0);
                if upper == INF {
                    broken = true;
                    return Found::All;
                }
                let slot = latest.entry((who.owner(), inst.state)).or_insert(0);
                *slot = (*slot).max(constant(upper));
            }
            Found::Open
        });
        if broken || e.stopped.is_some() {
            return None;
        }
    }
    Some(
        latest
            .into_iter()
            .map(|(k, v)| (k, u64::try_from(v).unwrap_or(0).saturating_mul(unit)))
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::load_genom3_wcet;

    /// One task of period 4 ms running `k0` (1 ms) then `k1` (2 ms) in
    /// every wake-up: `k0` ends at most 1 ms after the tick, `k1` 3 ms.
    #[test]
    fn a_codel_ends_after_those_before_it() {
        let c = load_genom3_wcet(
            "component c {\n  task t {\n    period 4 ms;\n    codel<start> s() yield k0;\n    codel<k0> f0() yield k1;\n    codel<k1> f1() yield pause::k0;\n  };\n};\n",
            "t.start 0ms\nt.k0 1ms\nt.k1 2ms\n",
        );
        let m = Machine::new(&c, 1).expect("GenoM3");
        let w = codel_windows(&m, Limits::default()).expect("explored");
        let fsm = m.fsm(Owner::Task(0));
        let at = |name: &str| -> u64 {
            let s = fsm
                .states
                .iter()
                .position(|s| s.name == name)
                .expect("state");
            w[&(Owner::Task(0), u8::try_from(s).expect("small"))]
        };
        assert_eq!(at("k0"), 1_000_000);
        assert_eq!(at("k1"), 3_000_000);
    }

    /// A task that can overrun gives no windows.
    #[test]
    fn an_overrun_gives_none() {
        let c = load_genom3_wcet(
            "component c {\n  task t {\n    period 2 ms;\n    codel<start> s() yield k0;\n    codel<k0> f0() yield k1;\n    codel<k1> f1() yield pause::k0;\n  };\n};\n",
            "t.start 0ms\nt.k0 1ms\nt.k1 2ms\n",
        );
        let m = Machine::new(&c, 1).expect("GenoM3");
        assert!(codel_windows(&m, Limits::default()).is_none());
    }
}
