//! The execution threads' processes: wake-ups, rounds, codel begins and
//! ends, overruns, and the locks codels hold.

use std::collections::BTreeMap;

use genom_model::behaviour::{Effect, Ending};
use genom_model::component::{CodelId, uses_conflict as conflict};
use genom_model::timed_automata::{
    ClockConstraint, ClockId, CmpOp, Edge, Expr, LabelKind, Location, LocationId, ProcessId,
    ProcessKind, Stmt,
};

use super::graph::loc;
use super::{Builder, event_id};

impl<'a> Builder<'a> {
    pub(super) fn lock_update(&self, codel: CodelId, delta: i64) -> Vec<Stmt> {
        self.c.codels[codel]
            .structures()
            .into_iter()
            .filter_map(|(d, w)| {
                let &(r, wv) = self.locks.get(&d)?;
                let v = if w { wv } else { r };
                Some(Stmt::set(v, Expr::add([Expr::var(v), Expr::int(delta)])))
            })
            .collect()
    }

    pub(super) fn thread_process(&mut self, k: usize) {
        let c = self.c;
        let t = self.thrs[k].clone();
        let th = &c.threads[t.id];
        let kind = match t.period {
            Some(p) => format!("periodic, period {p}"),
            None => "aperiodic".to_owned(),
        };
        let p = self.add_process(
            &t.name,
            ProcessKind::Thread(t.id),
            th.name.span,
            format!(
                "execution thread {} ({kind}): runs one codel of each eligible service per {}, in acknowledgment order",
                t.name,
                if t.period.is_some() { "period" } else { "round" }
            ),
        );
        let period_inv: Vec<ClockConstraint> = match (t.period, t.period_clock) {
            (Some(per), Some(x)) => vec![ClockConstraint {
                clock: x,
                op: CmpOp::Le,
                bound: per,
            }],
            _ => Vec::new(),
        };
        let idle = self.add_location(
            p,
            Location {
                initial: true,
                invariant: period_inv.clone(),
                ..loc("idle", th.name.span, "no codel running")
            },
        );
        let overrun = t.period.map(|_| {
            let label = self.fresh_label(&format!("overrun_{}", t.name));
            self.add_labelled(
                p,
                Location {
                    committed: true,
                    labels: vec![label],
                    ..loc(
                        "overrun",
                        th.name.span,
                        &format!(
                            "thread {} woke up with codels of its previous period unfinished (violation: nothing happens any more)",
                            t.name
                        ),
                    )
                },
                Some(LabelKind::Overrun(t.id)),
            )
        });
        // Running locations.
        let mut running: BTreeMap<CodelId, LocationId> = BTreeMap::new();
        for &s in &t.members {
            for codel in self.running_codels(s) {
                let kd = &c.codels[codel];
                let sname = self.sname(s);
                let w = self.wcet[codel.0 as usize];
                let label = self.fresh_label(&format!("codel_{sname}_{}", kd.name.name));
                let mut inv = period_inv.clone();
                inv.push(ClockConstraint {
                    clock: t.exec_clock,
                    op: CmpOp::Le,
                    bound: w,
                });
                let l = self.add_labelled(
                    p,
                    Location {
                        invariant: inv,
                        labels: vec![label],
                        ..loc(
                            &format!("run_{sname}_{}", kd.name.name),
                            kd.name.span,
                            &format!(
                                "{} runs {} codel {} of {sname} (WCET {w})",
                                t.name,
                                kd.kind.keyword(),
                                kd.name.name
                            ),
                        )
                    },
                    Some(LabelKind::Codel(codel)),
                );
                running.insert(codel, l);
            }
        }
        // Begins (urgent).
        for &s in &t.members {
            for pos in self.ready_positions(s) {
                let m = self.machine(s);
                let Some(q) = m.begin[usize::from(pos)] else {
                    continue;
                };
                let Some(codel) = m.positions[usize::from(q)].codel() else {
                    continue;
                };
                let Some(&to) = running.get(&codel) else {
                    continue;
                };
                let v = self.svc(s).clone();
                let mut st = vec![
                    Stmt::set(v.pos, Expr::int(self.value(s, q))),
                    Stmt::set(t.busy, Expr::int(1)),
                ];
                st.extend(self.lock_update(codel, 1));
                st.push(Stmt::Reset(t.exec_clock));
                let text = self.position_text(m.positions[usize::from(pos)]);
                self.add_edge(
                    p,
                    Edge {
                        from: idle,
                        to,
                        event: event_id("begin"),
                        guard: self.begin_guard(s, pos),
                        clock_guard: Vec::new(),
                        statements: st,
                        urgent: true,
                        labels: Vec::new(),
                        span: c.codels[codel].name.span,
                        description: format!(
                            "{} begins {}::{} ({} {text}; its turn, its locks free)",
                            t.name, v.name, c.codels[codel].name.name, v.name
                        ),
                    },
                );
            }
        }
        // Finishes.
        for &s in &t.members {
            let (_, slot) = self.svc(s).placement.unwrap_or((k, 0));
            for pos in self.running_positions(s) {
                let m = self.machine(s);
                let Some(codel) = m.positions[usize::from(pos)].codel() else {
                    continue;
                };
                let Some(&from) = running.get(&codel) else {
                    continue;
                };
                let label = self.net.processes[p.0 as usize].locations[from.0 as usize]
                    .labels
                    .clone();
                for (fk, f) in m.finish[usize::from(pos)].iter().enumerate() {
                    self.locals = 0;
                    let v = self.svc(s).clone();
                    let mut st = vec![
                        Stmt::set_elem(t.elig, slot as i64, Expr::int(0)),
                        Stmt::set(t.busy, Expr::int(0)),
                    ];
                    st.extend(self.lock_update(codel, -1));
                    let what = match f.effect {
                        Effect::Goto(q) => {
                            st.push(Stmt::set(v.pos, Expr::int(self.value(s, q))));
                            st.extend(self.turn(k));
                            self.position_text(m.positions[usize::from(q)])
                        }
                        Effect::End(ending) => {
                            let affected = self.affected([s]);
                            let (saved, before) = self.save(&affected);
                            let mut all = saved;
                            all.extend(st);
                            st = all;
                            st.extend(self.end(s, ending));
                            st.extend(self.settle(&affected, &before, None, false, &[k]));
                            match ending {
                                Ending::Success => "ends (success)".to_owned(),
                                Ending::Report(r) => format!(
                                    "ends with report {}",
                                    c.services[s]
                                        .reports
                                        .get(r)
                                        .map_or("?", |n| n.name.as_str())
                                ),
                                Ending::Interrupted => "ends (INTERRUPTED or TIMEOUT)".to_owned(),
                            }
                        }
                    };
                    let outcome = match f.outcome {
                        Some(o) => match o {
                            genom_model::component::Outcome::Codel(n) => {
                                format!("with {}", c.codels[n].name.name)
                            }
                            genom_model::component::Outcome::End => "with end".to_owned(),
                            genom_model::component::Outcome::Report(r) => format!(
                                "with {}",
                                c.services[s]
                                    .reports
                                    .get(r)
                                    .map_or("?", |n| n.name.as_str())
                            ),
                        },
                        None => "(interrupted: its on-inter follows)".to_owned(),
                    };
                    let from_text = self.position_text(m.positions[usize::from(pos)]);
                    self.add_edge(
                        p,
                        Edge {
                            from,
                            to: idle,
                            event: event_id("finish"),
                            guard: Expr::and([self.frozen_ok(), self.at(s, pos)]),
                            clock_guard: Vec::new(),
                            statements: st,
                            urgent: false,
                            labels: label.clone(),
                            span: c.codels[codel].name.span,
                            description: format!(
                                "{}::{} ends {outcome} ({from_text}, outcome {fk}): {} {what}",
                                v.name, c.codels[codel].name.name, v.name
                            ),
                        },
                    );
                }
            }
        }
        // Wake-ups or rounds.
        match (t.period, t.period_clock, overrun) {
            (Some(per), Some(x), Some(ov)) => {
                let at_period = vec![ClockConstraint {
                    clock: x,
                    op: CmpOp::Ge,
                    bound: per,
                }];
                let mut st = vec![Stmt::Reset(x)];
                st.extend(self.fresh_round(k));
                st.extend(self.turn(k));
                self.add_edge(
                    p,
                    Edge {
                        from: idle,
                        to: idle,
                        event: event_id("wake"),
                        guard: Expr::and([
                            self.frozen_ok(),
                            Expr::eq(self.elig_sum(k), Expr::int(0)),
                        ]),
                        clock_guard: at_period.clone(),
                        statements: st,
                        urgent: false,
                        labels: Vec::new(),
                        span: th.name.span,
                        description: format!(
                            "{} wakes up (period {per}): every service at a ready position becomes eligible",
                            t.name
                        ),
                    },
                );
                self.idle_overruns(k, p, idle, ov, &at_period);
                for (&codel, &from) in &running {
                    // A codel that has run its whole WCET ends at this
                    // instant, before the wake-up (codel ends at the same
                    // instant take priority): only a codel that could still
                    // run makes the wake-up an overrun.
                    let w = self.wcet[codel.0 as usize];
                    if w == 0 {
                        continue;
                    }
                    let mut guard = at_period.clone();
                    guard.push(ClockConstraint {
                        clock: t.exec_clock,
                        op: CmpOp::Lt,
                        bound: w,
                    });
                    let label = self.net.processes[p.0 as usize].locations[from.0 as usize]
                        .labels
                        .clone();
                    self.add_edge(
                        p,
                        Edge {
                            from,
                            to: ov,
                            event: event_id("overrun"),
                            guard: self.frozen_ok(),
                            clock_guard: guard,
                            statements: Vec::new(),
                            urgent: false,
                            labels: label,
                            span: th.name.span,
                            description: format!(
                                "{} wakes up while a codel still runs, before its WCET: overrun",
                                t.name
                            ),
                        },
                    );
                }
            }
            _ => {
                let mut st = self.fresh_round(k);
                st.extend(self.turn(k));
                self.add_edge(
                    p,
                    Edge {
                        from: idle,
                        to: idle,
                        event: event_id("round"),
                        guard: self.round_guard(k),
                        clock_guard: Vec::new(),
                        statements: st,
                        urgent: true,
                        labels: Vec::new(),
                        span: th.name.span,
                        description: format!(
                            "{} starts a round: every service at a ready position becomes eligible",
                            t.name
                        ),
                    },
                );
            }
        }
    }

