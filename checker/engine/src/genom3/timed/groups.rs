//! The timed GenoM3 model explored group by group. Timing couples two tasks
//! when a codel of one waits for a codel of the other (GenoM3's exclusion
//! lists), and GenoM3's resource FIFO (8.3) couples every task that takes
//! tickets (a task with a codel that is not `async`) with every thread
//! that may wait for a lock: its ticket may come behind a waiting one
//! (head-of-line blocking). So as soon as some codel may wait for a lock,
//! the tasks that take tickets form one group. Services couple as in the
//! untimed parts
//! (`after`/`before`, `interrupts`); an activity is coupled to its task. A
//! group is a connected component of those links over tasks and services.
//!
//! Each group is explored with the tasks and services of the group, the
//! built-in `kill` and `abort_activity` (as in the untimed parts), and
//! every function or attribute whose control codels hold a lock that a
//! codel of the group's tasks contends: the control thread then serves
//! only requests that matter to the group. Leaving out the others' requests
//! only removes moments where the control thread is busy elsewhere, which a
//! later request models anyway; the other tasks never hold a lock the
//! group's codels wait for. So every execution of the group alone is the
//! projection of an execution of the whole component, and conversely: a
//! task overruns in its group exactly when it overruns in the component.
//! (Shutdown is the exception the module does not claim exactness for:
//! after `kill`, the permanent stop codels wait for every instance of the
//! component to end, of the group only here.)

use genom_model::component::Idx;

use super::locks::Locks;
use crate::genom3::machine::{ControlKind, Machine};
use crate::kernel::parts::Links;

/// The tasks and services of one timed exploration.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Group {
    /// Per task: in the group.
    pub tasks: Vec<bool>,
    /// Per activity: requested.
    pub acts: Vec<bool>,
    /// Per control service: requested.
    pub ctls: Vec<bool>,
}

/// The groups of `m` that have a periodic task (no other can overrun), in
/// task order.
pub fn groups(m: &Machine<'_>, locks: &Locks) -> Vec<Group> {
    let ns = m.c.services.len();
    let nt = m.tasks.len();
    let mut links = Links::new(ns + nt);
    let builtin = |s: genom_model::component::ServiceId| m.is_builtin(s);
    let mut link = |a: usize, b: usize| links.link(a, b);
    for (sid, deps) in m.after.iter().chain(m.before.iter()) {
        for d in deps.iter().filter(|d| !builtin(**d) && !builtin(*sid)) {
            link(sid.index(), d.index());
        }
    }
    for a in &m.activities {
        link(a.service.index(), ns + a.task);
        for &t in &a.interrupts {
            link(a.service.index(), m.activities[t].service.index());
        }
    }
    for k in m.controls.iter().filter(|k| !k.builtin) {
        for &t in &k.interrupts {
            link(k.service.index(), m.activities[t].service.index());
        }
    }
    for k in 0..locks.len() {
        for &j in locks.waits_for(k) {
            let (t, u) = (locks.key_task[k], locks.key_task[j]);
            if t < nt && u < nt {
                link(ns + t, ns + u);
            }
        }
    }
    // The FIFO: some codel may wait (of a task, or the control thread's for
    // a task's codel); every task taking tickets may queue behind it.
    if (0..locks.len()).any(|k| !locks.waits_for(k).is_empty()) {
        let queued: Vec<usize> = (0..nt).filter(|&t| takes_tickets(locks, t)).collect();
        for w in queued.windows(2) {
            link(ns + w[0], ns + w[1]);
        }
    }
    let mut out: Vec<Group> = Vec::new();
    for part in links.parts(ns..ns + nt) {
        let r = part[0];
        let tasks: Vec<bool> = (0..nt).map(|u| links.same(ns + u, r)).collect();
        if !(0..nt).any(|u| tasks[u] && m.tasks[u].period_ns.is_some()) {
            continue;
        }
        let acts = m
            .activities
            .iter()
            .map(|a| links.same(a.service.index(), r))
            .collect();
        let ctls = (0..m.controls.len())
            .map(|k| {
                let c = &m.controls[k];
                c.builtin
                    || c.kind != ControlKind::Plain
                    || links.same(c.service.index(), r)
                    || contends(m, locks, c.service, &tasks)
            })
            .collect();
        out.push(Group { tasks, acts, ctls });
    }
    out
}

/// Whether a control codel of `sid` and a codel of one of `tasks` exclude
/// each other.
fn contends(
    m: &Machine<'_>,
    locks: &Locks,
    sid: genom_model::component::ServiceId,
    tasks: &[bool],
) -> bool {
    let n = m.control_codels.get(&sid).map_or(0, Vec::len);
    (0..n).filter_map(|i| locks.ctl_key(sid, i)).any(|k| {
        (0..locks.len()).any(|j| {
            let t = locks.key_task[j];
            t < tasks.len() && tasks[t] && (locks.excludes(k, j) || locks.excludes(j, k))
        })
    })
}

/// Whether task `t` has a codel that takes a ticket (one not `async`).
fn takes_tickets(locks: &Locks, t: usize) -> bool {
    (0..locks.len()).any(|k| locks.key_task[k] == t && !locks.is_async(k))
}
