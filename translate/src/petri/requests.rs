//! The request of a service: the step-level transition with the gates of
//! steps 1–4, then its chain of request-level micro-steps (remove pending
//! instances, interrupt the `stops` targets, acknowledge).

use genom_model::behaviour::{Effect, IDLE, Position};
use genom_model::component::{CodelId, Idx, ServiceId, ThreadId};
use genom_model::petri::{
    PRIORITY_REQUEST, PRIORITY_STEP, PlaceId, PlaceKind, Transition, TransitionKind,
};
use genom_model::span::Span;

use super::{Arcs, Builder, others, position_name, position_text, stop_targets};

impl<'a> Builder<'a> {
    /// Steps 1–4 as the arcs of one transition, then the chain.
    pub(super) fn request(&mut self, s: ServiceId) {
        let name = self.name(s);
        let svc = &self.c.services[s];
        let span = svc
            .control
            .map_or(self.span(s), |k| self.c.codels[k].name.span);
        let label = format!("request {name} (accepted)");
        let mut t = Transition::new(
            format!("{name}.request"),
            label,
            span,
            PRIORITY_STEP,
            TransitionKind::Request(s),
        );
        if self.c.init_service().is_some_and(|i| i != s) {
            t = t.read(self.net.init_done);
        }
        for f in others(self.c, s, |x| &x.forbids) {
            t = t.inhibit(self.instance_places(f));
        }
        if !svc.stops.iter().any(|r| r.id == s) {
            t = t.inhibit(self.instance_places(s));
        }
        if let Some(control) = svc.control {
            t = t.inhibit(self.locked_by(control, None));
        }
        self.request_chain(s, t);
    }

    /// Running places whose codel conflicts with `codel`, or that belong to
    /// another service of `thread` (given as the service `codel` belongs to
    /// and its thread; that service's own places are left out).
    pub(super) fn locked_by(
        &self,
        codel: CodelId,
        thread: Option<(ServiceId, ThreadId)>,
    ) -> Vec<PlaceId> {
        let mut out = Vec::new();
        for j in self.c.services.ids() {
            let same = match thread {
                Some((me, _)) if me == j => continue,
                Some((_, th)) => self.machine(j).thread == Some(th),
                None => false,
            };
            for (p, d) in self.running_places(j) {
                if same || self.c.conflicts(codel, d) {
                    out.push(p);
                }
            }
        }
        out
    }

    pub(super) fn stage(&mut self, s: ServiceId, what: &str) -> PlaceId {
        let n = self
            .net
            .places
            .iter()
            .filter(|p| matches!(p.kind, PlaceKind::Request(x, _) if x == s))
            .count();
        let n = u16::try_from(n).unwrap_or(u16::MAX);
        let name = self.name(s);
        let label = format!("request {name} accepted, next: {what}");
        self.add_place(
            format!("{name}.req.{n}"),
            label,
            self.span(s),
            PlaceKind::Request(s, n),
        )
    }

    /// The micro-steps of a request after its gate `gate`: own pending
    /// instance (self-stop), then each target, then the acknowledgment.
    pub(super) fn request_chain(&mut self, s: ServiceId, gate: Transition) {
        let targets = stop_targets(self.c, s);
        if targets.is_empty() {
            let p = self.sp(s).pending;
            self.add(gate.post(p));
            return;
        }
        let self_stop = targets.iter().find(|t| t.0 == s).copied();
        let first = match self_stop {
            Some(_) => format!("interrupt the pending {}", self.name(s)),
            None => self.step_text(s, &targets, 0),
        };
        let mut stage = self.stage(s, &first);
        self.add(gate.post(stage));
        if let Some(me) = self_stop {
            let what = self.step_text(s, &targets, 0);
            stage = self.remove_pending(s, me, stage, &what);
        }
        for (k, &target) in targets.iter().enumerate() {
            if target.0 != s {
                let what = format!("interrupt {}", self.name(target.0));
                stage = self.remove_pending(s, target, stage, &what);
            }
            let what = self.step_text(s, &targets, k + 1);
            stage = self.interrupt_main(s, k, target, stage, &what);
        }
        self.acknowledge(s, stage);
    }

    /// What the chain of `s` does at target `k` (or acknowledges).
    pub(super) fn step_text(
        &self,
        s: ServiceId,
        targets: &[(ServiceId, Span)],
        k: usize,
    ) -> String {
        match targets.get(k) {
            Some(&(u, _)) if u != s => format!("interrupt the pending {}", self.name(u)),
            Some(&(u, _)) => format!("interrupt {}", self.name(u)),
            None => "acknowledge".to_owned(),
        }
    }

