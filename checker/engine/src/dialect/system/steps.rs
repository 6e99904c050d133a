//! The transitions of the untimed semantics: [`System::apply`] and the
//! steps it is made of (requests, interrupts, codels, watchdogs, endings,
//! urgent starts), with the trace events they write.

use genom_model::behaviour::{Effect, Ending, IDLE};
use genom_model::component::{CodelId, Outcome, ServiceId};
use genom_model::kinds::ServiceKind;
use genom_model::trace::{Event, TraceStep};

use super::{Action, Config, System};

impl<'a> System<'a> {
    /// Applies an action; `None` if it is not enabled. Trace events go to
    /// `events` when given.
    pub fn apply(
        &self,
        cfg: &Config,
        action: Action,
        events: &mut Option<&mut Vec<TraceStep>>,
    ) -> Option<Config> {
        let mut next = cfg.clone();
        self.apply_in_place(&mut next, action, events)
            .then_some(next)
    }

    /// [`Self::apply`] on `cfg` itself (no allocation): `false`, with `cfg`
    /// unspecified, if the action is not enabled.
    pub fn apply_in_place(
        &self,
        cfg: &mut Config,
        action: Action,
        events: &mut Option<&mut Vec<TraceStep>>,
    ) -> bool {
        let Some(i) = self.member_index(action.service()) else {
            return false;
        };
        let done = match action {
            Action::Request(_) => self.request(cfg, i, events),
            Action::Begin(_) => self.begin(cfg, i, events),
            Action::Finish(_, k) => self.finish(cfg, i, usize::from(k), events),
            Action::Watchdog(_, pending) => self.watchdog(cfg, i, pending, events),
        };
        if done.is_none() {
            return false;
        }
        self.closure(cfg, events);
        true
    }

    pub(super) fn request(
        &self,
        cfg: &mut Config,
        i: usize,
        ev: &mut Option<&mut Vec<TraceStep>>,
    ) -> Option<()> {
        if !self.request_enabled(cfg, i) {
            return None;
        }
        let s = self.members[i].service;
        self.emit(ev, Event::Request, s, None, || {
            (None, format!("a client requests `{}`", self.name(s)))
        });
        if let Some(control) = self.c.services[s].control {
            self.emit(ev, Event::Accept, s, Some(control), || {
                let f = self.function(control);
                (None, format!("control codel `{f}` accepts the request"))
            });
        }
        let mut mask = 0u64;
        for (bit, &t) in self.members[i].stops.iter().enumerate() {
            self.interrupt_pending(cfg, t, false, ev);
            self.interrupt_main(cfg, t, false, ev);
            if cfg.main[t] != IDLE {
                mask |= 1 << bit;
            }
        }
        cfg.pending[i] = Some(mask);
        self.emit(ev, Event::Acknowledge, s, None, || {
            (
                None,
                format!("`{}` is acknowledged (pending)", self.name(s)),
            )
        });
        Some(())
    }

    pub(super) fn interrupt_pending(
        &self,
        cfg: &mut Config,
        t: usize,
        watchdog: bool,
        ev: &mut Option<&mut Vec<TraceStep>>,
    ) {
        if cfg.pending[t].take().is_none() {
            return;
        }
        let s = self.members[t].service;
        let (event, reply) = if watchdog {
            (Event::Watchdog, "TIMEOUT")
        } else {
            (Event::Interrupt, "INTERRUPTED")
        };
        self.emit(ev, event, s, None, || {
            (
                None,
                format!("the pending instance of `{}` is interrupted", self.name(s)),
            )
        });
        self.emit_reply(ev, s, reply);
    }

    /// Interrupts the main instance of member `t` (steps 5, watchdog).
    pub(super) fn interrupt_main(
        &self,
        cfg: &mut Config,
        t: usize,
        watchdog: bool,
        ev: &mut Option<&mut Vec<TraceStep>>,
    ) {
        let Some(effect) = self.machine(t).interrupt[usize::from(cfg.main[t])] else {
            return;
        };
        let s = self.members[t].service;
        let at = self.position(cfg, t).codel();
        let who = if watchdog {
            "the max-time watchdog interrupts"
        } else {
            "interrupt"
        };
        let event = if watchdog {
            Event::Watchdog
        } else {
            Event::Interrupt
        };
        self.emit(ev, event, s, at, || {
            let place = at
                .map(|c| format!(" at `{}`", self.c.codels[c].name.name))
                .unwrap_or_default();
            (None, format!("{who} `{}`{place}", self.name(s)))
        });
        match effect {
            Effect::Goto(q) => {
                cfg.main[t] = q;
                cfg.timed_out[t] |= watchdog;
            }
            Effect::End(ending) => self.end(cfg, t, ending, watchdog, ev),
        }
    }

