//! The process of one task: `sleep` (periodic, before its first tick),
//! `idle`, one location per codel of its slots (label `codel_S_C` for an
//! activity's codel, on its location in each of the activity's slots), and
//! `overrun` (label `overrun_T`, committed and without edges: nothing
//! happens after it, as in the engine).
//!
//! Edges: ticks (15.1: at `delay`, then every `period`, when the previous
//! wake-up's work is finished; else the overrun edge), activations of an
//! aperiodic task (15.4: at any time while it has an instance to start or
//! resume and nothing due), codel begins (urgent, when no other thread runs
//! a codel of its exclusion list, 15.5), codel ends (15.3: any time within
//! [0, WCET], at least the WCET for `async`; one edge per yield plus one
//! for an exception, 9.1), and the urgent `drop` of a permanent codel the
//! shutdown killed.

use genom_model::timed_automata::{
    ClockConstraint, CmpOp, Edge, Expr, Label, LabelKind, Location, Process, ProcessId,
    ProcessKind, Stmt,
};

use super::read::KeyOwner;
use super::stmts::{idx, is, set};
use super::{Builder, FAILED, STOPPED, lid};

fn cc(clock: genom_model::timed_automata::ClockId, op: CmpOp, bound: i64) -> ClockConstraint {
    ClockConstraint { clock, op, bound }
}

