//! The time unit, as the engine computes it: the GCD of the durations of
//! the component, and the timed clusters the watchdogs are measured in.

use genom_model::component::{Component, ServiceId};

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// The engine's time unit for a set of services (`timed::clocks::unit_ns`).
pub(super) fn unit_ns(c: &Component, services: &[ServiceId]) -> u64 {
    let mut g = 0;
    for &s in services {
        let svc = &c.services[s];
        if let Some(t) = svc.thread.and_then(|t| c.threads[t.id].period) {
            g = gcd(g, t.ns);
        }
        if let Some(m) = svc.max_time.filter(|_| svc.start.is_some()) {
            g = gcd(g, m.ns);
        }
        for &k in &svc.codels {
            if let Some(w) = c.codels[k].wcet {
                g = gcd(g, w.ns);
            }
        }
    }
    g.max(1)
}

pub(super) fn units(ns: u64, unit: u64) -> i64 {
    i64::try_from(ns / unit.max(1)).unwrap_or(i64::MAX / 4)
}

/// For each service (by index), the services its timed cluster
/// (`Component::timed_clusters`) is explored with: the cluster, plus the
/// init service.
pub(super) fn cluster_of(c: &Component) -> Vec<Vec<ServiceId>> {
    let root = c.timed_cluster_roots();
    let clusters = c.timed_clusters();
    let init = c.init_service();
    root.iter()
        .map(|&r| {
            let mut members = clusters
                .iter()
                .find(|m| m.first().is_some_and(|s| s.0 as usize == r))
                .cloned()
                .unwrap_or_default();
            if let Some(s) = init.filter(|s| !members.contains(s)) {
                members.push(s);
                members.sort();
            }
            members
        })
        .collect()
}
