//! Timing facts of a component shared by the timed engine and the exports:
//! whether the component gives timing, lock conflicts between uses of
//! structures, and the timed clusters the zone engine explores one by one.

use super::{Component, ServiceId, StructureId};

/// Whether two uses of structures conflict: a shared structure that one of
/// them writes (LANGUAGE.md section 3).
pub fn uses_conflict(a: &[(StructureId, bool)], b: &[(StructureId, bool)]) -> bool {
    a.iter()
        .any(|&(s, wa)| b.iter().any(|&(t, wb)| s == t && (wa || wb)))
}

impl Component {
    /// Whether the component gives timing: some codel WCET or service
    /// max-time (then the timed engine decides the verdicts).
    pub fn gives_timing(&self) -> bool {
        self.codels.values().any(|k| k.wcet.is_some())
            || self.services.values().any(|s| s.max_time.is_some())
    }

    /// The timed clusters, each sorted, in order of their first service:
    /// the connected components of the `stops`/`delays`/`forbids` relation
    /// *and* of sharing a thread or a lock (timing couples those).
    pub fn timed_clusters(&self) -> Vec<Vec<ServiceId>> {
        let root = self.timed_cluster_roots();
        let mut groups: std::collections::BTreeMap<usize, Vec<ServiceId>> = Default::default();
        for s in self.services.ids() {
            groups.entry(root[s.0 as usize]).or_default().push(s);
        }
        groups.into_values().collect()
    }

    /// For each service (by index), the smallest service index of its timed
    /// cluster.
    pub fn timed_cluster_roots(&self) -> Vec<usize> {
        let mut parent: Vec<usize> = (0..self.services.len()).collect();
        let uses: Vec<Vec<(StructureId, bool)>> = self
            .services
            .values()
            .map(|s| {
                s.codels
                    .iter()
                    .flat_map(|&k| self.codels[k].structures())
                    .collect()
            })
            .collect();
        for (s, svc) in self.services.iter() {
            for r in svc.stops.iter().chain(&svc.delays).chain(&svc.forbids) {
                union(&mut parent, s.0 as usize, r.id.0 as usize);
            }
            for (t, other) in self.services.iter().filter(|&(t, _)| t > s) {
                let same_thread =
                    svc.thread.is_some() && svc.thread.map(|r| r.id) == other.thread.map(|r| r.id);
                if same_thread || uses_conflict(&uses[s.0 as usize], &uses[t.0 as usize]) {
                    union(&mut parent, s.0 as usize, t.0 as usize);
                }
            }
        }
        (0..parent.len()).map(|x| find(&parent, x)).collect()
    }
}

/// The root of `x` in a union-find forest whose roots are the smallest
/// members.
fn find(parent: &[usize], mut x: usize) -> usize {
    while parent[x] != x {
        x = parent[x];
    }
    x
}

/// Joins the trees of `a` and `b`, keeping the smaller root.
fn union(parent: &mut [usize], a: usize, b: usize) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    parent[ra.max(rb)] = ra.min(rb);
}
