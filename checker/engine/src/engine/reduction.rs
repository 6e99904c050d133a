//! Partial-order reduction of the untimed semantics: in a state where one
//! service's next codel step is *quiet* (independent of everything the
//! other services can do before it, and invisible to every property the
//! analysis reads), only that service's step is explored; the other
//! interleavings lead to states the reduced search reaches anyway.
//!
//! The reduced set is a *stubborn set* in Valmari's sense, built from
//! static tables computed once per exploration:
//!
//! - **finishing a codel** (all the ways the codel can finish) is quiet
//!   when every way leads to another codel of the same instance (none ends
//!   the instance), the service has no `max-time` watchdog, and nothing
//!   can interrupt the instance while the codel runs: either every service
//!   that `stops` it has a control codel that conflicts with the running
//!   codel (its requests wait for the codel's locks), or the instance is
//!   already interrupted and has no pending instance that could be;
//! - **beginning a codel** is quiet when the service is the only member on
//!   its thread, no member stops it, it has no watchdog, and the codel
//!   conflicts with no codel and no control codel of another member.
//!
//! A quiet step changes only its own service's position; it leaves every
//! instance, pending instance and wait mask as it was, never takes a lock
//! a request could need, and one of its ways keeps "may never end" at
//! least as true as it was (the starvation verdict reads it). The explorer
//! adds the *cycle proviso*: a state whose reduced successors include an
//! already stored state is expanded fully, so no step is postponed for
//! ever around a cycle. `docs/semantics.md` ("Partial-order reduction")
//! gives the argument that every verdict is preserved; tests/reduction.rs
//! compares reduced and full explorations on generated components.

use genom_model::behaviour::{Effect, Position};
use genom_model::component::CodelId;

use super::system::{Action, Config, Reduce, System, conflict};

/// The static facts the reduction needs about the members of a system.
#[derive(Debug, Clone, Default)]
pub struct Reduction {
    /// Per codel of the component (indexed by codel id): finishing it is
    /// protected from interrupts (every stopper's control codel conflicts
    /// with it). Only meaningful for codels of members.
    finish_locked: Vec<bool>,
    /// Per codel: conflicts with no codel and no control codel of another
    /// member.
    private_codel: Vec<bool>,
    /// Per member: some member (itself included) lists it in `stops`.
    stoppable: Vec<bool>,
    /// Per member: it is the only member on its thread.
    own_thread: Vec<bool>,
}

impl System<'_> {
    /// The same system, explored with partial-order reduction.
    #[must_use]
    pub fn with_reduction(self) -> Self {
        let r = Reduction::new(&self);
        self.reduced_by(r)
    }
}

impl Reduce for Reduction {
    fn stubborn(&self, sys: &System<'_>, cfg: &Config, actions: &mut [Action]) -> usize {
        Reduction::stubborn(self, sys, cfg, actions)
    }
}

impl Reduction {
    /// The tables of `sys`.
    pub fn new(sys: &System<'_>) -> Self {
        let c = sys.component();
        let n = sys.len();
        let mut stoppers: Vec<Vec<usize>> = vec![Vec::new(); n];
        for x in 0..n {
            for &t in sys.stops_of(x) {
                stoppers[t].push(x);
            }
        }
        let stoppable: Vec<bool> = stoppers.iter().map(|s| !s.is_empty()).collect();
        let own_thread: Vec<bool> = (0..n)
            .map(|j| {
                let t = sys.machine_of(j).thread;
                t.is_none() || (0..n).all(|k| k == j || sys.machine_of(k).thread != t)
            })
            .collect();
        let codels = member_codels(sys);
        let mut finish_locked = vec![false; c.codels.len()];
        let mut private_codel = vec![false; c.codels.len()];
        for &(j, codel) in &codels {
            let uses = sys.codel_uses(codel);
            finish_locked[codel.0 as usize] = stoppers[j]
                .iter()
                .all(|&x| conflict(sys.control_uses(x), uses));
            // Only members that may begin quietly need it (quadratic).
            private_codel[codel.0 as usize] = own_thread[j]
                && !stoppable[j]
                && codels
                    .iter()
                    .all(|&(i, other)| i == j || !conflict(uses, sys.codel_uses(other)));
        }
        Reduction {
            finish_locked,
            private_codel,
            stoppable,
            own_thread,
        }
    }

    /// Moves a stubborn subset of `actions` (the actions enabled in `cfg`)
    /// to the front and returns its length; `actions.len()` when no quiet
    /// step exists.
    pub fn stubborn(&self, sys: &System<'_>, cfg: &Config, actions: &mut [Action]) -> usize {
        let Some(j) = (0..sys.len()).find(|&j| self.quiet(sys, cfg, j)) else {
            return actions.len();
        };
        let s = sys.service(j);
        let mut n = 0;
        for k in 0..actions.len() {
            if matches!(actions[k], Action::Begin(t) | Action::Finish(t, _) if t == s) {
                actions.swap(n, k);
                n += 1;
            }
        }
        if n == 0 { actions.len() } else { n }
    }

