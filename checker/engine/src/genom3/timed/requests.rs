//! Which requests the timed GenoM3 model explores
//! (`docs/genom3-semantics.md` 15.5): the control codels of each function
//! and attribute that some task's codel contends, the request that stands
//! for others whose runs are the same or among its own
//! ("Interchangeable requests"), and the requests that change nothing a
//! task sees when they could run at once ("Quiet requests").

use std::collections::BTreeMap;

use genom_model::component::{Idx, ServiceId};

use super::locks;
use crate::genom3::machine::{Control, ControlKind, Machine};

/// Whether a control service's request has no effect but its codels: it
/// is [`anonymous`] and interrupts nothing.
fn inert(ctl: &Control, tracked: &[u64]) -> bool {
    anonymous(ctl, tracked) && ctl.interrupts.is_empty()
}

/// Whether a control service's request is known by its codels and its
/// interruptions alone: a plain function or attribute (not a built-in)
/// that no `after`/`before` names (`tracked`: the completions some step
/// reads), so that no step reads which service it was.
fn anonymous(ctl: &Control, tracked: &[u64]) -> bool {
    let sid = ctl.service.index();
    let watched = tracked[sid / 64] >> (sid % 64) & 1 == 1;
    ctl.kind == ControlKind::Plain && !watched
}

/// A control service of a request kind, with its contended codels' WCETs.
type Member = (usize, Vec<Option<i64>>);

/// For each control service, the one of the group (`ctls`) that stands
/// for it in requests (docs/genom3-semantics.md 15.5, "Interchangeable
/// requests"). Both are [`anonymous`], admitted under the same
/// `after`/`before` services, interrupt the same activities, and run
/// contended codels that wait for and make wait the same codels and can
/// throw alike; and, phase by phase, the one standing for the other has
/// the same WCET (`dominate` false: their runs are the same), or a WCET
/// at least as long (`dominate`: every run of the other is one of its
/// own, its codels taking the other's durations). Each stands for itself
/// or for one that stands for itself.
pub(super) fn canonical_calls(
    m: &Machine<'_>,
    locks: &locks::Locks,
    jobs: &BTreeMap<ServiceId, Vec<usize>>,
    tracked: &[u64],
    ctls: &[bool],
    dominate: bool,
) -> Vec<u16> {
    // Per request kind, its services with their codels' WCETs.
    let mut kinds: BTreeMap<_, Vec<Member>> = BTreeMap::new();
    let mut canon: Vec<u16> = (0..m.controls.len()).map(|k| k as u16).collect();
    for (k, ctl) in m.controls.iter().enumerate() {
        let sid = ctl.service;
        if !ctls[k] || !anonymous(ctl, tracked) {
            continue;
        }
        let keys = jobs.get(&sid).into_iter().flatten().filter_map(|&i| {
            let key = locks.ctl_key(sid, i)?;
            Some((i, key))
        });
        let (mut codels, mut wcets) = (Vec::new(), Vec::new());
        for (i, key) in keys {
            let (excl, waited_by, upper, lower) = locks.signature(key);
            let exact = (!dominate).then_some(upper);
            codels.push((excl, waited_by, exact, lower, ctl_copy(m, sid, i)));
            wcets.push(upper);
        }
        let mut interrupts = ctl.interrupts.clone();
        interrupts.sort_unstable();
        let admission = (m.after.get(&sid).cloned(), m.before.get(&sid).cloned());
        kinds
            .entry((codels, interrupts, admission))
            .or_default()
            .push((k, wcets));
    }
    let covers = |a: &[Option<i64>], b: &[Option<i64>]| {
        a.iter()
            .zip(b)
            .all(|(x, y)| x.unwrap_or(0) >= y.unwrap_or(0))
    };
    for members in kinds.values() {
        // The maximal members, the first of equals: each stands for itself.
        let maximal: Vec<&Member> = members
            .iter()
            .enumerate()
            .filter(|&(n, (_, w))| {
                !members
                    .iter()
                    .enumerate()
                    .any(|(o, (_, v))| covers(v, w) && (!covers(w, v) || o < n))
            })
            .map(|(_, x)| x)
            .collect();
        for (k, w) in members {
            if let Some(&&(j, _)) = maximal.iter().find(|(_, v)| covers(v, w)) {
                canon[*k] = j as u16;
            }
        }
    }
    canon
}

/// Whether the `i`-th control codel of service `sid` is an attribute's ids
/// copy (it throws nothing).
pub(crate) fn ctl_copy(m: &Machine<'_>, sid: ServiceId, i: usize) -> bool {
    m.control_codels
        .get(&sid)
        .and_then(|v| v.get(i))
        .is_some_and(|c| c.codel.is_none())
}

/// For each control service whose request does nothing but run one
/// contended control codel that takes no time and cannot throw (an
/// attribute's ids copy, for one): that codel's key.
pub(super) fn quiet_calls(
    m: &Machine<'_>,
    locks: &locks::Locks,
    jobs: &BTreeMap<ServiceId, Vec<usize>>,
    tracked: &[u64],
) -> Vec<Option<usize>> {
    m.controls
        .iter()
        .map(|ctl| {
            let sid = ctl.service;
            let &[i] = jobs.get(&sid)?.as_slice() else {
                return None;
            };
            let key = locks.ctl_key(sid, i)?;
            let copy = ctl_copy(m, sid, i);
            (inert(ctl, tracked) && copy && locks.wcet_of(key) == Some(0)).then_some(key)
        })
        .collect()
}
