//! Guards and urgency: when a request is enabled, when a thread may begin
//! a codel or start a round, when a watchdog arms, and the network's
//! urgency predicate.

use genom_model::behaviour::{PosId, Position};
use genom_model::component::{ServiceId, uses_conflict as conflict};
use genom_model::timed_automata::Expr;

use super::Builder;

impl<'a> Builder<'a> {
    /// Steps 1–3 and the lock test of the untimed `request_enabled`.
    pub(super) fn request_enabled(&self, s: ServiceId) -> Expr {
        let v = self.svc(s);
        let mut parts = Vec::new();
        if let Some(init) = self.c.init_service().filter(|&i| i != s) {
            let _ = init;
            parts.push(Expr::eq(Expr::var(self.init_done), Expr::int(1)));
        }
        for &t in &v.forbidders {
            parts.push(self.no_instance(t));
        }
        if !v.self_stop {
            parts.push(self.no_instance(s));
        }
        parts.push(self.locks_free(&v.control_uses));
        Expr::and(parts)
    }

    /// Some thread at its turn, idle, wants a lock `s`'s control codel
    /// would take.
    pub(super) fn thread_waits_for(&self, s: ServiceId) -> Expr {
        let uses = &self.svc(s).control_uses;
        let mut out = Vec::new();
        for t in &self.thrs {
            for (slot, &j) in t.members.iter().enumerate() {
                let m = self.machine(j);
                let positions: Vec<Expr> = m
                    .positions
                    .iter()
                    .enumerate()
                    .filter(|(_, p)| {
                        matches!(p, Position::Ready { .. } | Position::StopReady { .. })
                    })
                    .filter(|(_, p)| {
                        p.codel()
                            .is_some_and(|k| conflict(&self.c.codels[k].structures(), uses))
                    })
                    .filter_map(|(i, _)| PosId::try_from(i).ok())
                    .map(|p| self.at(j, p))
                    .collect();
                if positions.is_empty() {
                    continue;
                }
                out.push(Expr::and([
                    Expr::eq(Expr::var(t.busy), Expr::int(0)),
                    Expr::eq(Expr::var(t.turn), Expr::int(slot as i64)),
                    Expr::or(positions),
                ]));
            }
        }
        Expr::or(out)
    }

    /// The guard of a codel begin of `s` at ready position `p`.
    pub(super) fn begin_guard(&self, s: ServiceId, p: PosId) -> Expr {
        let v = self.svc(s);
        let Some((k, slot)) = v.placement else {
            return Expr::FALSE;
        };
        let t = &self.thrs[k];
        let m = self.machine(s);
        let Some(codel) = m.positions[usize::from(p)].codel() else {
            return Expr::FALSE;
        };
        let uses = self.c.codels[codel].structures();
        Expr::and([
            Expr::eq(Expr::var(t.busy), Expr::int(0)),
            self.at(s, p),
            Expr::eq(Expr::var(t.turn), Expr::int(slot as i64)),
            self.locks_free(&uses),
            self.control_free(&uses),
        ])
    }

    pub(super) fn elig_sum(&self, k: usize) -> Expr {
        let t = &self.thrs[k];
        Expr::add((0..t.members.len()).map(|i| Expr::elem(t.elig, i as i64)))
    }

    pub(super) fn round_guard(&self, k: usize) -> Expr {
        let t = &self.thrs[k];
        if t.period.is_some() {
            return Expr::FALSE;
        }
        Expr::and([
            Expr::eq(self.elig_sum(k), Expr::int(0)),
            Expr::eq(Expr::var(t.busy), Expr::int(0)),
            Expr::or(t.members.iter().map(|&s| self.ready(s))),
        ])
    }

    /// The urgent edges of thread `k`'s `idle` location, as guards.
    pub(super) fn thread_urgency(&self, k: usize) -> Expr {
        let t = &self.thrs[k];
        let mut parts = vec![self.round_guard(k)];
        for &s in &t.members {
            for p in self.ready_positions(s) {
                parts.push(self.begin_guard(s, p));
            }
        }
        Expr::or(parts)
    }

    pub(super) fn engine_urgency(&self) -> Expr {
        Expr::or((0..self.thrs.len()).map(|k| self.thread_urgency(k)))
    }

    /// The guards of a watchdog's urgent edges: (arm, disarm).
    pub(super) fn arming(&self, s: ServiceId) -> Option<(Expr, Expr)> {
        let armed = Expr::var(self.svc(s).armed?);
        let live = self.live(s);
        Some((
            Expr::and([Expr::eq(armed.clone(), Expr::int(0)), live.clone()]),
            Expr::and([Expr::eq(armed, Expr::int(1)), Expr::negation(live)]),
        ))
    }

    /// Some urgent edge of the network is enabled: the engine's urgency
    /// plus the arming and disarming of watchdogs.
    pub(super) fn network_urgency(&self) -> Expr {
        let mut parts = vec![self.engine_urgency()];
        for v in &self.svcs {
            if let Some((arm, disarm)) = self.arming(v.id) {
                parts.push(arm);
                parts.push(disarm);
            }
        }
        Expr::or(parts)
    }
}
