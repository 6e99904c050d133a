//! The transitions other than requests: urgent starts, clearing and
//! dropping wait tokens, codel begins and finishes, and watchdogs.

use genom_model::behaviour::{Effect, Ending, PosId, Position};
use genom_model::component::{CodelId, Outcome, ServiceId};
use genom_model::petri::{
    PRIORITY_CLEAR, PRIORITY_DROP, PRIORITY_START, PRIORITY_STEP, Transition, TransitionKind,
};

use super::{Arcs, Builder, others, position_name, position_text, stop_targets};

impl<'a> Builder<'a> {
    pub(super) fn service_transitions(&mut self, s: ServiceId) {
        self.request(s);
        self.start(s);
        self.clears(s);
        self.drops(s);
        self.codel_steps(s);
        self.watchdogs(s);
    }

    /// Step 7: the urgent start of a pending instance.
    pub(super) fn start(&mut self, s: ServiceId) {
        let name = self.name(s);
        let m = self.machine(s);
        let svc = &self.c.services[s];
        let span = svc
            .start
            .map_or(self.span(s), |k| self.c.codels[k].name.span);
        let label = match m.start {
            Some(_) => format!("{name} starts"),
            None => format!("{name} starts and completes at once"),
        };
        let mut t = Transition::new(
            format!("{name}.start"),
            label,
            span,
            PRIORITY_START,
            TransitionKind::Start(s),
        );
        let sp = self.sp(s);
        t = t
            .pre(sp.pending)
            .inhibit(sp.waits.iter().map(|w| w.1).collect::<Vec<_>>());
        for d in others(self.c, s, |x| &x.delays) {
            t = t.inhibit(self.instance_places(d));
        }
        match m.start {
            Some(p) => {
                let t = t.pre(self.idle(s)).post(self.pos(s, p));
                self.add(t);
            }
            None => {
                let t = t.read(self.idle(s));
                self.success(s, t);
            }
        }
    }

    /// Adds `t`, an ending with success of `s`: for the init service, one
    /// variant completes initialisation (and acknowledges the autos), one
    /// runs once initialisation is done.
    pub(super) fn success(&mut self, s: ServiceId, t: Transition) {
        if self.c.init_service() != Some(s) {
            self.add(t);
            return;
        }
        let mut first = t.clone();
        first.name.push_str(".init");
        first.label.push_str("; initialisation completes");
        first = first.pre(self.net.init_not_done).post(self.net.init_done);
        for a in self.autos() {
            let Some(p) = self.machine(a).start else {
                first
                    .label
                    .push_str(&format!(", {} completes at once", self.name(a)));
                continue;
            };
            first = first.pre(self.idle(a)).post(self.pos(a, p));
            first.label.push_str(&format!(", {} starts", self.name(a)));
        }
        self.add(first);
        self.add(t.read(self.net.init_done));
    }

    /// A wait token is cleared as soon as its target is idle.
    pub(super) fn clears(&mut self, s: ServiceId) {
        let name = self.name(s);
        for (k, (t, w)) in self.sp(s).waits.clone().into_iter().enumerate() {
            let tn = self.name(t);
            let span = stop_targets(self.c, s).get(k).map_or(self.span(s), |x| x.1);
            let label = format!("pending {name} no longer waits for {tn} (it ended)");
            let kind = TransitionKind::ClearWait(s, t);
            let tr = Transition::new(
                format!("{name}.clear.{tn}"),
                label,
                span,
                PRIORITY_CLEAR,
                kind,
            );
            self.add(tr.pre(w).read(self.idle(t)));
        }
    }

    /// The wait tokens of a removed pending instance are discarded.
    pub(super) fn drops(&mut self, s: ServiceId) {
        let Some(d) = self.sp(s).dropping else { return };
        let (name, span) = (self.name(s), self.span(s));
        let waits = self.sp(s).waits.clone();
        for &(t, w) in &waits {
            let tn = self.name(t);
            let label = format!("the removed pending {name} discards its wait for {tn}");
            let tr = Transition::new(
                format!("{name}.drop.{tn}"),
                label,
                span,
                PRIORITY_DROP,
                TransitionKind::Drop(s),
            );
            self.add(tr.pre(d).pre(w).post(d));
        }
        let label = format!("the removed pending {name} is gone");
        let tr = Transition::new(
            format!("{name}.dropped"),
            label,
            span,
            PRIORITY_DROP,
            TransitionKind::Drop(s),
        );
        self.add(
            tr.pre(d)
                .inhibit(waits.iter().map(|w| w.1).collect::<Vec<_>>()),
        );
    }

    /// Codel begin and finish transitions of every position.
    pub(super) fn codel_steps(&mut self, s: ServiceId) {
        let m = self.machine(s);
        for (k, &p) in m.positions.iter().enumerate() {
            let pid = PosId::try_from(k).unwrap_or(PosId::MAX);
            if let Some(q) = m.begin[k] {
                self.begin(s, pid, q);
            }
            for f in 0..m.finish[k].len() {
                self.finish(s, pid, p, f);
            }
        }
    }

