//! The codels of the timed GenoM3 model: their durations in model units
//! and GenoM3's exclusion lists (`docs/genom3-semantics.md` 8.1-8.2).
//!
//! An FSM codel of task T *excludes* (waits while another task runs) a
//! codel of another task when their parameters conflict
//! ([`crate::genom3::machine::Access::conflicts`]: same port or remote
//! whatever the directions, overlapping ids member paths with a writer),
//! except a codel of a service that interrupts the first codel's own
//! service (GenoM3's generator leaves those out; the exception is
//! one-sided). Codels of one task never exclude each other, and an `async`
//! codel takes no lock (7.1). Control codels (`validate`, a function's
//! codels) exclude the conflicting FSM codels of every task and are
//! excluded by them; they never exclude each other (one control thread).

use std::collections::BTreeMap;

use genom_model::component::ServiceId;

use crate::genom3::machine::{Fsm, Machine, Owner};

/// Durations and exclusions of every FSM codel, by a dense key.
#[derive(Debug, Clone)]
pub struct Locks {
    /// First key of each activity's states.
    act_base: Vec<usize>,
    /// First key of each task's permanent states.
    perm_base: Vec<usize>,
    /// First key of each service's control codels.
    ctl_base: BTreeMap<ServiceId, usize>,
    /// Per key: upper bound of its duration (`None`: unbounded, `async`).
    upper: Vec<Option<i64>>,
    /// Per key: lower bound of its duration (an `async` codel's WCET).
    lower: Vec<i64>,
    /// Per key: the keys it waits for.
    excl: Vec<Vec<usize>>,
    /// Per key: its task (`usize::MAX` for a control codel).
    pub key_task: Vec<usize>,
}

impl Locks {
    /// Reads the machine's codels, durations in units of `unit` ns.
    pub fn new(m: &Machine<'_>, unit: u64) -> Locks {
        let mut owners: Vec<(Owner, usize, &Fsm)> = Vec::new();
        let mut act_base = Vec::new();
        let mut perm_base = Vec::new();
        let mut next = 0;
        for (a, act) in m.activities.iter().enumerate() {
            act_base.push(next);
            owners.push((Owner::Activity(a), act.task, &act.fsm));
            next += act.fsm.states.len();
        }
        for t in 0..m.tasks.len() {
            perm_base.push(next);
            let fsm = m.fsm(Owner::Task(t));
            owners.push((Owner::Task(t), t, fsm));
            next += fsm.states.len();
        }
        let mut ctl_base = BTreeMap::new();
        let mut ctl_fsms = Vec::new();
        for (&sid, states) in &m.control_codels {
            ctl_base.insert(sid, next);
            next += states.len();
            ctl_fsms.push(states);
        }
        let units = |ns: u64| i64::try_from(ns / unit.max(1)).unwrap_or(i64::MAX / 4);
        let mut upper = Vec::with_capacity(next);
        let mut lower = Vec::with_capacity(next);
        let mut codels = Vec::with_capacity(next);
        for &(owner, task, fsm) in &owners {
            for st in &fsm.states {
                let w = st.wcet_ns.map_or(0, units);
                upper.push((!st.is_async).then_some(w));
                lower.push(if st.is_async { w } else { 0 });
                codels.push((Some(owner), task, st));
            }
        }
        // The control thread: no task, no owner.
        for st in ctl_fsms.into_iter().flatten() {
            let w = st.wcet_ns.map_or(0, units);
            upper.push(Some(w));
            lower.push(0);
            codels.push((None, usize::MAX, st));
        }
        let key_task = codels.iter().map(|&(_, t, _)| t).collect();
        let excl = codels
            .iter()
            .map(|&(owner, task, st)| {
                codels
                    .iter()
                    .enumerate()
                    .filter(|&(_, &(o2, t2, s2))| {
                        t2 != task
                            && !st.is_async
                            && !s2.is_async
                            && !interrupts(m, o2, owner)
                            && st
                                .access
                                .iter()
                                .any(|x| s2.access.iter().any(|y| x.conflicts(y)))
                    })
                    .map(|(k, _)| k)
                    .collect()
            })
            .collect();
        Locks {
            act_base,
            perm_base,
            ctl_base,
            key_task,
            upper,
            lower,
            excl,
        }
    }

    /// The key of `owner`'s state `state`.
    pub fn key(&self, owner: Owner, state: u8) -> usize {
        let base = match owner {
            Owner::Activity(a) => self.act_base[a],
            Owner::Task(t) => self.perm_base[t],
        };
        base + usize::from(state)
    }

    /// The key of service `sid`'s `i`-th control codel.
    pub fn ctl_key(&self, sid: ServiceId, i: usize) -> Option<usize> {
        self.ctl_base.get(&sid).map(|b| b + i)
    }

    /// The duration bound of the codel of key `k`.
    pub fn wcet_of(&self, k: usize) -> Option<i64> {
        self.upper[k]
    }

    /// Whether the codel of key `k` is `async`: it takes no lock and no
    /// ticket in the resource FIFO.
    pub fn is_async(&self, k: usize) -> bool {
        self.upper[k].is_none()
    }

    /// Upper bound of the codel's duration (`None`: unbounded).
    pub fn wcet(&self, owner: Owner, state: u8) -> Option<i64> {
        self.upper[self.key(owner, state)]
    }

    /// Lower bound of the codel's duration.
    pub fn lower(&self, owner: Owner, state: u8) -> i64 {
        self.lower[self.key(owner, state)]
    }

    /// Whether codel `k` waits for, or makes wait, some other codel (else
    /// its duration matters to no task).
    pub fn contended(&self, k: usize) -> bool {
        !self.excl[k].is_empty() || self.excl.iter().any(|e| e.binary_search(&k).is_ok())
    }

    /// What a codel is to the others: whom it waits for, who waits for it,
    /// its duration bounds. Two codels with equal signatures are
    /// interchangeable.
    pub fn signature(&self, k: usize) -> (Vec<usize>, Vec<usize>, Option<i64>, i64) {
        let waited_by = (0..self.excl.len())
            .filter(|&j| self.excludes(j, k))
            .collect();
        (
            self.excl[k].clone(),
            waited_by,
            self.upper[k],
            self.lower[k],
        )
    }

    /// The codels that codel `k` waits for.
    pub fn waits_for(&self, k: usize) -> &[usize] {
        &self.excl[k]
    }

    /// Number of keys.
    pub fn len(&self) -> usize {
        self.excl.len()
    }

    /// Whether there is no codel.
    pub fn is_empty(&self) -> bool {
        self.excl.is_empty()
    }

    /// Whether codel `k` waits while codel `j` runs.
    pub fn excludes(&self, k: usize, j: usize) -> bool {
        self.excl[k].binary_search(&j).is_ok()
    }
}

/// Whether `by`'s service interrupts `target`'s (both activities).
fn interrupts(m: &Machine<'_>, by: Option<Owner>, target: Option<Owner>) -> bool {
    match (by, target) {
        (Some(Owner::Activity(b)), Some(Owner::Activity(a))) => {
            m.activities[b].interrupts.contains(&a)
        }
        _ => false,
    }
}