    pub(super) fn acknowledge(&mut self, s: ServiceId, stage: PlaceId) {
        let name = self.name(s);
        let label = format!("request {name}: acknowledge (pending)");
        let kind = TransitionKind::Acknowledge(s);
        let t = Transition::new(
            format!("{name}.ack"),
            label,
            self.span(s),
            PRIORITY_REQUEST,
            kind,
        );
        let p = self.sp(s).pending;
        self.add(t.pre(stage).post(p));
    }

    /// Removes the pending instance of `t` if any; returns the next stage,
    /// labelled `what`.
    pub(super) fn remove_pending(
        &mut self,
        s: ServiceId,
        target: (ServiceId, Span),
        stage: PlaceId,
        what: &str,
    ) -> PlaceId {
        let (t, span) = target;
        let (name, tn) = (self.name(s), self.name(t));
        let next = self.stage(s, what);
        let n = self.stage_number(stage);
        let kind = TransitionKind::RequestStep(s);
        let label = format!("request {name}: interrupt the pending {tn}");
        let id = format!("{name}.req.{n}.pending.{tn}");
        let yes = Transition::new(id, label, span, PRIORITY_REQUEST, kind);
        let pending = self.sp(t).pending;
        let mut yes = yes.pre(stage).pre(pending).post(next);
        if let Some(d) = self.sp(t).dropping {
            yes = yes.post(d);
        }
        self.add(yes);
        let label = format!("request {name}: {tn} has no pending instance");
        let id = format!("{name}.req.{n}.nopending.{tn}");
        let no = Transition::new(id, label, span, PRIORITY_REQUEST, kind);
        self.add(no.pre(stage).inhibit([pending]).post(next));
        next
    }

    pub(super) fn stage_number(&self, stage: PlaceId) -> u16 {
        match self.net.places.get(stage.index()).map(|p| p.kind) {
            Some(PlaceKind::Request(_, n)) => n,
            _ => 0,
        }
    }

    /// Step 5 on the main instance of the `k`-th target: one micro-step per
    /// position of the target; marks the wait place unless the target is
    /// (then) idle. Returns the next stage, labelled `what`.
    pub(super) fn interrupt_main(
        &mut self,
        s: ServiceId,
        k: usize,
        target: (ServiceId, Span),
        stage: PlaceId,
        what: &str,
    ) -> PlaceId {
        let (t, span) = target;
        let next = self.stage(s, what);
        let n = self.stage_number(stage);
        let wait = self.sp(s).waits[k].1;
        let m = self.machine(t);
        for (pi, &p) in m.positions.iter().enumerate() {
            let place = self.sp(t).positions[pi];
            let tr = self.interrupt_step(s, t, p, n, span).pre(stage).post(next);
            let tr = match m.interrupt[pi] {
                Some(Effect::Goto(q)) => tr.pre(place).post(self.pos(t, q)).post(wait),
                Some(Effect::End(_)) => tr.pre(place).post(self.idle(t)),
                None if pi == usize::from(IDLE) => tr.read(place),
                None => tr.read(place).post(wait),
            };
            self.add(tr);
        }
        next
    }

    pub(super) fn interrupt_step(
        &self,
        s: ServiceId,
        t: ServiceId,
        p: Position,
        n: u16,
        span: Span,
    ) -> Transition {
        let (name, tn) = (self.name(s), self.name(t));
        let at = position_text(self.c, p);
        let m = self.machine(t);
        let effect = m.find(p).and_then(|k| m.interrupt[usize::from(k)]);
        let label = match (effect, p) {
            (Some(Effect::End(_)), _) => {
                format!("request {name}: interrupt {tn} {at}: it ends (INTERRUPTED)")
            }
            (Some(_), _) => format!("request {name}: interrupt {tn} {at}"),
            (None, Position::Idle) => format!("request {name}: {tn} is idle"),
            (None, _) => format!("request {name}: {tn} {at} is already interrupted; wait for it"),
        };
        let id = format!("{name}.req.{n}.{tn}.{}", position_name(self.c, p));
        Transition::new(
            id,
            label,
            span,
            PRIORITY_REQUEST,
            TransitionKind::RequestStep(s),
        )
    }
}
