//! Deadlock detection in one state: a cycle of pending instances that
//! block each other through `delays`, none of which a watchdog can end
//! (read by [`super::analysis`] on every new state).

use genom_model::component::ServiceId;

use super::system::{Config, System};

/// Services of a cycle of pending instances blocking each other through
/// `delays`, none of which a watchdog can end.
pub(super) fn pending_cycle(sys: &System<'_>, cfg: &Config) -> Option<Vec<ServiceId>> {
    if cfg.main.len() <= 64 {
        pending_cycle_small(sys, cfg)
    } else {
        pending_cycle_any(sys, cfg)
    }
}

/// [`pending_cycle`] with at most 64 members: the relation as bit masks
/// (no allocation unless there is a cycle).
pub(super) fn pending_cycle_small(sys: &System<'_>, cfg: &Config) -> Option<Vec<ServiceId>> {
    let n = cfg.main.len();
    let node =
        |i: usize| cfg.pending[i].is_some() && !sys.machine_of(i).watchdog && !sys.is_input(i);
    let mut reach = [0u64; 64];
    let mut any = false;
    for i in (0..n).filter(|&i| node(i)) {
        for (t, d) in sys.blockers_iter(cfg, i) {
            if d && node(t) {
                reach[i] |= 1 << t;
                any = true;
            }
        }
    }
    if !any {
        return None;
    }
    // Transitive closure (Warshall): bit j of reach[i] when a path of at
    // least one edge leads from i to j.
    for k in 0..n {
        for i in 0..n {
            if reach[i] >> k & 1 == 1 {
                reach[i] |= reach[k];
            }
        }
    }
    let first = (0..n).find(|&i| reach[i] >> i & 1 == 1)?;
    let mut cycle: Vec<ServiceId> = (0..n)
        .filter(|&j| reach[j] >> j & 1 == 1)
        .filter(|&j| reach[first] >> j & 1 == 1 && reach[j] >> first & 1 == 1)
        .map(|j| sys.service(j))
        .collect();
    cycle.sort();
    Some(cycle)
}

/// [`pending_cycle`] with any number of members.
pub(super) fn pending_cycle_any(sys: &System<'_>, cfg: &Config) -> Option<Vec<ServiceId>> {
    let n = cfg.main.len();
    let node =
        |i: usize| cfg.pending[i].is_some() && !sys.machine_of(i).watchdog && !sys.is_input(i);
    let edges: Vec<Vec<usize>> = (0..n)
        .map(|i| {
            if !node(i) {
                return Vec::new();
            }
            sys.blockers(cfg, i)
                .into_iter()
                .filter(|&(t, d)| d && node(t))
                .map(|(t, _)| t)
                .collect()
        })
        .collect();
    let reach = |from: usize| {
        let mut seen = vec![false; n];
        let mut stack = edges[from].clone();
        while let Some(x) = stack.pop() {
            if !std::mem::replace(&mut seen[x], true) {
                stack.extend(edges[x].iter().copied());
            }
        }
        seen
    };
    let closure: Vec<Vec<bool>> = (0..n).map(reach).collect();
    let on_cycle: Vec<usize> = (0..n).filter(|&i| closure[i][i]).collect();
    let first = *on_cycle.first()?;
    let mut cycle: Vec<ServiceId> = on_cycle
        .iter()
        .filter(|&&j| closure[first][j] && closure[j][first])
        .map(|&j| sys.service(j))
        .collect();
    cycle.sort();
    Some(cycle)
}
