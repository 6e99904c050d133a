//! The control thread (sections 4-6): requests at any time once the
//! component runs (10.1), admitted by `after`/`before` (4.1, 4.2); an
//! activity request takes a free slot of the activity (one instance, two
//! for an activity that interrupts itself: the request restarting it,
//! 3.4) after interrupting its targets (5.1), pending while one of them
//! stops (5.3); a function or attribute marks itself done and interrupts
//! its targets (6.1), `kill` all of them before the shutdown (5.7, 10.2);
//! `abort_activity` interrupts one instance (5.6). The control codels that
//! take time (a WCET and a lock some task's codel contends, 15.5) run in
//! turn: each waits for its locks (urgent begin), runs within its WCET,
//! and ends with success (the next one, or the request's effect) or an
//! exception (the request changes nothing). The others are instantaneous.
//! Also the network's urgency predicate.

use genom_model::component::ServiceId;
use genom_model::timed_automata::{
    ClockConstraint, CmpOp, Edge, Expr, Location, Process, ProcessKind, Stmt,
};

use super::read::CtlKind;
use super::stmts::{idx, is, set};
use super::{Builder, DRAIN, RUN};

/// A request's effect once its control codels succeeded.
#[derive(Debug, Clone, Copy)]
enum Job {
    /// An activity's request (its service).
    Accept(ServiceId),
    /// A function, attribute or built-in (index into `controls`).
    Call(usize),
}

