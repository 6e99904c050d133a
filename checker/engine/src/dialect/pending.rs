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
    pending_cycle_bits(sys, cfg).map(|set| cycle_services(sys, set))
}

/// The services of the members whose bits are in `set`, sorted.
pub(super) fn cycle_services(sys: &System<'_>, set: u64) -> Vec<ServiceId> {
    let mut cycle: Vec<ServiceId> = bits(set).map(|j| sys.service(j)).collect();
    cycle.sort();
    cycle
}

/// The indices of the bits set in `set`, ascending.
fn bits(mut set: u64) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        let j = set.trailing_zeros();
        set &= set.wrapping_sub(1);
        (j < 64).then_some(j as usize)
    })
}

/// [`pending_cycle_small`] as the bits of the cycle's members (at most 64
/// members): the pending members that may be on a cycle, each with an edge
/// to the pending members among its `delayers`; `None` at once when fewer
/// than two of them or no edge.
pub(super) fn pending_cycle_bits(sys: &System<'_>, cfg: &Config) -> Option<u64> {
    let pending = (cfg.pending.iter().enumerate())
        .filter(|(_, p)| p.is_some())
        .fold(0u64, |set, (i, _)| set | 1 << i);
    let nodes = pending & sys.cycle_members();
    if nodes.count_ones() < 2 {
        return None;
    }
    let mut reach = [0u64; 64];
    let mut any = false;
    for i in bits(nodes) {
        reach[i] = sys.delayer_bits(i) & nodes;
        any |= reach[i] != 0;
    }
    if !any {
        return None;
    }
    // Transitive closure (Warshall) over the nodes: bit j of reach[i] when
    // a path of at least one edge leads from i to j.
    for k in bits(nodes) {
        for i in bits(nodes) {
            if reach[i] >> k & 1 == 1 {
                reach[i] |= reach[k];
            }
        }
    }
    let first = bits(nodes).find(|&i| reach[i] >> i & 1 == 1)?;
    let set = bits(nodes)
        .filter(|&j| reach[j] >> j & 1 == 1)
        .filter(|&j| reach[first] >> j & 1 == 1 && reach[j] >> first & 1 == 1)
        .fold(0u64, |set, j| set | 1 << j);
    Some(set)
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
