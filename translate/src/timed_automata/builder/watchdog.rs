//! The watchdogs' processes: arming and disarming with their service's
//! instance, the interrupt at the max-time, and the probe that finds a
//! max-time exceeded.

use genom_model::component::ServiceId;
use genom_model::timed_automata::{
    ClockConstraint, ClockId, CmpOp, Edge, Expr, LabelKind, Location, LocationId, ProcessId,
    ProcessKind, Stmt,
};

use super::graph::loc;
use super::{Builder, event_id};

impl<'a> Builder<'a> {
    pub(super) fn watchdog_process(&mut self, s: ServiceId) {
        let c = self.c;
        let svc = &c.services[s];
        let Some(mt) = svc.max_time else { return };
        let v = self.svc(s).clone();
        let Some((clock, max)) = v.watch else { return };
        let name = v.name.clone();
        let p = self.add_process(
            &format!("{name}_watchdog"),
            ProcessKind::Watchdog(s),
            mt.span,
            if v.watch_exact {
                format!("the max-time watchdog of {name}: interrupts its instance {max} after acknowledgment")
            } else {
                format!(
                    "the max-time watchdog of {name}: its codels loop and its max-time is beyond the exactly timed horizon, so it interrupts its instance at any time from {max} after acknowledgment on"
                )
            },
        );
        let fire = |b: &mut Builder<'a>, pending: bool| -> Vec<Stmt> {
            b.locals = 0;
            let affected = b.affected([s]);
            let (mut st, before) = b.save(&affected);
            if pending {
                st.extend(b.interrupt_pending(s));
            } else {
                st.extend(b.interrupt_main(s, true));
            }
            st.extend(b.settle(&affected, &before, None, false, &[]));
            st
        };
        let off = self.add_location(
            p,
            Location {
                initial: true,
                ..loc(
                    "off",
                    mt.span,
                    &format!("{name} has no instance the watchdog can interrupt"),
                )
            },
        );
        let bound = |op| ClockConstraint {
            clock,
            op,
            bound: max,
        };
        let on = self.add_location(
                p,
                Location {
                    invariant: if v.watch_exact {
                        vec![bound(CmpOp::Le)]
                    } else {
                        Vec::new()
                    },
                    ..loc(
                        "on",
                        mt.span,
                        &format!(
                            "{name} has a pending or interruptible active instance, acknowledged at most {max} ago"
                        ),
                    )
                },
            );
        let (arm, disarm) = self.arming(s).unwrap_or((Expr::FALSE, Expr::FALSE));
        let armed = v.armed.unwrap_or(self.net.frozen);
        self.add_edge(
            p,
            Edge {
                from: off,
                to: on,
                event: event_id("arm"),
                guard: arm,
                clock_guard: Vec::new(),
                statements: vec![Stmt::set(armed, Expr::int(1))],
                urgent: true,
                labels: Vec::new(),
                span: mt.span,
                description: format!("{name} has an instance to watch"),
            },
        );
        self.add_edge(
            p,
            Edge {
                from: on,
                to: off,
                event: event_id("disarm"),
                guard: disarm,
                clock_guard: Vec::new(),
                statements: vec![Stmt::set(armed, Expr::int(0))],
                urgent: true,
                labels: Vec::new(),
                span: mt.span,
                description: format!(
                    "{name} has no instance to watch any more (ended or interrupted)"
                ),
            },
        );
        let st = fire(self, false);
        self.add_edge(
            p,
            Edge {
                from: on,
                to: on,
                event: event_id("watchdog"),
                guard: Expr::and([self.frozen_ok(), self.watchable(s)]),
                clock_guard: vec![bound(CmpOp::Ge)],
                statements: st,
                urgent: false,
                labels: Vec::new(),
                span: mt.span,
                description: format!(
                    "max-time reached: the watchdog interrupts {name}'s active instance"
                ),
            },
        );
        let st = fire(self, true);
        self.add_edge(
            p,
            Edge {
                from: on,
                to: on,
                event: event_id("watchdog"),
                guard: Expr::and([self.frozen_ok(), Expr::eq(self.pend(s), Expr::int(1))]),
                clock_guard: vec![bound(CmpOp::Ge)],
                statements: st,
                urgent: false,
                labels: Vec::new(),
                span: mt.span,
                description: format!(
                    "max-time reached: the watchdog ends {name}'s pending instance (TIMEOUT)"
                ),
            },
        );
        // A looping service's max-time is enforced by its watchdog: no
        // deadline to miss, so no probe (the engine reports advice).
        if !self.machine(s).active_loop {
            self.watchdog_probe(p, s, on, (clock, max));
        }
    }

    /// The observer of a watchdog process `p` (location `on`): at the
    /// max-time, in a non-urgent state, it freezes every other process and
    /// checks whether time can pass the max-time (`late`).
    pub(super) fn watchdog_probe(
        &mut self,
        p: ProcessId,
        s: ServiceId,
        on: LocationId,
        (clock, max): (ClockId, i64),
    ) {
        let Some(mt) = self.c.services[s].max_time else {
            return;
        };
        let name = self.svc(s).name.clone();
        let bound = |op| ClockConstraint {
            clock,
            op,
            bound: max,
        };
        let probe = self.add_location(
            p,
            loc(
                "probe",
                mt.span,
                &format!("observer: at {name}'s max-time, everything else frozen, can time pass?"),
            ),
        );
        let label = self.fresh_label(&format!("timeout_{name}"));
        let late = self.add_labelled(
            p,
            Location {
                committed: true,
                labels: vec![label],
                ..loc(
                    "late",
                    mt.span,
                    &format!(
                        "{name}'s instance is still running after its max-time (max-time exceeded)"
                    ),
                )
            },
            Some(LabelKind::Timeout(s)),
        );
        let live = self.live(s);
        let urgency = self.engine_urgency();
        self.add_edge(
            p,
            Edge {
                from: on,
                to: probe,
                event: event_id("probe"),
                guard: Expr::and([self.frozen_ok(), live, Expr::negation(urgency)]),
                clock_guard: vec![bound(CmpOp::Ge)],
                statements: vec![Stmt::set(self.net.frozen, Expr::int(1))],
                urgent: false,
                labels: Vec::new(),
                span: mt.span,
                description: format!(
                    "observer: {name}'s max-time is reached in a state where time may pass; freeze everything else"
                ),
            },
        );
        self.add_edge(
            p,
            Edge {
                from: probe,
                to: late,
                event: event_id("exceed"),
                guard: Expr::TRUE,
                clock_guard: vec![bound(CmpOp::Gt)],
                statements: Vec::new(),
                urgent: false,
                labels: Vec::new(),
                span: mt.span,
                description: format!(
                    "observer: time passes beyond {name}'s max-time with its instance still running"
                ),
            },
        );
        self.add_edge(
            p,
            Edge {
                from: probe,
                to: on,
                event: event_id("resume"),
                guard: Expr::TRUE,
                clock_guard: vec![bound(CmpOp::Le)],
                statements: vec![Stmt::set(self.net.frozen, Expr::int(0))],
                urgent: false,
                labels: Vec::new(),
                span: mt.span,
                description: format!(
                    "observer: time cannot pass {name}'s max-time here; everything resumes"
                ),
            },
        );
    }
}
