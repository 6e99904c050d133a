//! The steps of services: ends, auto starts, interrupts, the urgent
//! starts' closure, settling a step and handling a request.

use std::collections::BTreeSet;

use genom_model::behaviour::{Effect, Ending};
use genom_model::component::ServiceId;
use genom_model::timed_automata::{Expr, LValue, Stmt};

use super::Builder;
use super::bookkeeping::Before;

impl<'a> Builder<'a> {
    /// `System::end`: the main instance of `s` ends.
    pub(super) fn end(&self, s: ServiceId, ending: Ending) -> Vec<Stmt> {
        let v = self.svc(s);
        let mut out = vec![Stmt::set(v.pos, Expr::int(0))];
        if let Some(t) = v.tmo {
            out.push(Stmt::set(t, Expr::int(0)));
        }
        for k in &self.svcs {
            for (bit, &t) in k.stops.iter().enumerate() {
                if t == s {
                    if let Some(w) = k.wait {
                        out.push(Stmt::set_elem(w, bit as i64, Expr::int(0)));
                    }
                }
            }
        }
        if ending == Ending::Success && self.c.init_service() == Some(s) {
            let mut then = vec![Stmt::set(self.init_done, Expr::int(1))];
            then.extend(self.start_autos());
            Stmt::push_if(
                &mut out,
                Expr::eq(Expr::var(self.init_done), Expr::int(0)),
                then,
                Vec::new(),
            );
        }
        out
    }

    /// Initialisation completes: every auto service becomes active at its
    /// start codel (never pending; one without start codel completes at
    /// once, which changes nothing here).
    pub(super) fn start_autos(&self) -> Vec<Stmt> {
        let mut out = Vec::new();
        for a in self.svcs.iter().filter(|a| a.auto) {
            let Some(p) = self.machine(a.id).start else {
                continue;
            };
            Stmt::push_if(
                &mut out,
                self.no_instance(a.id),
                vec![Stmt::set(a.pos, Expr::int(self.value(a.id, p)))],
                Vec::new(),
            );
        }
        out
    }

    pub(super) fn interrupt_pending(&self, t: ServiceId) -> Vec<Stmt> {
        let v = self.svc(t);
        let mut then = vec![Stmt::set(v.pend, Expr::int(0))];
        if let Some(w) = v.wait {
            for bit in 0..v.stops.len() {
                then.push(Stmt::set_elem(w, bit as i64, Expr::int(0)));
            }
        }
        let mut out = Vec::new();
        Stmt::push_if(
            &mut out,
            Expr::eq(self.pend(t), Expr::int(1)),
            then,
            Vec::new(),
        );
        out
    }

    /// `System::interrupt_main`: one `if` per interruptible position (the
    /// positions they lead to are not interruptible, so the tests are
    /// exclusive even in sequence).
    pub(super) fn interrupt_main(&self, t: ServiceId, watchdog: bool) -> Vec<Stmt> {
        let v = self.svc(t);
        let m = self.machine(t);
        let mut out = Vec::new();
        for &p in &v.order {
            let Some(effect) = m.interrupt[usize::from(p)] else {
                continue;
            };
            let then = match effect {
                Effect::Goto(q) => {
                    let mut s = vec![Stmt::set(v.pos, Expr::int(self.value(t, q)))];
                    if let (true, Some(tmo)) = (watchdog, v.tmo) {
                        s.push(Stmt::set(tmo, Expr::int(1)));
                    }
                    s
                }
                Effect::End(ending) => self.end(t, ending),
            };
            Stmt::push_if(&mut out, self.at(t, p), then, Vec::new());
        }
        out
    }

    /// Step 7: starts pending instances among `candidates`, first one first,
    /// until none can.
    pub(super) fn closure(&mut self, candidates: &BTreeSet<ServiceId>) -> Vec<Stmt> {
        if candidates.is_empty() {
            return Vec::new();
        }
        let go = self.local();
        let g = || Expr::Local(go.clone());
        let mut body = vec![Stmt::Assign(LValue::Local(go.clone()), Expr::int(0))];
        for &s in candidates {
            let v = self.svc(s);
            let mut cond = vec![
                Expr::eq(g(), Expr::int(0)),
                Expr::eq(self.pend(s), Expr::int(1)),
                Expr::eq(self.pos(s), Expr::int(0)),
            ];
            if let Some(w) = v.wait {
                for bit in 0..v.stops.len() {
                    cond.push(Expr::eq(Expr::elem(w, bit as i64), Expr::int(0)));
                }
            }
            for &d in &v.delayers {
                cond.push(self.no_instance(d));
            }
            let mut then = vec![Stmt::set(v.pend, Expr::int(0))];
            match self.machine(s).start {
                Some(p) => then.push(Stmt::set(v.pos, Expr::int(self.value(s, p)))),
                None => then.extend(self.end(s, Ending::Success)),
            }
            then.push(Stmt::Assign(LValue::Local(go.clone()), Expr::int(1)));
            Stmt::push_if(&mut body, Expr::and(cond), then, Vec::new());
        }
        vec![
            Stmt::Local(go.clone(), Expr::int(1)),
            Stmt::While(Expr::eq(g(), Expr::int(1)), body),
        ]
    }

    /// The services whose instances may change when those of `seeds` do
    /// (and the urgent starts follow): `stops`/`delays` dependents, and the
    /// auto services when the init service is among them.
    pub(super) fn affected(
        &self,
        seeds: impl IntoIterator<Item = ServiceId>,
    ) -> BTreeSet<ServiceId> {
        let mut set: BTreeSet<ServiceId> = seeds.into_iter().collect();
        let mut stack: Vec<ServiceId> = set.iter().copied().collect();
        let init = self.c.init_service();
        while let Some(x) = stack.pop() {
            for k in &self.svcs {
                let depends =
                    k.stops.contains(&x) || k.delayers.contains(&x) || (Some(x) == init && k.auto);
                if depends && set.insert(k.id) {
                    stack.push(k.id);
                }
            }
        }
        set
    }

    /// The common tail of a step: urgent starts, bookkeeping, turns.
    pub(super) fn settle(
        &mut self,
        affected: &BTreeSet<ServiceId>,
        before: &Before,
        requested: Option<ServiceId>,
        initial: bool,
        extra_threads: &[usize],
    ) -> Vec<Stmt> {
        let mut out = self.closure(affected);
        out.extend(self.bookkeep(affected, before, requested, initial));
        let mut threads = self.threads_of(affected);
        threads.extend(extra_threads.iter().copied());
        for k in threads {
            out.extend(self.turn(k));
        }
        out
    }

    /// A whole accepted request of `s` (steps 5–7 and the bookkeeping).
    pub(super) fn request(&mut self, s: ServiceId) -> Vec<Stmt> {
        self.locals = 0;
        let v = self.svc(s).clone();
        let mut seeds = vec![s];
        seeds.extend(v.stops.iter().copied());
        let affected = self.affected(seeds);
        let (mut out, before) = self.save(&affected);
        for &t in &v.stops {
            out.extend(self.interrupt_pending(t));
            out.extend(self.interrupt_main(t, false));
        }
        out.push(Stmt::set(v.pend, Expr::int(1)));
        if let Some(w) = v.wait {
            for (bit, &t) in v.stops.iter().enumerate() {
                out.push(Stmt::set_elem(
                    w,
                    bit as i64,
                    Expr::ne(self.pos(t), Expr::int(0)),
                ));
            }
        }
        out.extend(self.settle(&affected, &before, Some(s), false, &[]));
        out
    }

    // ----- processes ---------------------------------------------------------
}
