//! The timed transitions: time passing under the invariants (with
//! extrapolation), wake-ups and rounds, and firing an untimed action with
//! its clock resets and trace events.

use genom_model::behaviour::IDLE;
use genom_model::component::{CodelId, ServiceId};
use genom_model::kinds::ServiceKind;
use genom_model::trace::TraceStep;

use super::{Change, TAction, TState, TimedSystem, Violation};
use crate::dialect::system::{Action, Config, System, conflict};
use crate::kernel::explore::Model;
use crate::zones::dbm::{Dbm, lt};

impl<'a> TimedSystem<'a> {
    /// Lets time pass (unless urgent) under the invariants, and
    /// extrapolates when asked.
    pub fn settle_with(&self, mut st: TState, extrapolate: bool) -> TState {
        if st.violation.is_none() && !self.urgent(&st) {
            st.zone.up();
        }
        for (x, c) in self.invariants(&st, None) {
            st.zone.upper(x, c);
        }
        // After the delay: a clock freed before it would still record that
        // it is at least as old as the others.
        self.free_dead_clocks(&mut st);
        self.free_endless_responses(&mut st);
        if extrapolate && !st.zone.is_empty() {
            st.zone.extrapolate(&self.clocks.lower, &self.clocks.upper);
        }
        st
    }

    /// Frees the clocks whose value no longer matters: the execution clock
    /// of a thread that runs no codel, the control clock when no request is
    /// being handled (active-clock reduction: fewer, larger zones).
    pub(super) fn free_dead_clocks(&self, st: &mut TState) {
        for (k, t) in self.threads.iter().enumerate() {
            if !self.thread_busy(st, k) {
                st.zone.free(t.exec_clock);
            }
        }
        if st.ctl.is_none() {
            st.zone.free(self.ctl_clock);
        }
    }

    /// Starts a new period of thread `k`, or records an overrun.
    pub(super) fn wake(&self, st: &mut TState, k: usize) {
        if self.unfinished(st, k) {
            st.violation = Some(Violation::Overrun(u16::try_from(k).unwrap_or(u16::MAX)));
            return;
        }
        st.eligible[k] = self.fresh_round(st, k);
        if let Some(x) = self.threads[k].period_clock {
            st.zone.reset(x);
        }
    }

    /// Thread `k` still runs a codel or has services left to run in the
    /// current period.
    pub(super) fn unfinished(&self, st: &TState, k: usize) -> bool {
        st.eligible[k] != 0 || self.thread_busy(st, k)
    }

    /// The part of `zone` (at a wake-up of thread `k` with work left from
    /// the previous period) where the overrun is genuine; `None` when that
    /// work can all finish at the wake-up instant, which then comes after
    /// it (codel ends and zero-time steps at an instant take priority over
    /// a wake-up at the same instant). Genuine:
    ///
    /// - while the thread runs a codel: only where its execution clock is
    ///   strictly below its WCET (at its WCET it ends first, and what is
    ///   left is judged then, at the same instant);
    /// - else, when a service still to run a codel has a positive WCET: the
    ///   whole zone (it has not started, and may take time);
    /// - else (codels without WCET): where one of them waits for a lock
    ///   held by a running codel of another thread, or by the control
    ///   codel, whose clock is strictly below its WCET (the first such part
    ///   not empty: one witness is enough, the state is a terminal
    ///   violation).
    pub(super) fn overrun_zone(&self, st: &TState, zone: &Dbm, k: usize) -> Option<Dbm> {
        let t = &self.threads[k];
        let below = |clock: usize, w: i64| {
            let mut z = zone.clone();
            z.constrain(clock, 0, lt(w)).then_some(z)
        };
        if let Some(c) = self.running_on(st, k) {
            return below(t.exec_clock, self.wcet[c.0 as usize]);
        }
        let waiting: Vec<CodelId> = t
            .members
            .iter()
            .enumerate()
            .filter(|&(slot, _)| st.eligible[k] & (1 << slot) != 0)
            .filter_map(|(_, &i)| self.sys.position(&st.cfg, i).codel())
            .collect();
        if waiting.iter().any(|c| self.wcet[c.0 as usize] > 0) {
            return Some(zone.clone());
        }
        waiting
            .iter()
            .flat_map(|&c| self.lock_holders(st, k, self.sys.codel_uses(c)))
            .find_map(|(clock, w)| below(clock, w))
    }