    /// The overruns of thread `k` woken up idle with services still to run
    /// a codel this period (the engine's `overrun_zone`): genuine when one
    /// of those codels has a positive WCET; when all take no time, only
    /// while one waits for a lock held by a running codel of another
    /// thread (or the control codel) that is below its WCET (at its WCET it
    /// ends first, at the same instant).
    pub(super) fn idle_overruns(
        &mut self,
        k: usize,
        p: ProcessId,
        idle: LocationId,
        ov: LocationId,
        at_period: &[ClockConstraint],
    ) {
        let t = self.thrs[k].clone();
        let mut positive = Vec::new();
        let mut zero = Vec::new();
        for (slot, &s) in t.members.iter().enumerate() {
            for pos in self.ready_positions(s) {
                let Some(codel) = self.machine(s).positions[usize::from(pos)].codel() else {
                    continue;
                };
                let at = Expr::and([
                    Expr::eq(Expr::elem(t.elig, slot as i64), Expr::int(1)),
                    self.at(s, pos),
                ]);
                if self.wcet[codel.0 as usize] > 0 {
                    positive.push(at);
                } else {
                    zero.push((at, codel));
                }
            }
        }
        let any_positive = Expr::or(positive);
        let span = self.c.threads[t.id].name.span;
        let mut edges = vec![(
            Expr::and([self.frozen_ok(), any_positive.clone()]),
            at_period.to_vec(),
            "a service still to run has a codel with a WCET",
        )];
        for (at, codel) in zero {
            for (holder, clock, w) in self.lock_holders(k, codel) {
                let mut cg = at_period.to_vec();
                cg.push(ClockConstraint {
                    clock,
                    op: CmpOp::Lt,
                    bound: w,
                });
                let guard = Expr::and([
                    self.frozen_ok(),
                    Expr::negation(any_positive.clone()),
                    at.clone(),
                    holder,
                ]);
                edges.push((
                    guard,
                    cg,
                    "a service still to run waits for a lock held by a running codel",
                ));
            }
        }
        for (guard, clock_guard, why) in edges {
            self.add_edge(
                p,
                Edge {
                    from: idle,
                    to: ov,
                    event: event_id("overrun"),
                    guard,
                    clock_guard,
                    statements: Vec::new(),
                    urgent: false,
                    labels: Vec::new(),
                    span,
                    description: format!("{} wakes up with work left ({why}): overrun", t.name),
                },
            );
        }
    }

