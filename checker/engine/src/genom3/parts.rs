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

use genom_model::component::{Idx, ServiceId};

use super::machine::{Machine, Role};
use crate::kernel::parts::Links;

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
    let global = |sid: ServiceId| match m.role.get(&sid) {
        Some(Role::Control(k)) => m.controls[*k].builtin,
        _ => false,
    };
    let mut links = Links::new(m.c.services.len());
    let mut link = |a: ServiceId, b: ServiceId| {
        if !global(a) && !global(b) {
            links.link(a.index(), b.index());
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
    let base = Part {
        acts: vec![false; m.activities.len()],
        ctls: m.controls.iter().map(|k| k.builtin).collect(),
        perms: false,
    };
    let mut out = Vec::new();
    if m.tasks.iter().any(|t| t.perm.is_some()) {
        out.push(Part {
            perms: true,
            ..base.clone()
        });
    }
    let requested = m.role.keys().filter(|s| !global(**s)).map(|s| s.index());
    for services in links.parts(requested) {
        let mut g = base.clone();
        for s in services {
            match m.role.get(&<ServiceId as Idx>::new(s)) {
                Some(Role::Activity(a)) => g.acts[*a] = true,
                Some(Role::Control(k)) => g.ctls[*k] = true,
                None => {}
            }
        }
        out.push(g);
    }
    if out.is_empty() {
        out.push(base);
    }
    out
}