impl Builder<'_> {
    /// `after`/`before` admit service `sid`.
    fn admissible(&self, sid: ServiceId) -> Expr {
        let mut c = Vec::new();
        for x in self.r.after.get(&sid).into_iter().flatten() {
            if let Some(&d) = self.done.get(x) {
                c.push(is(d, 1));
            }
        }
        for x in self.r.before.get(&sid).into_iter().flatten() {
            if let Some(&d) = self.done.get(x) {
                c.push(is(d, 0));
            }
        }
        Expr::and(c)
    }

    /// The effect of a job, with its steps that follow.
    fn effect(&mut self, job: Job) -> Vec<Stmt> {
        let e = self.local();
        let mut out = vec![Stmt::Local(e.clone(), Expr::int(0))];
        match job {
            Job::Accept(sid) => {
                // The first free slot: the slots of one activity are
                // interchangeable, as the engine's instances are.
                let slots = self.r.slot_of.get(&sid).cloned().unwrap_or_default();
                let mut chain = Vec::new();
                for &a in slots.iter().rev() {
                    let accept = self.accept(a, &e);
                    chain = vec![Stmt::If(is(self.slots[a].st, 0), accept, chain)];
                }
                out.extend(chain);
            }
            Job::Call(k) => {
                let ctl = self.r.controls[k].clone();
                out.extend(self.mark_service_done(ctl.service));
                for &b in &ctl.interrupts {
                    out.extend(self.flag(b, false, &e));
                }
                if ctl.kind == CtlKind::Kill {
                    out.push(set(self.phase, DRAIN));
                }
            }
        }
        out.extend(self.settle(&e));
        out
    }

    /// A request accepted into free slot `a`: it interrupts its targets
    /// (the activity's other slot too when it interrupts itself) and is
    /// accepted, or delayed while one of them stops (5.1, 5.3).
    fn accept(&self, a: usize, e: &str) -> Vec<Stmt> {
        let targets: Vec<usize> = self.r.slots[a]
            .interrupts
            .iter()
            .copied()
            .filter(|&b| b != a)
            .collect();
        let mut out = Vec::new();
        for &b in &targets {
            out.extend(self.flag(b, false, e));
        }
        let st = self.slots[a].st;
        let delayed = Expr::or(targets.iter().map(|&b| self.stopping(b)));
        Stmt::push_if(&mut out, delayed, vec![set(st, 1)], vec![set(st, 2)]);
        out
    }

    fn ctl_edge(&self, from: usize, to: usize, ev: &str, guard: Expr, desc: String) -> Edge {
        super::plain_edge((from, to), ev, guard, self.c.name.span, desc)
    }

    /// The control thread's process.
    pub(super) fn control_process(&mut self) {
        let span = self.c.name.span;
        let mut p = Process {
            name: self.fresh("control"),
            kind: ProcessKind::Control,
            locations: vec![Location {
                name: "idle".to_owned(),
                initial: true,
                urgent: false,
                committed: false,
                invariant: Vec::new(),
                labels: Vec::new(),
                span,
                description: "waiting for a request".to_owned(),
            }],
            edges: Vec::new(),
            span,
            description: "the control thread: requests and control codels".to_owned(),
        };
        let running = is(self.phase, RUN);
        let acts: Vec<(ServiceId, Vec<usize>)> = self
            .r
            .slot_of
            .iter()
            .map(|(&sid, v)| (sid, v.clone()))
            .collect();
        for (sid, slots) in acts {
            let free = Expr::or(slots.iter().map(|&a| is(self.slots[a].st, 0)));
            let guard = Expr::and([running.clone(), free, self.admissible(sid)]);
            self.request(&mut p, sid, guard, Job::Accept(sid));
        }
        for k in 0..self.r.controls.len() {
            let ctl = self.r.controls[k].clone();
            let guard = Expr::and([running.clone(), self.admissible(ctl.service)]);
            if ctl.kind == CtlKind::Abort {
                let all: Vec<usize> = self.r.slot_of.values().flatten().copied().collect();
                for a in all {
                    let e = self.local();
                    let mut edge = self.ctl_edge(
                        0,
                        0,
                        "request",
                        Expr::and([
                            guard.clone(),
                            Expr::within(&Expr::var(self.slots[a].st), 1, 3),
                        ]),
                        format!("abort_activity on {}", self.r.slots[a].name),
                    );
                    edge.statements = vec![Stmt::Local(e.clone(), Expr::int(0))];
                    edge.statements.extend(self.mark_service_done(ctl.service));
                    edge.statements.extend(self.flag(a, false, &e));
                    edge.statements.extend(self.settle(&e));
                    p.edges.push(edge);
                }
                continue;
            }
            let inert = ctl.kind == CtlKind::Plain
                && ctl.interrupts.is_empty()
                && !self.done.contains_key(&ctl.service)
                && !self.timed_ctl.contains_key(&ctl.service);
            if !inert {
                self.request(&mut p, ctl.service, guard, Job::Call(k));
            }
        }
        self.net.processes.push(p);
    }

    /// A request of service `sid`: its effect at once, or its timed
    /// control codels in turn, then its effect.
    fn request(&mut self, p: &mut Process, sid: ServiceId, guard: Expr, job: Job) {
        let name = self.c.services[sid].name.name.clone();
        let Some(timed) = self.timed_ctl.get(&sid).cloned() else {
            let mut e = self.ctl_edge(0, 0, "request", guard, format!("request {name}"));
            e.statements = self.effect(job);
            p.edges.push(e);
            return;
        };
        let codels = self.r.ctl_codels.get(&sid).cloned().unwrap_or_default();
        let first = p.locations.len();
        let mut r = self.ctl_edge(
            0,
            first,
            "request",
            guard,
            format!("request {name}: its control codels run"),
        );
        r.statements = vec![set(self.cph, self.cph_value(sid, 0, false))];
        p.edges.push(r);
        for (n, &j) in timed.iter().enumerate() {
            let codel = &codels[j];
            let w = self.bounds[codel.key].1.unwrap_or(0);
            let wait = p.locations.len();
            let run = wait + 1;
            let base = Location {
                name: super::sanitize(&format!("wait_{name}_{}", codel.name)),
                initial: false,
                urgent: false,
                committed: false,
                invariant: Vec::new(),
                labels: Vec::new(),
                span: self.c.services[sid].name.span,
                description: format!("{name}'s control codel {} waits for its locks", codel.name),
            };
            let mut running = base.clone();
            running.name = super::sanitize(&format!("run_{name}_{}", codel.name));
            running.invariant = vec![ClockConstraint {
                clock: self.ctl_clock,
                op: CmpOp::Le,
                bound: w,
            }];
            running.description = format!("{name}'s control codel {} runs", codel.name);
            p.locations.extend([base, running]);
            let mut b = self.ctl_edge(
                wait,
                run,
                "cbegin",
                self.ctl_may_begin(codel.key),
                format!("{name}: control codel {} begins", codel.name),
            );
            b.urgent = true;
            b.statements = self.fifo_leave(None);
            b.statements.extend([
                set(self.crun, idx(codel.key) + 1),
                set(self.cph, self.cph_value(sid, n, true)),
                Stmt::Reset(self.ctl_clock),
            ]);
            p.edges.push(b);
            let mut k = self.ctl_edge(
                wait,
                wait,
                "cticket",
                self.ctl_must_wait(codel.key),
                format!(
                    "{name}: control codel {} takes a ticket and waits",
                    codel.name
                ),
            );
            k.urgent = true;
            k.statements = self.fifo_take(None, None);
            p.edges.push(k);
            let last = n + 1 == timed.len();
            let mut ok = self.ctl_edge(
                run,
                if last { 0 } else { run + 1 },
                "cend",
                self.alive(),
                format!("{name}: control codel {} succeeds", codel.name),
            );
            ok.statements = vec![set(self.crun, 0)];
            if last {
                ok.statements.push(set(self.cph, 0));
                ok.statements.extend(self.effect(job));
            } else {
                ok.statements
                    .push(set(self.cph, self.cph_value(sid, n + 1, false)));
            }
            p.edges.push(ok);
            if codel.copy {
                // An attribute's ids copy throws nothing.
                continue;
            }
            let mut fail = self.ctl_edge(
                run,
                0,
                "cend",
                self.alive(),
                format!("{name}: control codel {} raises an exception", codel.name),
            );
            fail.statements = vec![set(self.crun, 0), set(self.cph, 0)];
            p.edges.push(fail);
        }
    }

    /// Control codel `k` may begin: its locks are free and it is its turn
    /// in GenoM3's resource FIFO (8.3).
    fn ctl_may_begin(&self, k: usize) -> Expr {
        Expr::and([
            self.alive(),
            self.fifo_begin(None, None, self.lock_free(k, None)),
        ])
    }

    /// Control codel `k` cannot begin now: the control thread takes a
    /// ticket.
    fn ctl_must_wait(&self, k: usize) -> Expr {
        Expr::and([
            self.alive(),
            self.fifo_must_wait(None, self.lock_free(k, None)),
        ])
    }

    /// The value of `cph` at the `n`-th timed control codel of `sid`,
    /// waiting or running.
    fn cph_value(&self, sid: ServiceId, n: usize, running: bool) -> i64 {
        let before: usize = self.timed_ctl.range(..sid).map(|(_, v)| v.len()).sum();
        idx(2 * (before + n) + 1 + usize::from(running))
    }

    /// Some urgent edge is enabled: a codel may begin, a killed permanent
    /// codel is dropped, or a control codel may begin.
    pub(super) fn urgency(&self) -> Expr {
        let mut any = Vec::new();
        for (i, slot) in self.r.slots.iter().enumerate() {
            for s in 0..slot.fsm.states.len() {
                any.push(self.begin_guard(i, s));
                any.push(self.ticket_guard(i, s));
            }
        }
        for (t, task) in self.r.tasks.iter().enumerate() {
            if task.perm.is_some() {
                let tv = self.tasks[t];
                any.push(Expr::and([is(tv.busy, 1), is(tv.cur, 0)]));
            }
        }
        for (&sid, timed) in &self.timed_ctl {
            let codels = self.r.ctl_codels.get(&sid).cloned().unwrap_or_default();
            for (n, &j) in timed.iter().enumerate() {
                let wait = is(self.cph, self.cph_value(sid, n, false));
                any.push(Expr::and([wait.clone(), self.ctl_may_begin(codels[j].key)]));
                any.push(Expr::and([wait, self.ctl_must_wait(codels[j].key)]));
            }
        }
        Expr::or(any)
    }
}