    pub(super) fn begin(
        &self,
        cfg: &mut Config,
        i: usize,
        ev: &mut Option<&mut Vec<TraceStep>>,
    ) -> Option<()> {
        let m = self.machine(i);
        let q = m.begin[usize::from(cfg.main[i])]?;
        let codel = m.positions[usize::from(q)].codel()?;
        if !self.can_begin(cfg, i, codel) {
            return None;
        }
        cfg.main[i] = q;
        let s = self.members[i].service;
        self.emit(ev, Event::CodelStart, s, Some(codel), || {
            let thread = m
                .thread
                .map_or("control", |t| self.c.threads[t].name.name.as_str());
            let text = format!("thread `{thread}` runs `{}`", self.c.codel_label(codel));
            (None, text)
        });
        Some(())
    }

    pub(super) fn finish(
        &self,
        cfg: &mut Config,
        i: usize,
        k: usize,
        ev: &mut Option<&mut Vec<TraceStep>>,
    ) -> Option<()> {
        let m = self.machine(i);
        let p = usize::from(cfg.main[i]);
        let f = *m.finish[p].get(k)?;
        let codel = m.positions[p].codel()?;
        let s = self.members[i].service;
        self.emit(ev, Event::CodelEnd, s, Some(codel), || {
            let outcome = f.outcome.map(|o| self.outcome_name(s, o));
            let label = self.c.codel_label(codel);
            let text = match &outcome {
                Some(o) => format!("`{label}` ends with `{o}`"),
                None => format!("`{label}` ends; the service was interrupted"),
            };
            (outcome, text)
        });
        match f.effect {
            Effect::Goto(q) => cfg.main[i] = q,
            Effect::End(ending) => self.end(cfg, i, ending, cfg.timed_out[i], ev),
        }
        Some(())
    }

    pub(super) fn watchdog(
        &self,
        cfg: &mut Config,
        i: usize,
        pending: bool,
        ev: &mut Option<&mut Vec<TraceStep>>,
    ) -> Option<()> {
        if !self.machine(i).watchdog {
            return None;
        }
        if pending {
            cfg.pending[i]?;
            self.interrupt_pending(cfg, i, true, ev);
        } else {
            self.machine(i).interrupt[usize::from(cfg.main[i])]?;
            self.interrupt_main(cfg, i, true, ev);
        }
        Some(())
    }

    /// The main instance of member `i` ends: reply, release waiters, and
    /// complete initialisation.
    pub(super) fn end(
        &self,
        cfg: &mut Config,
        i: usize,
        ending: Ending,
        timeout: bool,
        ev: &mut Option<&mut Vec<TraceStep>>,
    ) {
        cfg.main[i] = IDLE;
        cfg.timed_out[i] = false;
        let s = self.members[i].service;
        if ev.is_some() {
            let reply = match ending {
                Ending::Success => "end",
                Ending::Report(r) => self.c.services[s]
                    .reports
                    .get(r)
                    .map_or("", |r| r.name.as_str()),
                Ending::Interrupted if timeout => "TIMEOUT",
                Ending::Interrupted => "INTERRUPTED",
            };
            self.emit_reply(ev, s, reply);
        }
        for (k, m) in self.members.iter().enumerate() {
            if let Some(mask) = cfg.pending[k] {
                let ended: u64 = m
                    .stops
                    .iter()
                    .enumerate()
                    .filter(|&(_, &t)| t == i)
                    .map(|(bit, _)| 1 << bit)
                    .sum();
                cfg.pending[k] = Some(mask & !ended);
            }
        }
        if ending == Ending::Success && !cfg.init_done && self.init == Some(s) {
            cfg.init_done = true;
            // Not a second reply: the success reply just emitted completes
            // initialisation.
            if let Some(last) = ev.as_deref_mut().and_then(|sink| sink.last_mut()) {
                last.text.push_str("; initialisation completes");
            }
            self.start_autos(cfg, ev);
        }
    }

    /// Initialisation completes: every auto service becomes active at its
    /// start codel at once (section 3: autos are not requests, are never
    /// pending, and their `delays`/`forbids` about each other do not apply);
    /// one without start codel completes at once.
    pub(super) fn start_autos(&self, cfg: &mut Config, ev: &mut Option<&mut Vec<TraceStep>>) {
        for (i, m) in self.members.iter().enumerate() {
            if m.input
                || self.c.services[m.service].kind != ServiceKind::Auto
                || Self::has_instance(cfg, i)
            {
                continue;
            }
            let s = m.service;
            match self.machine(i).start {
                Some(p) => {
                    cfg.main[i] = p;
                    self.emit(ev, Event::Start, s, self.c.services[s].start, || {
                        (None, format!("auto service `{}` starts", self.name(s)))
                    });
                }
                None => {
                    self.emit(ev, Event::Start, s, None, || {
                        (
                            None,
                            format!("auto service `{}` completes at once", self.name(s)),
                        )
                    });
                    self.end(cfg, i, Ending::Success, false, ev);
                }
            }
        }
    }