impl Builder<'_> {
    /// Nothing stopped the component.
    pub(super) fn alive(&self) -> Expr {
        Expr::cmp(CmpOp::Lt, Expr::var(self.phase), Expr::int(STOPPED))
    }

    /// No thread but `except` (a task, or the control thread with `None`)
    /// runs a codel that codel `k` waits for.
    pub(super) fn lock_free(&self, k: usize, except: Option<usize>) -> Expr {
        let mut c = Vec::new();
        for &j in &self.r.keys[k].excl {
            let running = match self.r.keys[j].task {
                Some(u) if Some(u) != except => self.tasks[u].run,
                Some(_) => continue,
                None => self.crun,
            };
            c.push(Expr::ne(Expr::var(running), Expr::int(idx(j) + 1)));
        }
        Expr::and(c)
    }

    /// Task `t` has work left in its current wake-up.
    fn unfinished(&self, t: usize) -> Expr {
        let mut c = vec![is(self.tasks[t].cont, 1), is(self.tasks[t].busy, 1)];
        for &i in &self.r.tasks[t].slots {
            c.push(is(self.slots[i].due, 1));
        }
        Expr::or(c)
    }

    /// Slot `i`'s state `s` is due on its idle task.
    fn due_now(&self, i: usize, s: usize) -> Expr {
        let t = self.r.slots[i].task;
        let sv = self.slots[i];
        Expr::and([
            self.alive(),
            is(self.tasks[t].busy, 0),
            is(sv.due, 1),
            is(sv.q, idx(s)),
        ])
    }

    /// The guards of slot `i`'s begin of state `s` (an idle task): its
    /// locks free and its turn in the resource FIFO (an `async` codel takes
    /// no lock and no ticket).
    pub(super) fn begin_guard(&self, i: usize, s: usize) -> Expr {
        let t = self.r.slots[i].task;
        let key = self.r.slots[i].fsm.states[s].key;
        let go = if self.bounds[key].1.is_none() {
            self.fifo_async(t)
        } else {
            self.fifo_begin(Some(t), Some(i), self.lock_free(key, Some(t)))
        };
        Expr::and([self.due_now(i, s), go])
    }

    /// The guards of slot `i`'s ticket for state `s`: due, and it cannot
    /// begin now (never for an `async` codel).
    pub(super) fn ticket_guard(&self, i: usize, s: usize) -> Expr {
        let t = self.r.slots[i].task;
        let key = self.r.slots[i].fsm.states[s].key;
        if self.bounds[key].1.is_none() {
            return Expr::FALSE;
        }
        let wait = self.fifo_must_wait(Some(t), self.lock_free(key, Some(t)));
        Expr::and([self.due_now(i, s), wait])
    }

    /// The task's process.
    pub(super) fn task_process(&mut self, t: usize) {
        let task = self.r.tasks[t].clone();
        let tv = self.tasks[t];
        let pid = ProcessId(u32::try_from(self.net.processes.len()).unwrap_or(u32::MAX));
        let mut p = Process {
            name: self.fresh(&format!("task_{}", task.name)),
            kind: ProcessKind::Thread(task.id),
            locations: Vec::new(),
            edges: Vec::new(),
            span: task.span,
            description: format!("task {}: its ticks, sweeps and codels", task.name),
        };
        let period_inv: Vec<ClockConstraint> = tv
            .period
            .map(|(x, per, _)| vec![cc(x, CmpOp::Le, per)])
            .unwrap_or_default();
        let loc = |name: &str, inv: Vec<ClockConstraint>, desc: String| Location {
            name: name.to_owned(),
            initial: false,
            urgent: false,
            committed: false,
            invariant: inv,
            labels: Vec::new(),
            span: task.span,
            description: desc,
        };
        // 0 sleep (periodic only, else unused), 1 idle, 2 overrun, codels.
        let mut sleep = loc(
            "sleep",
            tv.period
                .map(|(x, _, d)| vec![cc(x, CmpOp::Le, d)])
                .unwrap_or_default(),
            "before the first tick".to_owned(),
        );
        sleep.initial = tv.period.is_some();
        let mut idle = loc("idle", period_inv.clone(), "no codel runs".to_owned());
        idle.initial = tv.period.is_none();
        let mut over = loc("overrun", Vec::new(), "the task overran".to_owned());
        over.committed = true;
        p.locations.extend([sleep, idle, over]);
        if tv.period.is_some() {
            let label = self.fresh_label(&format!("overrun_{}", task.name));
            p.locations[2].labels.push(label.clone());
            self.net.labels.push(Label {
                name: label,
                kind: LabelKind::Overrun(task.id),
                process: pid,
                location: lid(2),
            });
        }
        self.ticks(t, &mut p);
        for &i in &task.slots {
            for s in 0..self.r.slots[i].fsm.states.len() {
                self.codel_location(t, i, s, &period_inv, pid, &mut p);
            }
        }
        self.net.processes.push(p);
    }

    fn edge(&self, from: usize, to: usize, ev: &str, guard: Expr, desc: String) -> Edge {
        super::plain_edge((from, to), ev, guard, self.c.name.span, desc)
    }

    /// Ticks, overruns from `idle` and activations.
    fn ticks(&mut self, t: usize, p: &mut Process) {
        let tv = self.tasks[t];
        let name = self.r.tasks[t].name.clone();
        let Some((x, per, delay)) = tv.period else {
            let e = self.local();
            let mut any = Vec::new();
            for &i in &self.r.tasks[t].slots {
                any.push(Expr::within(&Expr::var(self.slots[i].st), 2, 4));
            }
            let guard = Expr::and([
                self.alive(),
                self.spawned(t),
                Expr::negation(self.unfinished(t)),
                Expr::or(any),
            ]);
            let mut w = self.edge(1, 1, "wake", guard, format!("task {name} is activated"));
            w.statements = vec![Stmt::Local(e.clone(), Expr::int(0))];
            w.statements.extend(self.sweep(t, true, &e));
            w.statements.extend(self.finish(t, &e));
            p.edges.push(w);
            return;
        };
        for (from, at, what) in [(0, delay, "first tick"), (1, per, "tick")] {
            let e = self.local();
            let mut guard = vec![self.alive()];
            if from == 1 {
                guard.push(Expr::negation(self.unfinished(t)));
            }
            let mut k = self.edge(
                from,
                1,
                "tick",
                Expr::and(guard),
                format!("task {name}'s {what}"),
            );
            k.clock_guard = vec![cc(x, CmpOp::Eq, at)];
            k.statements = vec![Stmt::Local(e.clone(), Expr::int(0)), Stmt::Reset(x)];
            let mut body = self.sweep(t, true, &e);
            body.extend(self.finish(t, &e));
            Stmt::push_if(&mut k.statements, self.spawned(t), body, Vec::new());
            p.edges.push(k);
        }
        self.idle_overruns(t, x, per, p);
    }

    /// The overrun edges from `idle`: at the tick, with due work, nothing
    /// urgent, and either no other thread running a codel or one running
    /// below its WCET (at its WCET it ends first, at the same instant).
    fn idle_overruns(
        &mut self,
        t: usize,
        x: genom_model::timed_automata::ClockId,
        per: i64,
        p: &mut Process,
    ) {
        let name = self.r.tasks[t].name.clone();
        let base = Expr::and([
            self.alive(),
            self.unfinished(t),
            Expr::negation(self.urgency()),
        ]);
        let mut variants: Vec<(Expr, Vec<ClockConstraint>)> = Vec::new();
        let mut none = vec![is(self.crun, 0)];
        for (u, uv) in self.tasks.iter().enumerate() {
            if u != t {
                none.push(is(uv.cur, 0));
            }
        }
        variants.push((Expr::and(none), Vec::new()));
        for (k, key) in self.r.keys.iter().enumerate() {
            let (running, clock) = match key.task {
                Some(u) if u == t => continue,
                Some(u) => (
                    Expr::and([
                        is(self.tasks[u].run, idx(k) + 1),
                        Expr::ne(Expr::var(self.tasks[u].cur), Expr::int(0)),
                    ]),
                    self.tasks[u].exec,
                ),
                None => {
                    let KeyOwner::Ctl(sid, i) = key.owner else {
                        continue;
                    };
                    if !self.timed_ctl.get(&sid).is_some_and(|v| v.contains(&i)) {
                        continue;
                    }
                    (is(self.crun, idx(k) + 1), self.ctl_clock)
                }
            };
            let cg = match self.bounds[k].1 {
                Some(w) => vec![cc(clock, CmpOp::Lt, w)],
                None => Vec::new(),
            };
            variants.push((running, cg));
        }
        for (g, mut cg) in variants {
            let mut o = self.edge(
                1,
                2,
                "overrun",
                Expr::and([base.clone(), g]),
                format!("task {name}'s tick finds its work unfinished"),
            );
            cg.push(cc(x, CmpOp::Eq, per));
            o.clock_guard = cg;
            p.edges.push(o);
        }
    }

    /// The location of slot `i`'s codel in state `s`, its begin, ends,
    /// overrun and drop edges.
    fn codel_location(
        &mut self,
        t: usize,
        i: usize,
        s: usize,
        period_inv: &[ClockConstraint],
        pid: ProcessId,
        p: &mut Process,
    ) {
        let slot = self.r.slots[i].clone();
        let st = slot.fsm.states[s].clone();
        let tv = self.tasks[t];
        let (lower, upper) = self.bounds[st.key];
        let at = p.locations.len();
        let mut inv = period_inv.to_vec();
        if let Some(w) = upper {
            inv.push(cc(tv.exec, CmpOp::Le, w));
        }
        let mut labels = Vec::new();
        if let (Some(sid), Some(codel)) = (slot.service, st.codel) {
            // One label per codel, on its location in each of the
            // activity's slots.
            let label = match self.codel_labels.get(&codel) {
                Some(l) => l.clone(),
                None => {
                    let l = self.fresh_label(&format!(
                        "codel_{}_{}",
                        self.c.services[sid].name.name, self.c.codels[codel].name.name
                    ));
                    self.codel_labels.insert(codel, l.clone());
                    l
                }
            };
            labels.push(label.clone());
            self.net.labels.push(Label {
                name: label,
                kind: LabelKind::Codel(codel),
                process: pid,
                location: lid(at),
            });
        }
        p.locations.push(Location {
            name: self.fresh_location(p, &format!("{}_{}", slot.name, st.name)),
            initial: false,
            urgent: false,
            committed: false,
            invariant: inv,
            labels: labels.clone(),
            span: st.span,
            description: format!("{} runs its codel of state {}", slot.name, st.name),
        });
        let here = format!("{} {}", slot.name, st.name);
        let mut b = self.edge(
            1,
            at,
            "begin",
            self.begin_guard(i, s),
            format!("{here}: begins"),
        );
        b.urgent = true;
        b.statements = self.fifo_leave(Some(t));
        b.statements.extend([
            set(self.slots[i].due, 0),
            set(tv.busy, 1),
            set(tv.cur, idx(i) + 1),
            set(tv.run, idx(st.key) + 1),
            Stmt::Reset(tv.exec),
        ]);
        p.edges.push(b);
        let ticket = self.ticket_guard(i, s);
        if !ticket.is_false() {
            let mut k = self.edge(
                1,
                1,
                "ticket",
                ticket,
                format!("{here}: takes a ticket and waits"),
            );
            k.urgent = true;
            k.statements = self.fifo_take(Some(t), Some(i));
            p.edges.push(k);
        }
        let live = Expr::and([self.alive(), self.busy(i)]);
        for o in 0..=st.yields.len() {
            let mut e = self.edge(
                at,
                1,
                "finish",
                live.clone(),
                format!("{here}: ends, {}", outcome(&slot, &st, o)),
            );
            if lower > 0 {
                e.clock_guard = vec![cc(tv.exec, CmpOp::Ge, lower)];
            }
            e.labels.clone_from(&labels);
            e.statements = self.end_statements(t, i, s, o);
            p.edges.push(e);
        }
        if let Some((x, per, _)) = tv.period {
            let mut o = self.edge(
                at,
                2,
                "overrun",
                live,
                format!("{here}: the tick comes before its end"),
            );
            o.clock_guard = vec![cc(x, CmpOp::Eq, per)];
            if let Some(w) = upper {
                o.clock_guard.push(cc(tv.exec, CmpOp::Lt, w));
            }
            p.edges.push(o);
        }
        if slot.service.is_none() {
            let mut d = self.edge(
                at,
                1,
                "drop",
                is(tv.cur, 0),
                format!("{here}: killed by the shutdown"),
            );
            d.urgent = true;
            d.statements = vec![set(tv.busy, 0), set(tv.run, 0)];
            p.edges.push(d);
        }
    }

    fn fresh_location(&self, p: &Process, want: &str) -> String {
        let base = super::sanitize(want);
        let mut name = base.clone();
        let mut k = 2;
        while p.locations.iter().any(|l| l.name == name)
            || matches!(name.as_str(), "sleep" | "idle" | "overrun")
        {
            name = format!("{base}_{k}");
            k += 1;
        }
        name
    }

    /// The end of slot `i`'s codel in state `s` with outcome `o` (a yield,
    /// or one past them: an exception), then the steps that follow.
    fn end_statements(&mut self, t: usize, i: usize, s: usize, o: usize) -> Vec<Stmt> {
        let e = self.local();
        let tv = self.tasks[t];
        let sv = self.slots[i];
        let slot = self.r.slots[i].clone();
        let perm = slot.service.is_none();
        let booting = Expr::and([is(self.phase, super::BOOT), is(self.booted, idx(t))]);
        let b = self.local();
        let mut out = vec![
            Stmt::Local(e.clone(), Expr::int(0)),
            Stmt::Local(b.clone(), booting),
            set(tv.busy, 0),
            set(tv.cur, 0),
            set(tv.run, 0),
        ];
        match slot.fsm.states[s].yields.get(o).copied() {
            Some((Some(next), pause)) => {
                if !pause {
                    out.push(set(tv.cont, 1));
                }
                let landed = vec![
                    set(sv.q, idx(next)),
                    set(sv.pz, i64::from(pause)),
                    set(sv.fl, 0),
                ];
                if perm {
                    out.extend(landed);
                } else {
                    let stop = match slot.fsm.stop {
                        Some(stop) => vec![
                            set(sv.st, 4),
                            set(sv.q, idx(stop)),
                            set(sv.pz, 0),
                            set(sv.fl, 0),
                        ],
                        None => self.end_slot(i, false, &e),
                    };
                    out.push(Stmt::If(
                        Expr::and([is(sv.fl, 1), is(sv.st, 3)]),
                        stop,
                        landed,
                    ));
                }
            }
            Some((None, _)) => out.extend(self.end_slot(i, true, &e)),
            None if perm => out.push(Stmt::If(
                Expr::eq(Expr::Local(b.clone()), Expr::int(1)),
                vec![set(self.phase, FAILED)],
                self.clear(i),
            )),
            None => out.extend(self.end_slot(i, false, &e)),
        }
        if perm {
            Stmt::push_if(
                &mut out,
                Expr::eq(Expr::Local(b), Expr::int(1)),
                vec![Stmt::set(
                    self.booted,
                    Expr::add([Expr::var(self.booted), Expr::int(1)]),
                )],
                Vec::new(),
            );
        }
        out.extend(self.settle(&e));
        out.extend(self.finish(t, &e));
        out
    }
}

/// What outcome `o` of a codel is, for descriptions.
fn outcome(slot: &super::read::Slot, st: &super::read::State, o: usize) -> String {
    match st.yields.get(o) {
        Some((Some(n), pause)) => format!(
            "yield {}{}",
            if *pause { "pause::" } else { "" },
            slot.fsm.states[*n].name
        ),
        Some((None, _)) => "yield ether".to_owned(),
        None => "an exception".to_owned(),
    }
}
