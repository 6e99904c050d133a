//! The statements that edges share: clearing a slot, interrupting one
//! (5.1, 5.2, 5.4 and 15.6), opening a sweep (1.4, 1.5, 15.2), the steps
//! that follow at once after any step (boot order 10.1, pending
//! interrupters re-examined 5.3, shutdown 10.2) and the continuation sweep
//! of a task whose sweep made an unpaused transition.
//!
//! `e` is the name of the edge's local variable that says an instance
//! ended (it triggers the re-examination of pending interrupters).

use genom_model::timed_automata::{Expr, LValue, Stmt, VarId};

use super::{Builder, DRAIN, PERM_STOP, STOPPED};

pub(super) fn v(x: VarId) -> Expr {
    Expr::var(x)
}

pub(super) fn is(x: VarId, c: i64) -> Expr {
    Expr::eq(Expr::var(x), Expr::int(c))
}

pub(super) fn set(x: VarId, c: i64) -> Stmt {
    Stmt::set(x, Expr::int(c))
}

pub(super) fn set_local(e: &str, c: i64) -> Stmt {
    Stmt::Assign(LValue::Local(e.to_owned()), Expr::int(c))
}

pub(super) fn idx(i: usize) -> i64 {
    i64::try_from(i).unwrap_or(i64::MAX)
}

fn when(out: &mut Vec<Stmt>, c: Expr, a: Vec<Stmt>) {
    Stmt::push_if(out, c, a, Vec::new());
}

