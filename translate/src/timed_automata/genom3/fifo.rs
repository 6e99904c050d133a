//! GenoM3's resource FIFO in the network (docs/genom3-semantics.md 8.3 and
//! 15.5): a thread that cannot begin its codel at once (a lock it waits for
//! is held, or tickets are queued) takes a ticket (the urgent `ticket`
//! edge) and begins only at the queue's head with its locks free; a thread
//! without a ticket begins only when the queue is empty. The head blocks
//! every later ticket, conflicting or not (head-of-line blocking).
//!
//! The queue is kept as positions, so that one queue has one encoding:
//! `qlen` (tickets queued), per task `tpos_T` (its place, 1 the head, 0
//! none) and `tslot_T` (slot + 1 whose codel the ticket is for), and `cpos`
//! for the control thread. Serving or dropping a ticket moves the later
//! ones up by one. `async` codels take no ticket (7.2).

use genom_model::timed_automata::{CmpOp, Expr, Stmt, VarId};

use super::Builder;
use super::stmts::{idx, is, set, v};

/// The queue's variables.
#[derive(Debug, Clone)]
pub(super) struct Fifo {
    qlen: VarId,
    tpos: Vec<VarId>,
    tslot: Vec<VarId>,
    cpos: VarId,
}

impl Default for Fifo {
    fn default() -> Self {
        Fifo {
            qlen: VarId(0),
            tpos: Vec::new(),
            tslot: Vec::new(),
            cpos: VarId(0),
        }
    }
}

impl Builder<'_> {
    /// Declares the queue's variables (after the tasks and slots).
    pub(super) fn declare_fifo(&mut self) {
        let span = self.c.name.span;
        let n = idx(self.r.tasks.len() + 1);
        let slots = idx(self.r.slots.len());
        self.fifo.qlen = self.int(
            "qlen",
            n,
            span,
            "tickets queued in GenoM3's resource FIFO".to_owned(),
        );
        for t in 0..self.r.tasks.len() {
            let (name, span) = (self.r.tasks[t].name.clone(), self.r.tasks[t].span);
            let pos = self.int(
                &format!("tpos_{name}"),
                n,
                span,
                format!("task {name}'s place in the resource FIFO (1 the head, 0 no ticket)"),
            );
            let slot = self.int(
                &format!("tslot_{name}"),
                slots,
                span,
                format!("slot + 1 whose codel task {name}'s ticket is for (0: none)"),
            );
            self.fifo.tpos.push(pos);
            self.fifo.tslot.push(slot);
        }
        self.fifo.cpos = self.int(
            "cpos",
            n,
            span,
            "the control thread's place in the resource FIFO (1 the head, 0 no ticket)".to_owned(),
        );
    }

    /// The position variable of a thread (a task, `None` for control).
    fn pos(&self, th: Option<usize>) -> VarId {
        th.map_or(self.fifo.cpos, |t| self.fifo.tpos[t])
    }

    /// A thread may begin its codel (of slot `slot`, for a task) whose locks
    /// are free when `free`: its ticket is the head, or it holds none and
    /// none is queued.
    pub(super) fn fifo_begin(&self, th: Option<usize>, slot: Option<usize>, free: Expr) -> Expr {
        let pos = self.pos(th);
        let mine = match (th, slot) {
            (Some(t), Some(i)) => is(self.fifo.tslot[t], idx(i) + 1),
            _ => Expr::TRUE,
        };
        Expr::and([
            free,
            Expr::or([
                Expr::and([is(pos, 0), is(self.fifo.qlen, 0)]),
                Expr::and([is(pos, 1), mine]),
            ]),
        ])
    }

    /// An `async` codel begins: its thread holds no ticket (it takes none).
    pub(super) fn fifo_async(&self, t: usize) -> Expr {
        is(self.fifo.tpos[t], 0)
    }

    /// A thread takes a ticket: it holds none and cannot begin now.
    pub(super) fn fifo_must_wait(&self, th: Option<usize>, free: Expr) -> Expr {
        Expr::and([
            is(self.pos(th), 0),
            Expr::negation(Expr::and([is(self.fifo.qlen, 0), free])),
        ])
    }

    /// Takes a ticket (for slot `slot`, for a task): last in the queue.
    pub(super) fn fifo_take(&self, th: Option<usize>, slot: Option<usize>) -> Vec<Stmt> {
        let q = self.fifo.qlen;
        let mut out = vec![
            Stmt::set(self.pos(th), Expr::add([v(q), Expr::int(1)])),
            Stmt::set(q, Expr::add([v(q), Expr::int(1)])),
        ];
        if let (Some(t), Some(i)) = (th, slot) {
            out.push(set(self.fifo.tslot[t], idx(i) + 1));
        }
        out
    }

    /// The thread leaves the queue if it is in it (its ticket is served or
    /// dropped): the later tickets move up.
    pub(super) fn fifo_leave(&self, th: Option<usize>) -> Vec<Stmt> {
        let me = self.pos(th);
        let mut body = Vec::new();
        let others = (0..self.r.tasks.len())
            .map(Some)
            .chain([None])
            .filter(|&u| u != th);
        for u in others {
            let p = self.pos(u);
            body.push(Stmt::set(
                p,
                Expr::ite(
                    Expr::cmp(CmpOp::Gt, v(p), v(me)),
                    Expr::minus(v(p), Expr::int(1)),
                    v(p),
                ),
            ));
        }
        body.push(Stmt::set(
            self.fifo.qlen,
            Expr::minus(v(self.fifo.qlen), Expr::int(1)),
        ));
        body.push(set(me, 0));
        if let Some(t) = th {
            body.push(set(self.fifo.tslot[t], 0));
        }
        let mut out = Vec::new();
        Stmt::push_if(
            &mut out,
            Expr::cmp(CmpOp::Gt, v(me), Expr::int(0)),
            body,
            Vec::new(),
        );
        out
    }

    /// Slot `i`'s codel is gone without running: its task's ticket for it,
    /// if any, is dropped.
    pub(super) fn fifo_drop_slot(&self, i: usize) -> Vec<Stmt> {
        let t = self.r.slots[i].task;
        let mut out = Vec::new();
        Stmt::push_if(
            &mut out,
            is(self.fifo.tslot[t], idx(i) + 1),
            self.fifo_leave(Some(t)),
            Vec::new(),
        );
        out
    }
}