    /// Starts every pending instance that can start (step 7), until none can.
    pub(crate) fn closure(&self, cfg: &mut Config, ev: &mut Option<&mut Vec<TraceStep>>) {
        loop {
            // Only a pending instance with nothing to wait for and no main
            // instance can start: test that first, it rules out most.
            let ready = (cfg.pending.iter().zip(&cfg.main))
                .position(|(&p, &m)| p == Some(0) && m == IDLE)
                .and_then(|first| (first..self.members.len()).find(|&i| self.can_start(cfg, i)));
            let Some(i) = ready else { return };
            cfg.pending[i] = None;
            let s = self.members[i].service;
            match self.machine(i).start {
                Some(p) => {
                    cfg.main[i] = p;
                    self.emit(ev, Event::Start, s, self.c.services[s].start, || {
                        (None, format!("`{}` starts", self.name(s)))
                    });
                }
                None => {
                    self.emit(ev, Event::Start, s, None, || {
                        (None, format!("`{}` completes at once", self.name(s)))
                    });
                    self.end(cfg, i, Ending::Success, false, ev);
                }
            }
        }
    }

    /// Step 7: not delayed, and no longer waiting for interrupted instances.
    pub(super) fn can_start(&self, cfg: &Config, i: usize) -> bool {
        !self.members[i].input
            && cfg.pending[i] == Some(0)
            && cfg.main[i] == IDLE
            && !self.members[i]
                .delayers
                .iter()
                .any(|&t| Self::has_instance(cfg, t))
    }

    /// Member `i`'s pending instance is blocked by these members' instances
    /// (`true`: through `delays`; `false`: waiting for an interrupted
    /// instance to end).
    pub fn blockers(&self, cfg: &Config, i: usize) -> Vec<(usize, bool)> {
        self.blockers_iter(cfg, i).collect()
    }

    /// [`Self::blockers`], without collecting them.
    pub fn blockers_iter<'s>(
        &'s self,
        cfg: &'s Config,
        i: usize,
    ) -> impl Iterator<Item = (usize, bool)> + 's {
        let mask = cfg.pending[i];
        let m = &self.members[i];
        let delayed = m
            .delayers
            .iter()
            .filter(move |&&t| mask.is_some() && Self::has_instance(cfg, t))
            .map(|&t| (t, true));
        let waiting = m
            .stops
            .iter()
            .enumerate()
            .filter(move |(b, _)| mask.is_some_and(|mask| mask & (1 << b) != 0))
            .map(|(_, &t)| (t, false));
        delayed.chain(waiting)
    }

    pub(super) fn name(&self, s: ServiceId) -> &'a str {
        &self.c.services[s].name.name
    }

    pub(super) fn function(&self, codel: CodelId) -> String {
        self.c.codels[codel].call.as_ref().map_or_else(
            || self.c.codels[codel].name.name.clone(),
            |c| c.function.name.clone(),
        )
    }

    pub(super) fn outcome_name(&self, s: ServiceId, o: Outcome) -> String {
        match o {
            Outcome::Codel(c) => self.c.codels[c].name.name.clone(),
            Outcome::End => "end".to_owned(),
            Outcome::Report(r) => self.c.services[s]
                .reports
                .get(r)
                .map_or_else(String::new, |r| r.name.clone()),
        }
    }

    pub(super) fn emit_reply(
        &self,
        ev: &mut Option<&mut Vec<TraceStep>>,
        s: ServiceId,
        reply: &str,
    ) {
        self.emit(ev, Event::Reply, s, None, || {
            (
                Some(reply.to_owned()),
                format!("`{}` replies {reply}", self.name(s)),
            )
        });
    }

    pub(super) fn emit(
        &self,
        ev: &mut Option<&mut Vec<TraceStep>>,
        event: Event,
        s: ServiceId,
        codel: Option<CodelId>,
        describe: impl FnOnce() -> (Option<String>, String),
    ) {
        let Some(sink) = ev.as_deref_mut() else {
            return;
        };
        let (outcome, text) = describe();
        let svc = &self.c.services[s];
        let thread = match event {
            Event::CodelStart | Event::CodelEnd => {
                let m = self.b.machine(s);
                Some(m.thread.map_or_else(
                    || "control".to_owned(),
                    |t| self.c.threads[t].name.name.clone(),
                ))
            }
            Event::Request | Event::Accept | Event::Acknowledge => Some("control".to_owned()),
            _ => None,
        };
        let span = codel.map_or(svc.name.span, |c| self.c.codels[c].name.span);
        sink.push(TraceStep {
            event,
            time_ns: None,
            thread,
            service: Some(svc.name.name.clone()),
            codel: codel.map(|c| self.c.codels[c].name.name.clone()),
            outcome,
            span: Some(span),
            text,
            aside: false,
        });
    }
}