    /// The execution clocks and WCETs of the running codels of threads
    /// other than `k`, and of the running control codel, that conflict
    /// with `uses`.
    pub(super) fn lock_holders(
        &self,
        st: &TState,
        k: usize,
        uses: &[(genom_model::component::StructureId, bool)],
    ) -> Vec<(usize, i64)> {
        let mut out = Vec::new();
        for (_, t2) in self.threads.iter().enumerate().filter(|&(k2, _)| k2 != k) {
            let held = t2
                .members
                .iter()
                .find_map(|&i| self.running_codel(&st.cfg, i))
                .filter(|&c| conflict(uses, self.sys.codel_uses(c)));
            if let Some(c) = held {
                out.push((t2.exec_clock, self.wcet[c.0 as usize]));
            }
        }
        if let Some(r) = st.ctl.map(usize::from) {
            if conflict(uses, self.sys.control_uses(r)) {
                out.push((self.ctl_clock, self.ctl_wcet[r].unwrap_or(0)));
            }
        }
        out
    }

    pub(super) fn fresh_round(&self, st: &TState, k: usize) -> u64 {
        self.threads[k]
            .members
            .iter()
            .enumerate()
            .filter(|&(_, &i)| self.active_ready(&st.cfg, i))
            .map(|(slot, _)| 1u64 << slot)
            .sum()
    }

    /// Clock resets and thread bookkeeping after the untimed configuration
    /// changed from `before` to `st.cfg`; `requested` is the member whose
    /// request was accepted, `initial` marks the component start.
    pub(super) fn bookkeep(
        &self,
        before: &Config,
        st: &mut TState,
        requested: Option<usize>,
        initial: bool,
    ) {
        let autos_acknowledged = !before.init_done && st.cfg.init_done;
        for i in 0..self.sys.len() {
            let auto = self.c.services[self.sys.service(i)].kind == ServiceKind::Auto;
            let acked = requested == Some(i)
                || (autos_acknowledged && auto)
                || (initial && System::has_instance(&st.cfg, i));
            let change = self.change(before, &st.cfg, i, acked);
            self.instance_clocks(before, st, i, change);
            self.response_clocks(before, st, i, change);
            self.instance_threads(st, i, change);
        }
    }

    /// What happened to member `i`'s instances.
    pub(super) fn change(&self, before: &Config, after: &Config, i: usize, acked: bool) -> Change {
        let start = self.sys.machine_of(i).start;
        let started = before.pending[i].is_some()
            && after.pending[i].is_none()
            && start.is_some_and(|p| after.main[i] == p && before.main[i] != p);
        let started = started || (acked && after.pending[i].is_none() && after.main[i] != IDLE);
        let ended = before.main[i] != IDLE && (after.main[i] == IDLE || started);
        Change {
            acked,
            started,
            ended,
        }
    }

    /// Watchdog clocks: reset at acknowledgment, carried along when the
    /// pending instance changes clock or starts, freed when unused.
    pub(super) fn instance_clocks(&self, before: &Config, st: &mut TState, i: usize, ch: Change) {
        let Some((main, pend)) = self.watch[i] else {
            return;
        };
        let pend_clock = |cfg: &Config| if cfg.main[i] == IDLE { main } else { pend };
        if ch.acked {
            let clock = if ch.started {
                main
            } else {
                pend_clock(&st.cfg)
            };
            st.zone.reset(clock);
        } else if before.pending[i].is_some() {
            let from = pend_clock(before);
            let to = if ch.started {
                main
            } else {
                pend_clock(&st.cfg)
            };
            if from != to && (ch.started || st.cfg.pending[i].is_some()) {
                st.zone.copy(to, from);
            }
        }
        let main_live =
            self.watchable(&st.cfg, i) || (st.cfg.pending[i].is_some() && st.cfg.main[i] == IDLE);
        let pend_live = pend != main && st.cfg.pending[i].is_some() && st.cfg.main[i] != IDLE;
        if !main_live {
            st.zone.free(main);
        }
        if pend != main && !pend_live {
            st.zone.free(pend);
        }
    }