    /// Whether member `j`'s next codel step is quiet in `cfg`.
    fn quiet(&self, sys: &System<'_>, cfg: &Config, j: usize) -> bool {
        let m = sys.machine_of(j);
        if m.watchdog {
            return false;
        }
        let p = usize::from(cfg.main[j]);
        match m.positions[p] {
            Position::Running { codel, .. } | Position::StopRunning { codel } => {
                self.quiet_finish(sys, cfg, j, codel)
            }
            Position::Ready { codel, .. } | Position::StopReady { codel } => {
                self.quiet_begin(sys, cfg, j, codel)
            }
            Position::Idle => false,
        }
    }

    fn quiet_finish(&self, sys: &System<'_>, cfg: &Config, j: usize, codel: CodelId) -> bool {
        let m = sys.machine_of(j);
        let p = usize::from(cfg.main[j]);
        let ways = &m.finish[p];
        let mut targets = Vec::with_capacity(ways.len());
        for f in ways {
            match f.effect {
                Effect::Goto(q) => targets.push(usize::from(q)),
                Effect::End(_) => return false,
            }
        }
        let protected = self.finish_locked[codel.0 as usize]
            || (m.interrupt[p].is_none()
                && cfg.pending[j].is_none()
                && !sys.stops_of(j).contains(&j));
        let keeps_never_end = !m.may_never_end[p] || targets.iter().any(|&q| m.may_never_end[q]);
        !targets.is_empty() && protected && keeps_never_end
    }

    fn quiet_begin(&self, sys: &System<'_>, cfg: &Config, j: usize, codel: CodelId) -> bool {
        let m = sys.machine_of(j);
        let p = usize::from(cfg.main[j]);
        let Some(r) = m.begin[p] else {
            return false;
        };
        let keeps_never_end = !m.may_never_end[p] || m.may_never_end[usize::from(r)];
        !self.stoppable[j]
            && self.own_thread[j]
            && self.private_codel[codel.0 as usize]
            && keeps_never_end
            && sys.can_begin(cfg, j, codel)
    }
}

/// Every codel of every member (control codels included), with its member.
fn member_codels(sys: &System<'_>) -> Vec<(usize, CodelId)> {
    let c = sys.component();
    let mut out = Vec::new();
    for j in 0..sys.len() {
        let svc = &c.services[sys.service(j)];
        let control = svc.control.filter(|k| !svc.codels.contains(k));
        out.extend(svc.codels.iter().copied().chain(control).map(|k| (j, k)));
    }
    out
}

#[cfg(test)]
mod tests {
    use genom_model::behaviour::Behaviour;
    use genom_model::component::ServiceId;

    use crate::engine::explore::{Limits, explore};
    use crate::engine::system::System;
    use crate::testing::check;

    /// Two looping services on threads of their own, sharing no data, and a
    /// third that stops the first while a codel writes what its control
    /// codel reads.
    const SRC: &str = "component t { lang: C; }\nids d { double x; }\n\
        thread t1 { period: 10ms; }\nthread t2 { period: 10ms; }\nthread t3 { period: 10ms; }\n\
        service a { thread: t1;\n start codel { exec: f(d.x); update: d.x; next: run; }\n\
          exec codel run { exec: f(d.x); update: d.x; next: run, end; } }\n\
        service b { thread: t2;\n start codel { exec: g(); next: run; }\n\
          exec codel run { exec: g(); next: run, end; } }\n\
        service c { thread: t3; stops: a;\n control codel { exec: h(const d.x); }\n\
          start codel { exec: k(); next: end; } }\n";

    #[test]
    fn quiet_steps_cut_interleavings_and_keep_every_local_state() {
        let c = check(SRC).component.expect("a component");
        let b = Behaviour::new(&c);
        let all: Vec<ServiceId> = c.services.ids().collect();
        let positions = |reduce: bool| {
            let sys = System::new(&c, &b, &all, false);
            let sys = if reduce { sys.with_reduction() } else { sys };
            let mut seen = std::collections::BTreeSet::new();
            let e = explore(&sys, Limits::default(), |_, cfg| {
                for i in 0..cfg.main.len() {
                    seen.insert((i, cfg.main[i]));
                }
            });
            assert!(e.stopped.is_none());
            (e.store.len(), e.reduced, seen)
        };
        let (full, none, all_full) = positions(false);
        let (reduced, expansions, all_reduced) = positions(true);
        assert_eq!(none, 0);
        assert!(expansions > 0, "some state is expanded with a quiet step");
        assert!(reduced < full, "{reduced} states, {full} without reduction");
        assert_eq!(all_reduced, all_full, "every position of every service");
    }
}
