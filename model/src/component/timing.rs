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

/// How many times the longest period or WCET of the services it is
/// explored with a looping service's max-time may be for its watchdog to be
/// timed exactly (docs/semantics.md, "Watchdogs of looping services").
pub const WATCHDOG_EXACT_FACTOR: u64 = 64;

/// Beyond that, the watchdog fires at any time from this many times the
/// longest period or WCET on (a sound over-approximation).
pub const WATCHDOG_HORIZON_FACTOR: u64 = 4;

impl Component {
    /// The longest period or WCET of `members` (0 when they have neither).
    fn longest_constant_ns(&self, members: &[ServiceId]) -> u64 {
        let mut longest = 0u64;
        for &s in members {
            let svc = &self.services[s];
            let period = svc
                .thread
                .and_then(|t| self.threads[t.id].period)
                .map_or(0, |p| p.ns);
            let wcet = svc
                .codels
                .iter()
                .chain(&svc.control)
                .filter_map(|&k| self.codels[k].wcet.map(|w| w.ns))
                .max()
                .unwrap_or(0);
            longest = longest.max(period).max(wcet);
        }
        longest
    }

    /// When the watchdog of service `s` (with a max-time), explored with
    /// `members`, fires in the timed models: `(instant, exact)`, in
    /// nanoseconds after the acknowledgment. Exactly at the max-time
    /// (`exact`), except for a looping service whose max-time is more than
    /// [`WATCHDOG_EXACT_FACTOR`] times the longest period or WCET of
    /// `members`: its watchdog fires at any time from
    /// [`WATCHDOG_HORIZON_FACTOR`] times that constant on (timing it
    /// exactly would unroll every period until its max-time).
    pub fn watchdog_instant_ns(
        &self,
        s: ServiceId,
        looping: bool,
        members: &[ServiceId],
    ) -> (u64, bool) {
        let max = self.services[s].max_time.map_or(0, |m| m.ns);
        let longest = self.longest_constant_ns(members);
        if !looping || longest == 0 || max <= longest.saturating_mul(WATCHDOG_EXACT_FACTOR) {
            return (max, true);
        }
        (longest.saturating_mul(WATCHDOG_HORIZON_FACTOR), false)
    }

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