    /// Eligibility in the current period and acknowledgment order.
    pub(super) fn instance_threads(&self, st: &mut TState, i: usize, ch: Change) {
        let Some((k, slot)) = self.placement[i] else {
            return;
        };
        if ch.ended {
            st.eligible[k] &= !(1u64 << slot);
        }
        let s = u8::try_from(slot).unwrap_or(u8::MAX);
        if ch.acked {
            st.order[k].retain(|&x| x != s);
            st.order[k].push(s);
        } else if !System::has_instance(&st.cfg, i) {
            st.order[k].retain(|&x| x != s);
        }
    }

    /// The successor of `st` by `a`, before time passes; `None` when not
    /// enabled or the guard is not satisfiable.
    pub fn fire(
        &self,
        st: &TState,
        a: TAction,
        events: &mut Option<&mut Vec<TraceStep>>,
    ) -> Option<TState> {
        if st.violation.is_some() {
            return None;
        }
        let mut next = st.clone();
        match a {
            TAction::Step(action) => self.fire_step(st, &mut next, action, events)?,
            TAction::RequestBegin(s) => {
                let i = self.sys.member_index(s)?;
                if self.ctl_wcet[i].is_none()
                    || !self.request_open(st, i)
                    || self.thread_waits_for(st, i)
                {
                    return None;
                }
                next.ctl = Some(u16::try_from(i).ok()?);
                next.zone.reset(self.ctl_clock);
                self.emit_control(events, s, true);
            }
            TAction::RequestEnd(s, accept) => {
                let i = self.sys.member_index(s)?;
                if st.ctl != Some(u16::try_from(i).ok()?) {
                    return None;
                }
                next.ctl = None;
                if accept {
                    next.cfg = self.accept(&st.cfg, s, events)?;
                    self.bookkeep(&st.cfg, &mut next, Some(i), false);
                } else {
                    if self.c.services[s].reports.is_empty() {
                        return None;
                    }
                    self.emit_control(events, s, false);
                }
            }
            TAction::WakeUp(k) => {
                let k = usize::from(k);
                let (p, x) = (self.threads.get(k)?.period?, self.threads[k].period_clock?);
                if !next.zone.lower(x, p) {
                    return None;
                }
                if self.unfinished(st, k) {
                    next.zone = self.overrun_zone(st, &next.zone, k)?;
                }
                self.emit_wake(events, k);
                self.wake(&mut next, k);
            }
            TAction::Round(k) => {
                let k = usize::from(k);
                if !self.round_enabled(st, k) {
                    return None;
                }
                next.eligible[k] = self.fresh_round(st, k);
            }
        }
        Some(next)
    }

    pub(super) fn fire_step(
        &self,
        st: &TState,
        next: &mut TState,
        action: Action,
        events: &mut Option<&mut Vec<TraceStep>>,
    ) -> Option<()> {
        let i = self.sys.member_index(action.service())?;
        match action {
            Action::Request(_) => {
                if self.ctl_wcet[i].is_some() || !self.request_open(st, i) {
                    return None;
                }
            }
            Action::Begin(_) => {
                if !self.may_begin(st, i) {
                    return None;
                }
                let (k, _) = self.placement[i]?;
                next.zone.reset(self.threads[k].exec_clock);
            }
            Action::Finish(..) => {
                let (k, slot) = self.placement[i]?;
                next.eligible[k] &= !(1u64 << slot);
            }
            Action::Watchdog(_, pending) => {
                if let (Some((main, pend)), Some(max)) = (self.watch[i], self.max_time[i]) {
                    let clock = if pending && st.cfg.main[i] != IDLE {
                        pend
                    } else {
                        main
                    };
                    if !next.zone.lower(clock, max) {
                        return None;
                    }
                }
            }
        }
        next.cfg = self.sys.apply(&st.cfg, action, events)?;
        let requested = matches!(action, Action::Request(_)).then_some(i);
        self.bookkeep(&st.cfg, next, requested, false);
        Some(())
    }