    pub(super) fn begin(&mut self, s: ServiceId, p: PosId, q: PosId) {
        let m = self.machine(s);
        let Some(codel) = m.positions[usize::from(q)].codel() else {
            return;
        };
        let name = self.name(s);
        let thread = m
            .thread
            .map_or("control", |t| self.c.threads[t].name.name.as_str());
        let label = format!("{thread} runs {}", self.c.codel_label(codel));
        let id = format!(
            "{name}.begin.{}",
            position_name(self.c, m.positions[usize::from(p)])
        );
        let kind = TransitionKind::Begin(s, p);
        let tr = Transition::new(
            id,
            label,
            self.c.codels[codel].name.span,
            PRIORITY_STEP,
            kind,
        );
        let locks = self.locked_by(codel, m.thread.map(|t| (s, t)));
        let tr = tr.pre(self.pos(s, p)).post(self.pos(s, q)).inhibit(locks);
        self.add(tr);
    }

    pub(super) fn finish(&mut self, s: ServiceId, pid: PosId, p: Position, k: usize) {
        let m = self.machine(s);
        let f = m.finish[usize::from(pid)][k];
        let Some(codel) = p.codel() else { return };
        let name = self.name(s);
        let label = self.finish_label(s, codel, f.outcome, f.effect);
        let id = format!("{name}.finish.{}.{k}", position_name(self.c, p));
        let kind = TransitionKind::Finish(s, pid, k);
        let tr = Transition::new(
            id,
            label,
            self.c.codels[codel].name.span,
            PRIORITY_STEP,
            kind,
        );
        let tr = tr.pre(self.pos(s, pid));
        match f.effect {
            Effect::Goto(q) => {
                let tr = tr.post(self.pos(s, q));
                self.add(tr);
            }
            Effect::End(e) => {
                let tr = tr.post(self.idle(s));
                if e == Ending::Success {
                    self.success(s, tr);
                } else {
                    self.add(tr);
                }
            }
        }
    }

    pub(super) fn finish_label(
        &self,
        s: ServiceId,
        codel: CodelId,
        outcome: Option<Outcome>,
        effect: Effect,
    ) -> String {
        let what = self.c.codel_label(codel);
        let name = self.name(s);
        let ends = match effect {
            Effect::End(Ending::Success) => format!("{name} ends (success)"),
            Effect::End(Ending::Report(r)) => format!("{name} ends ({})", self.report(s, r)),
            Effect::End(Ending::Interrupted) => format!("{name} ends (INTERRUPTED or TIMEOUT)"),
            Effect::Goto(q) => {
                let at = position_text(self.c, self.machine(s).positions[usize::from(q)]);
                format!("{name} {at}")
            }
        };
        match outcome {
            Some(o) => format!("{what} ends with {} -> {ends}", self.outcome(s, o)),
            None => format!("{what} ends, interrupted -> {ends}"),
        }
    }

    pub(super) fn report(&self, s: ServiceId, r: usize) -> &'a str {
        self.c.services[s]
            .reports
            .get(r)
            .map_or("?", |n| n.name.as_str())
    }

    pub(super) fn outcome(&self, s: ServiceId, o: Outcome) -> String {
        match o {
            Outcome::Codel(k) => self.c.codels[k].name.name.clone(),
            Outcome::End => "end".to_owned(),
            Outcome::Report(r) => self.report(s, r).to_owned(),
        }
    }

    /// The max-time watchdog: on the pending instance, and at every
    /// interruptible position.
    pub(super) fn watchdogs(&mut self, s: ServiceId) {
        let m = self.machine(s);
        let Some(max) = self.c.services[s].max_time.filter(|_| m.watchdog) else {
            return;
        };
        let name = self.name(s);
        let label = format!("the watchdog interrupts the pending {name} (TIMEOUT)");
        let kind = TransitionKind::Watchdog(s, None);
        let tr = Transition::new(
            format!("{name}.watchdog.pending"),
            label,
            max.span,
            PRIORITY_STEP,
            kind,
        );
        let mut tr = tr.pre(self.sp(s).pending);
        if let Some(d) = self.sp(s).dropping {
            tr = tr.post(d);
        }
        self.add(tr);
        for (k, &p) in m.positions.iter().enumerate() {
            let Some(effect) = m.interrupt[k] else {
                continue;
            };
            let pid = PosId::try_from(k).unwrap_or(PosId::MAX);
            let label = format!(
                "the watchdog interrupts {name} {}",
                position_text(self.c, p)
            );
            let id = format!("{name}.watchdog.{}", position_name(self.c, p));
            let kind = TransitionKind::Watchdog(s, Some(pid));
            let tr =
                Transition::new(id, label, max.span, PRIORITY_STEP, kind).pre(self.pos(s, pid));
            let to = match effect {
                Effect::Goto(q) => self.pos(s, q),
                Effect::End(_) => self.idle(s),
            };
            self.add(tr.post(to));
        }
    }
}
