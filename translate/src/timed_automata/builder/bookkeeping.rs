//! The bookkeeping of a step: saving the affected services' state, then
//! updating clocks, eligible sets, acknowledgment orders and turns.

use std::collections::{BTreeMap, BTreeSet};

use genom_model::component::ServiceId;
use genom_model::timed_automata::{Expr, Stmt};

use super::Builder;

impl<'a> Builder<'a> {
    pub(super) fn tracked(&self, s: ServiceId) -> bool {
        let v = self.svc(s);
        v.placement.is_some() || v.watch.is_some()
    }

    /// Saves, for the bookkeeping, the position and pending flag of the
    /// tracked `affected` services (and `init_done` when autos may be
    /// acknowledged).
    pub(super) fn save(&mut self, affected: &BTreeSet<ServiceId>) -> (Vec<Stmt>, Before) {
        let mut out = Vec::new();
        let mut before = Before::default();
        for &s in affected {
            if !self.tracked(s) {
                continue;
            }
            let (lp, lq) = (self.local(), self.local());
            out.push(Stmt::Local(lp.clone(), self.pos(s)));
            out.push(Stmt::Local(lq.clone(), self.pend(s)));
            before.saved.insert(s, (Expr::Local(lp), Expr::Local(lq)));
        }
        let autos = affected
            .iter()
            .any(|&s| self.svc(s).auto && self.tracked(s));
        if autos && self.c.init_service().is_some() {
            let l = self.local();
            out.push(Stmt::Local(l.clone(), Expr::var(self.init_done)));
            before.init = Some(Expr::Local(l));
        }
        (out, before)
    }

    /// `TimedSystem::bookkeep` for the affected services.
    pub(super) fn bookkeep(
        &self,
        affected: &BTreeSet<ServiceId>,
        before: &Before,
        requested: Option<ServiceId>,
        initial: bool,
    ) -> Vec<Stmt> {
        let mut out = Vec::new();
        for &s in affected {
            if !self.tracked(s) {
                continue;
            }
            let v = self.svc(s);
            let (bp, bq) = before
                .saved
                .get(&s)
                .cloned()
                .unwrap_or((Expr::int(0), Expr::int(0)));
            let acked = if requested == Some(s) {
                Expr::TRUE
            } else if initial {
                self.has_instance(s)
            } else if v.auto {
                match &before.init {
                    Some(bi) => Expr::and([
                        Expr::eq(bi.clone(), Expr::int(0)),
                        Expr::eq(Expr::var(self.init_done), Expr::int(1)),
                    ]),
                    None => Expr::FALSE,
                }
            } else {
                Expr::FALSE
            };
            let pos = self.pos(s);
            let pend = self.pend(s);
            let started_by_start = match self.machine(s).start {
                Some(p) => {
                    let sv = Expr::int(self.value(s, p));
                    Expr::and([
                        Expr::eq(bq.clone(), Expr::int(1)),
                        Expr::eq(pend.clone(), Expr::int(0)),
                        Expr::eq(pos.clone(), sv.clone()),
                        Expr::ne(bp.clone(), sv),
                    ])
                }
                None => Expr::FALSE,
            };
            let started = Expr::or([
                started_by_start,
                Expr::and([
                    acked.clone(),
                    Expr::eq(pend.clone(), Expr::int(0)),
                    Expr::ne(pos.clone(), Expr::int(0)),
                ]),
            ]);
            let ended = Expr::and([
                Expr::ne(bp, Expr::int(0)),
                Expr::or([Expr::eq(pos.clone(), Expr::int(0)), started]),
            ]);
            if let Some((clock, _)) = v.watch {
                Stmt::push_if(
                    &mut out,
                    acked.clone(),
                    vec![Stmt::Reset(clock)],
                    Vec::new(),
                );
            }
            if let Some((k, slot)) = v.placement {
                let t = &self.thrs[k];
                Stmt::push_if(
                    &mut out,
                    ended,
                    vec![Stmt::set_elem(t.elig, slot as i64, Expr::int(0))],
                    Vec::new(),
                );
                let mut requeue = self.order_remove(k, slot);
                requeue.extend(self.order_push(k, slot));
                let mut drop = Vec::new();
                Stmt::push_if(
                    &mut drop,
                    self.no_instance(s),
                    self.order_remove(k, slot),
                    Vec::new(),
                );
                Stmt::push_if(&mut out, acked, requeue, drop);
            }
        }
        out
    }

    /// Removes `slot` from thread `k`'s order (bubbling it to the end).
    pub(super) fn order_remove(&self, k: usize, slot: usize) -> Vec<Stmt> {
        let t = &self.thrs[k];
        let n = t.members.len() as i64;
        let s = slot as i64;
        let mut out = Vec::new();
        for i in 0..n - 1 {
            out.push(Stmt::If(
                Expr::eq(Expr::elem(t.ord, i), Expr::int(s)),
                vec![
                    Stmt::set_elem(t.ord, i, Expr::elem(t.ord, i + 1)),
                    Stmt::set_elem(t.ord, i + 1, Expr::int(s)),
                ],
                Vec::new(),
            ));
        }
        out.push(Stmt::If(
            Expr::eq(Expr::elem(t.ord, n - 1), Expr::int(s)),
            vec![Stmt::set_elem(t.ord, n - 1, Expr::int(n))],
            Vec::new(),
        ));
        out
    }

    /// Appends `slot` to thread `k`'s order (at the first empty entry).
    pub(super) fn order_push(&self, k: usize, slot: usize) -> Vec<Stmt> {
        let t = &self.thrs[k];
        let n = t.members.len() as i64;
        let s = slot as i64;
        (0..n)
            .map(|i| {
                let mut cond = vec![Expr::eq(Expr::elem(t.ord, i), Expr::int(n))];
                if i > 0 {
                    cond.push(Expr::ne(Expr::elem(t.ord, i - 1), Expr::int(n)));
                    cond.push(Expr::ne(Expr::elem(t.ord, i - 1), Expr::int(s)));
                }
                Stmt::If(
                    Expr::and(cond),
                    vec![Stmt::set_elem(t.ord, i, Expr::int(s))],
                    Vec::new(),
                )
            })
            .collect()
    }

    /// Recomputes thread `k`'s turn: the first eligible slot in order.
    pub(super) fn turn(&self, k: usize) -> Vec<Stmt> {
        let t = &self.thrs[k];
        let n = t.members.len() as i64;
        let mut out = vec![Stmt::set(t.turn, Expr::int(n))];
        for i in (0..n).rev() {
            let at = Expr::elem(t.ord, i);
            out.push(Stmt::If(
                Expr::eq(Expr::elem_at(t.elig, at.clone()), Expr::int(1)),
                vec![Stmt::set(t.turn, at)],
                Vec::new(),
            ));
        }
        out
    }

    pub(super) fn threads_of(&self, services: &BTreeSet<ServiceId>) -> BTreeSet<usize> {
        services
            .iter()
            .filter_map(|&s| self.svc(s).placement.map(|(k, _)| k))
            .collect()
    }

    /// `eligible := active ready members` for thread `k`.
    pub(super) fn fresh_round(&self, k: usize) -> Vec<Stmt> {
        let t = &self.thrs[k];
        t.members
            .iter()
            .enumerate()
            .map(|(slot, &s)| Stmt::set_elem(t.elig, slot as i64, self.ready(s)))
            .collect()
    }
}

/// The saved state of a step's affected services.
#[derive(Debug, Clone, Default)]
pub(super) struct Before {
    saved: BTreeMap<ServiceId, (Expr, Expr)>,
    init: Option<Expr>,
}
