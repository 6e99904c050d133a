//! The state of services as expressions: positions, pending instances,
//! the ready, running and watchable intervals, and free locks.

use std::collections::BTreeSet;

use genom_model::behaviour::{PosId, Position};
use genom_model::component::{CodelId, ServiceId, StructureId, uses_conflict as conflict};
use genom_model::timed_automata::Expr;

use super::Builder;

impl<'a> Builder<'a> {
    pub(super) fn position_text(&self, p: Position) -> String {
        let name = |k: CodelId| self.c.codels[k].name.name.clone();
        match p {
            Position::Idle => "idle".to_owned(),
            Position::Ready { codel, on_inter } => match on_inter {
                Some(i) => format!("ready at {} (on-inter {})", name(codel), name(i)),
                None => format!("ready at {}", name(codel)),
            },
            Position::Running { codel, interrupted } => {
                if interrupted {
                    format!("running {} (interrupted)", name(codel))
                } else {
                    format!("running {}", name(codel))
                }
            }
            Position::StopReady { codel } => format!("stopping, ready at {}", name(codel)),
            Position::StopRunning { codel } => format!("stopping, running {}", name(codel)),
        }
    }

    /// Codels that can be running (in a running position), in codel order.
    pub(super) fn running_codels(&self, s: ServiceId) -> Vec<CodelId> {
        let m = self.machine(s);
        let set: BTreeSet<CodelId> = m
            .positions
            .iter()
            .filter(|p| p.is_running())
            .filter_map(|p| p.codel())
            .collect();
        set.into_iter().collect()
    }

    // ----- expressions over the state ---------------------------------------

    pub(super) fn pos(&self, s: ServiceId) -> Expr {
        Expr::var(self.svc(s).pos)
    }

    pub(super) fn pend(&self, s: ServiceId) -> Expr {
        Expr::var(self.svc(s).pend)
    }

    pub(super) fn value(&self, s: ServiceId, p: PosId) -> i64 {
        self.svc(s).value[usize::from(p)]
    }

    pub(super) fn at(&self, s: ServiceId, p: PosId) -> Expr {
        Expr::eq(self.pos(s), Expr::int(self.value(s, p)))
    }

    pub(super) fn has_instance(&self, s: ServiceId) -> Expr {
        Expr::or([
            Expr::ne(self.pos(s), Expr::int(0)),
            Expr::eq(self.pend(s), Expr::int(1)),
        ])
    }

    pub(super) fn no_instance(&self, s: ServiceId) -> Expr {
        Expr::and([
            Expr::eq(self.pos(s), Expr::int(0)),
            Expr::eq(self.pend(s), Expr::int(0)),
        ])
    }

    pub(super) fn ready(&self, s: ServiceId) -> Expr {
        let (lo, hi) = self.svc(s).ready();
        Expr::within(&self.pos(s), lo, hi)
    }

    pub(super) fn watchable(&self, s: ServiceId) -> Expr {
        let (lo, hi) = self.svc(s).watchable();
        Expr::within(&self.pos(s), lo, hi)
    }

    pub(super) fn live(&self, s: ServiceId) -> Expr {
        Expr::or([self.watchable(s), Expr::eq(self.pend(s), Expr::int(1))])
    }

    /// No running thread codel conflicts with `uses`.
    pub(super) fn locks_free(&self, uses: &[(StructureId, bool)]) -> Expr {
        Expr::and(uses.iter().filter_map(|&(d, w)| {
            let &(r, wv) = self.locks.get(&d)?;
            Some(if w {
                Expr::and([
                    Expr::eq(Expr::var(r), Expr::int(0)),
                    Expr::eq(Expr::var(wv), Expr::int(0)),
                ])
            } else {
                Expr::eq(Expr::var(wv), Expr::int(0))
            })
        }))
    }

    /// No running control codel conflicts with `uses`.
    pub(super) fn control_free(&self, uses: &[(StructureId, bool)]) -> Expr {
        let Some(ctl) = self.ctl else {
            return Expr::TRUE;
        };
        Expr::and(
            self.svcs
                .iter()
                .filter(|r| r.ctl_wcet.is_some() && conflict(uses, &r.control_uses))
                .map(|r| Expr::ne(Expr::var(ctl), Expr::int(i64::from(r.id.0)))),
        )
    }

    pub(super) fn ready_positions(&self, s: ServiceId) -> Vec<PosId> {
        let v = self.svc(s);
        let (lo, hi) = v.ready();
        (lo..=hi)
            .filter_map(|x| v.order.get(usize::try_from(x).ok()?).copied())
            .collect()
    }

    pub(super) fn running_positions(&self, s: ServiceId) -> Vec<PosId> {
        let v = self.svc(s);
        (v.bounds[2]..v.bounds[4])
            .filter_map(|x| v.order.get(usize::try_from(x).ok()?).copied())
            .collect()
    }

    // ----- statements mirroring the engine ----------------------------------
}