    /// The running codels of other threads, and the control codels, that
    /// hold a lock `codel` of thread `k` needs: (it runs, its execution
    /// clock, its WCET), for those with a positive WCET.
    pub(super) fn lock_holders(&self, k: usize, codel: CodelId) -> Vec<(Expr, ClockId, i64)> {
        let uses = self.c.codels[codel].structures();
        let mut out = Vec::new();
        for (k2, t2) in self.thrs.iter().enumerate().filter(|&(k2, _)| k2 != k) {
            let _ = k2;
            for &s2 in &t2.members {
                for q in self.running_positions(s2) {
                    let Some(c2) = self.machine(s2).positions[usize::from(q)].codel() else {
                        continue;
                    };
                    let w = self.wcet[c2.0 as usize];
                    if w > 0 && conflict(&uses, &self.c.codels[c2].structures()) {
                        out.push((self.at(s2, q), t2.exec_clock, w));
                    }
                }
            }
        }
        if let (Some(ctl), Some(clock)) = (self.ctl, self.ctl_clock) {
            for r in &self.svcs {
                let Some(w) = r.ctl_wcet.filter(|&w| w > 0) else {
                    continue;
                };
                if conflict(&uses, &r.control_uses) {
                    out.push((
                        Expr::eq(Expr::var(ctl), Expr::int(i64::from(r.id.0))),
                        clock,
                        w,
                    ));
                }
            }
        }
        out
    }
}
