//! The control thread's process: the component start, requests, and the
//! control codels.

use std::collections::BTreeSet;

use genom_model::component::ServiceId;
use genom_model::timed_automata::{
    ClockConstraint, CmpOp, Edge, Expr, LabelKind, Location, ProcessKind, Stmt,
};

use super::bookkeeping::Before;
use super::graph::loc;
use super::{Builder, event_id};

impl<'a> Builder<'a> {
    pub(super) fn control_process(&mut self) {
        let c = self.c;
        let p = self.add_process(
            "control_thread",
            ProcessKind::Control,
            c.name.span,
            "the control thread: handles client requests one at a time and runs control codels"
                .to_owned(),
        );
        let start = self.add_location(
            p,
            loc(
                "start",
                c.name.span,
                "the component starts (committed: the start step happens at time 0)",
            ),
        );
        self.net.processes[p.0 as usize].locations[0].initial = true;
        self.net.processes[p.0 as usize].locations[0].committed = true;
        let idle = self.add_location(p, loc("idle", c.name.span, "no request being handled"));
        // The start: autos, urgent starts, bookkeeping, first wake-ups.
        self.locals = 0;
        let all: BTreeSet<ServiceId> = c.services.ids().collect();
        let mut st = Vec::new();
        if c.init_service().is_none() {
            st.extend(self.start_autos());
            st.extend(self.closure(&all));
        }
        st.extend(self.bookkeep(&all, &Before::default(), None, true));
        for k in 0..self.thrs.len() {
            if self.thrs[k].period.is_some() {
                st.extend(self.fresh_round(k));
            }
        }
        for k in 0..self.thrs.len() {
            st.extend(self.turn(k));
        }
        self.add_edge(
            p,
            Edge {
                from: start,
                to: idle,
                event: event_id("setup"),
                guard: Expr::TRUE,
                clock_guard: Vec::new(),
                statements: st,
                urgent: false,
                labels: Vec::new(),
                span: c.name.span,
                description: "the component starts: auto services are acknowledged (without init service) and start, periodic threads wake up".to_owned(),
            },
        );
        for s in c.services.ids() {
            let svc = &c.services[s];
            let name = svc.name.name.clone();
            let v = self.svc(s).clone();
            let enabled = self.request_enabled(s);
            match (v.ctl_wcet, svc.control, self.ctl, self.ctl_clock) {
                (Some(w), Some(k), Some(ctl), Some(clock)) => {
                    let span = c.codels[k].name.span;
                    let label = self.fresh_label(&format!("codel_{name}_control"));
                    let l = self.add_labelled(
                        p,
                        Location {
                            invariant: vec![ClockConstraint {
                                clock,
                                op: CmpOp::Le,
                                bound: w,
                            }],
                            labels: vec![label.clone()],
                            ..loc(
                                &format!("{name}_control"),
                                span,
                                &format!("the control codel of {name} runs (WCET {w})"),
                            )
                        },
                        Some(LabelKind::Codel(k)),
                    );
                    let guard = Expr::and([
                        self.frozen_ok(),
                        enabled.clone(),
                        Expr::negation(self.thread_waits_for(s)),
                    ]);
                    self.add_edge(
                        p,
                        Edge {
                            from: idle,
                            to: l,
                            event: event_id("request"),
                            guard,
                            clock_guard: Vec::new(),
                            statements: vec![
                                Stmt::set(ctl, Expr::int(i64::from(s.0))),
                                Stmt::Reset(clock),
                            ],
                            urgent: false,
                            labels: Vec::new(),
                            span: svc.name.span,
                            description: format!(
                                "a client requests {name} (not initialising, not forbidden, not busy, locks free, no thread waiting for them): its control codel runs"
                            ),
                        },
                    );
                    let mut st = vec![Stmt::set(ctl, Expr::int(c.services.len() as i64))];
                    st.extend(self.request(s));
                    self.add_edge(
                        p,
                        Edge {
                            from: l,
                            to: idle,
                            event: event_id("accept"),
                            guard: Expr::and([self.frozen_ok(), enabled]),
                            clock_guard: Vec::new(),
                            statements: st,
                            urgent: false,
                            labels: vec![label.clone()],
                            span,
                            description: format!(
                                "the control codel accepts: {name}'s stops targets are interrupted, {name} is acknowledged and starts when it can"
                            ),
                        },
                    );
                    if !svc.reports.is_empty() {
                        self.add_edge(
                            p,
                            Edge {
                                from: l,
                                to: idle,
                                event: event_id("reject"),
                                guard: self.frozen_ok(),
                                clock_guard: Vec::new(),
                                statements: vec![Stmt::set(
                                    ctl,
                                    Expr::int(c.services.len() as i64),
                                )],
                                urgent: false,
                                labels: vec![label],
                                span,
                                description: format!(
                                    "the control codel rejects the request of {name} with a report"
                                ),
                            },
                        );
                    }
                }
                _ => {
                    let st = self.request(s);
                    self.add_edge(
                        p,
                        Edge {
                            from: idle,
                            to: idle,
                            event: event_id("request"),
                            guard: Expr::and([self.frozen_ok(), enabled]),
                            clock_guard: Vec::new(),
                            statements: st,
                            urgent: false,
                            labels: Vec::new(),
                            span: svc.name.span,
                            description: format!(
                                "a client requests {name} (no control codel): its stops targets are interrupted, it is acknowledged and starts when it can"
                            ),
                        },
                    );
                }
            }
        }
    }
}