    /// The symbolic successor: fire, then let time pass.
    pub fn post(&self, st: &TState, a: TAction) -> Option<TState> {
        let fired = self.fire(st, a, &mut None)?;
        let settled = self.settle_with(fired, self.extrapolate);
        (!settled.zone.is_empty()).then_some(settled)
    }

    /// The untimed request of `s`, handled when its control codel accepts
    /// it; its events without the untimed `request` step (the request was
    /// written when the control codel began: one `request` per request).
    pub(super) fn accept(
        &self,
        cfg: &Config,
        s: ServiceId,
        events: &mut Option<&mut Vec<TraceStep>>,
    ) -> Option<Config> {
        let Some(sink) = events.as_deref_mut() else {
            return self.sys.apply(cfg, Action::Request(s), &mut None);
        };
        let mut steps = Vec::new();
        let next = self
            .sys
            .apply(cfg, Action::Request(s), &mut Some(&mut steps))?;
        if steps
            .first()
            .is_some_and(|x| x.event == genom_model::Event::Request)
        {
            steps.remove(0);
        }
        sink.extend(steps);
        Some(next)
    }

    pub(super) fn emit_control(
        &self,
        events: &mut Option<&mut Vec<TraceStep>>,
        s: ServiceId,
        begin: bool,
    ) {
        let Some(sink) = events.as_deref_mut() else {
            return;
        };
        let svc = &self.c.services[s];
        let (event, text) = if begin {
            (
                genom_model::Event::Request,
                format!(
                    "a client requests `{}`; its control codel runs",
                    svc.name.name
                ),
            )
        } else {
            (
                genom_model::Event::Reject,
                format!(
                    "the control codel of `{}` rejects the request",
                    svc.name.name
                ),
            )
        };
        let mut step = TraceStep::new(event, text);
        step.service = Some(svc.name.name.clone());
        step.thread = Some("control".to_owned());
        step.codel = svc.control.map(|k| self.c.codels[k].name.name.clone());
        step.span = Some(
            svc.control
                .map_or(svc.name.span, |k| self.c.codels[k].name.span),
        );
        if !begin {
            step.outcome = svc.reports.first().map(|r| r.name.clone());
        }
        sink.push(step);
    }

    pub(super) fn emit_wake(&self, events: &mut Option<&mut Vec<TraceStep>>, k: usize) {
        let Some(sink) = events.as_deref_mut() else {
            return;
        };
        let t = &self.c.threads[self.threads[k].id];
        let mut step = TraceStep::new(
            genom_model::Event::WakeUp,
            format!("thread `{}` wakes up", t.name.name),
        );
        step.thread = Some(t.name.name.clone());
        step.span = Some(t.name.span);
        sink.push(step);
    }

    /// The enabled actions of a state (their guards may still be empty).
    pub fn enabled(&self, st: &TState, out: &mut Vec<TAction>) {
        if st.violation.is_some() {
            return;
        }
        let mut steps = Vec::new();
        self.sys.actions(&st.cfg, &mut steps);
        for a in steps {
            let i = self.sys.member_index(a.service());
            match a {
                Action::Request(s) => match i.and_then(|i| self.ctl_wcet[i]) {
                    Some(_) => out.push(TAction::RequestBegin(s)),
                    None => out.push(TAction::Step(a)),
                },
                _ => out.push(TAction::Step(a)),
            }
        }
        if let Some(r) = st.ctl {
            let s = self.sys.service(usize::from(r));
            out.extend([TAction::RequestEnd(s, true), TAction::RequestEnd(s, false)]);
        }
        for (k, t) in self.threads.iter().enumerate() {
            let k = u16::try_from(k).unwrap_or(u16::MAX);
            out.push(if t.period.is_some() {
                TAction::WakeUp(k)
            } else {
                TAction::Round(k)
            });
        }
    }
}