impl Builder<'_> {
    /// Empties slot `i`.
    pub(super) fn clear(&self, i: usize) -> Vec<Stmt> {
        let s = self.slots[i];
        let mut out = self.fifo_drop_slot(i);
        out.extend(
            [s.st, s.q, s.due, s.pz, s.fl]
                .into_iter()
                .map(|x| set(x, 0)),
        );
        out
    }

    /// Slot `i` ends (`success`: its service completed, 4.1).
    pub(super) fn end_slot(&self, i: usize, success: bool, e: &str) -> Vec<Stmt> {
        let mut out = self.clear(i);
        if success {
            out.extend(self.mark_done(i));
        }
        if self.r.slots[i].service.is_some() {
            out.push(set_local(e, 1));
        }
        out
    }

    /// `done_S := 1` for slot `i`'s service, when tracked.
    fn mark_done(&self, i: usize) -> Vec<Stmt> {
        self.r.slots[i]
            .service
            .and_then(|s| self.done.get(&s))
            .map(|&d| vec![set(d, 1)])
            .unwrap_or_default()
    }

    /// `done_S := 1` for a control service, when tracked.
    pub(super) fn mark_service_done(&self, s: genom_model::component::ServiceId) -> Vec<Stmt> {
        self.done
            .get(&s)
            .map(|&d| vec![set(d, 1)])
            .unwrap_or_default()
    }

    /// Whether slot `i`'s codel runs now.
    pub(super) fn busy(&self, i: usize) -> Expr {
        is(self.tasks[self.r.slots[i].task].cur, idx(i) + 1)
    }

    /// Interrupts slot `i` (`spare`: not if accepted and not started): an
    /// accepted one ends; a running one whose codel runs or is due is
    /// flagged, another goes to `stop` (or ends without one); a stopping
    /// one is left alone.
    pub(super) fn flag(&self, i: usize, spare: bool, e: &str) -> Vec<Stmt> {
        let s = self.slots[i];
        let mut out = Vec::new();
        if !spare {
            when(
                &mut out,
                Expr::within(&v(s.st), 1, 2),
                self.end_slot(i, false, e),
            );
        }
        let to_stop = match self.r.slots[i].fsm.stop {
            Some(stop) => vec![set(s.st, 4), set(s.q, idx(stop)), set(s.pz, 0)],
            None => self.end_slot(i, false, e),
        };
        let running = vec![Stmt::If(
            Expr::or([self.busy(i), is(s.due, 1)]),
            vec![set(s.fl, 1)],
            to_stop,
        )];
        when(&mut out, is(s.st, 3), running);
        out
    }

    /// Slot `i` is on its way to end by an interruption.
    pub(super) fn stopping(&self, i: usize) -> Expr {
        let s = self.slots[i];
        Expr::or([is(s.st, 4), is(s.fl, 1)])
    }

    /// Opens a sweep of task `t`; `runnable`: accepted instances start and
    /// paused ones resume.
    pub(super) fn sweep(&self, t: usize, runnable: bool, e: &str) -> Vec<Stmt> {
        let mut out = Vec::new();
        let mut ends = false;
        for &i in &self.r.tasks[t].slots {
            let s = self.slots[i];
            let running = Expr::within(&v(s.st), 3, 4);
            if !runnable {
                when(
                    &mut out,
                    Expr::and([running, is(s.pz, 0)]),
                    vec![set(s.due, 1)],
                );
                continue;
            }
            let start = match self.r.slots[i].fsm.start {
                Some(st) => vec![set(s.st, 3), set(s.q, idx(st)), set(s.due, 1), set(s.pz, 0)],
                None => {
                    ends = true;
                    self.end_slot(i, true, e)
                }
            };
            let resume = vec![Stmt::If(
                running,
                vec![set(s.pz, 0), set(s.due, 1)],
                Vec::new(),
            )];
            if self.r.slots[i].service.is_some() {
                out.push(Stmt::If(is(s.st, 2), start, resume));
            } else {
                out.extend(resume);
            }
        }
        if ends {
            out.extend(self.settle(e));
        }
        out
    }

    /// Task `t`, idle with nothing due, sweeps again after an unpaused
    /// transition (periodic: starting and resuming nothing, 1.5).
    pub(super) fn finish(&self, t: usize, e: &str) -> Vec<Stmt> {
        let tv = self.tasks[t];
        let mut c = vec![is(tv.cont, 1)];
        for &i in &self.r.tasks[t].slots {
            c.push(is(self.slots[i].due, 0));
        }
        let mut body = vec![set(tv.cont, 0)];
        body.extend(self.sweep(t, tv.period.is_none(), e));
        let mut out = Vec::new();
        when(&mut out, Expr::and(c), body);
        out
    }

    /// Whether task `t` runs at all yet (spawned in the boot order).
    pub(super) fn spawned(&self, t: usize) -> Expr {
        Expr::or([
            Expr::ne(v(self.phase), Expr::int(super::BOOT)),
            Expr::cmp(
                genom_model::timed_automata::CmpOp::Ge,
                v(self.booted),
                Expr::int(idx(t)),
            ),
        ])
    }

    /// The steps that follow at once: boot order, pending interrupters
    /// re-examined while instances end, shutdown.
    pub(super) fn settle(&self, e: &str) -> Vec<Stmt> {
        let mut out = self.boot_order();
        let mut body = vec![set_local(e, 0)];
        for (a, slot) in self.r.slots.iter().enumerate() {
            if slot.service.is_none() || slot.interrupts.is_empty() {
                continue;
            }
            let s = self.slots[a];
            let mut inner = Vec::new();
            for &b in &slot.interrupts {
                // Its own activity's instances not started yet are spared
                // (ROS-act `interrupt_other` skips the interrupter itself).
                let own = self.r.slots[b].service == slot.service;
                inner.extend(self.flag(b, own, e));
            }
            let delayed = Expr::or(slot.interrupts.iter().map(|&b| self.stopping(b)));
            when(
                &mut inner,
                Expr::and([is(s.st, 1), Expr::negation(delayed)]),
                vec![set(s.st, 2)],
            );
            when(&mut body, Expr::within(&v(s.st), 1, 2), inner);
        }
        if body.len() > 1 {
            out.push(Stmt::While(
                Expr::eq(Expr::Local(e.to_owned()), Expr::int(1)),
                body,
            ));
        }
        out.extend(self.shutdown());
        out
    }

    /// Boot (10.1): tasks are spawned in order, each once its permanent
    /// activity ran its first codel (or at once without one).
    fn boot_order(&self) -> Vec<Stmt> {
        let n = self.r.tasks.len();
        let mut out = Vec::new();
        for t in 0..n {
            let mut c = vec![is(self.phase, super::BOOT), is(self.booted, idx(t))];
            if let Some(p) = self.r.tasks[t].perm {
                c.push(is(self.slots[p].st, 0));
            }
            when(&mut out, Expr::and(c), vec![set(self.booted, idx(t) + 1)]);
        }
        when(
            &mut out,
            Expr::and([is(self.phase, super::BOOT), is(self.booted, idx(n))]),
            vec![set(self.phase, super::RUN)],
        );
        out
    }

    /// The initial values of the boot order (the same rule, statically).
    pub(super) fn initial_boot(&self) -> (i64, i64) {
        let n = self.r.tasks.len();
        let mut booted = 0;
        while booted < n {
            let started = self.r.tasks[booted]
                .perm
                .is_some_and(|p| self.r.slots[p].fsm.start.is_some());
            if started {
                break;
            }
            booted += 1;
        }
        let phase = if booted >= n { super::RUN } else { super::BOOT };
        (idx(booted), phase)
    }

    /// Shutdown (10.2): once `kill` drained every instance, the permanent
    /// activities run their stop paths, last task first; then the
    /// component stops.
    fn shutdown(&self) -> Vec<Stmt> {
        let n = self.r.tasks.len();
        let mut out = Vec::new();
        let mut drained = vec![is(self.phase, DRAIN)];
        for (i, slot) in self.r.slots.iter().enumerate() {
            if slot.service.is_some() {
                drained.push(is(self.slots[i].st, 0));
            }
        }
        let mut body = vec![set(self.phase, PERM_STOP), set(self.pstop, idx(n))];
        for t in 0..n {
            let Some(p) = self.r.tasks[t].perm else {
                continue;
            };
            body.extend(self.clear(p));
            let tv = self.tasks[t];
            when(
                &mut body,
                self.busy(p),
                vec![set(tv.cur, 0), set(tv.run, 0)],
            );
        }
        when(&mut out, Expr::and(drained), body);
        let mut ended = vec![is(self.pstop, idx(n))];
        for t in 0..n {
            match self.r.tasks[t].perm {
                Some(p) => ended.push(Expr::and([is(self.pstop, idx(t)), is(self.slots[p].st, 0)])),
                None => ended.push(is(self.pstop, idx(t))),
            }
        }
        let mut chain = Vec::new();
        for below in 0..=n {
            let next = self.next_perm_stop(below);
            chain = vec![Stmt::If(is(self.pstop, idx(below)), next, chain)];
        }
        when(
            &mut out,
            Expr::and([is(self.phase, PERM_STOP), Expr::or(ended)]),
            chain,
        );
        out
    }

    /// Puts the last task before `below` with a permanent stop codel on
    /// its stop path, or stops the component.
    fn next_perm_stop(&self, below: usize) -> Vec<Stmt> {
        for t in (0..below).rev() {
            let Some(p) = self.r.tasks[t].perm else {
                continue;
            };
            let Some(stop) = self.r.slots[p].fsm.stop else {
                continue;
            };
            let s = self.slots[p];
            let mut out = self.fifo_drop_slot(p);
            out.extend([
                set(s.st, 4),
                set(s.q, idx(stop)),
                set(s.pz, 0),
                set(s.due, 0),
                set(self.pstop, idx(t)),
            ]);
            return out;
        }
        vec![set(self.phase, STOPPED)]
    }
}
