//! Exploring a GenoM3 component part by part. Two services influence each
//! other only through `after`/`before` (the flags of completed services)
//! and `interrupts` (flags and the wait of the interrupter); the built-in
//! `kill` and `abort_activity` reach every activity and are in every part.
//! A part is a connected component of that relation; the permanent
//! activities of the tasks form one more part. No step of one part
//! enables or disables a step of another (slots are per activity, and a
//! full task pool only refuses requests), so the states a part reaches
//! alone are exactly the projections of the states the whole component
//! reaches: the verdicts on its services and codels are the same, and a
//! part's trace, after the boot steps of the permanent activities, is a
//! trace of the whole component.

use std::collections::BTreeMap;

use genom_model::component::{Idx, ServiceId};

use super::machine::{Machine, Role};

/// The services requested in one exploration.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Part {
    /// Per activity: requested.
    pub acts: Vec<bool>,
    /// Per control service: requested.
    pub ctls: Vec<bool>,
    /// Whether the permanent activities run (the part of the tasks).
    pub perms: bool,
}

/// The parts of a machine: the permanent activities first (when a task has
/// some), then one part per group of linked services, in service order.
pub fn parts(m: &Machine<'_>) -> Vec<Part> {
    let n = m.c.services.len();
    let mut root: Vec<usize> = (0..n).collect();
    let global = |sid: ServiceId| match m.role.get(&sid) {
        Some(Role::Control(k)) => m.controls[*k].builtin,
        _ => false,
    };
    let mut link = |a: ServiceId, b: ServiceId| {
        if !global(a) && !global(b) {
            let (ra, rb) = (find(&mut root, a.index()), find(&mut root, b.index()));
            root[ra.max(rb)] = ra.min(rb);
        }
    };
    for (sid, deps) in m.after.iter().chain(m.before.iter()) {
        for &d in deps {
            link(*sid, d);
        }
    }
    for a in &m.activities {
        for &t in &a.interrupts {
            link(a.service, m.activities[t].service);
        }
    }
    for k in &m.controls {
        for &t in &k.interrupts {
            link(k.service, m.activities[t].service);
        }
    }
    let mut groups: BTreeMap<usize, Part> = BTreeMap::new();
    let base = Part {
        acts: vec![false; m.activities.len()],
        ctls: m.controls.iter().map(|k| k.builtin).collect(),
        perms: false,
    };
    for (sid, role) in &m.role {
        if global(*sid) {
            continue;
        }
        let g = groups
            .entry(find(&mut root, sid.index()))
            .or_insert_with(|| base.clone());
        match *role {
            Role::Activity(a) => g.acts[a] = true,
            Role::Control(k) => g.ctls[k] = true,
        }
    }
    let mut out = Vec::new();
    if m.tasks.iter().any(|t| t.perm.is_some()) {
        out.push(Part {
            perms: true,
            ..base.clone()
        });
    }
    out.extend(groups.into_values());
    if out.is_empty() {
        out.push(base);
    }
    out
}

fn find(root: &mut [usize], mut x: usize) -> usize {
    while root[x] != x {
        root[x] = root[root[x]];
        x = root[x];
    }
    x
}
