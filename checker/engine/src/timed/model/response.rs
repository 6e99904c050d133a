//! Response clocks: for the services whose worst-case response time is
//! measured, a clock reset when an instance is acknowledged and read while
//! it has not replied (one per instance slot: the main instance, and the
//! pending one of a self-stopping service, exactly as the watchdog clocks
//! follow the instances). And the states from which an instance can stay
//! alive forever.

use genom_model::behaviour::IDLE;

use super::{Change, TState, TimedSystem};
use crate::dialect::system::Config;
use crate::timed::clocks::ClockRole;

/// Why an instance may never reply, from a state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Forever {
    /// Member `.0`'s codels can loop forever (it has no watchdog, or one
    /// that the model times approximately and need never fire), and the
    /// instance is that member's, or is pending behind it.
    Loops(usize),
    /// The instance is pending and nothing will ever happen without a new
    /// request: no instance is active, no control codel runs, no watchdog
    /// is armed; only wake-ups, which find nothing to run.
    Blocked,
}

impl TimedSystem<'_> {
    /// Adds response clocks for the members marked in `tracked`, compared
    /// with constants up to `horizon` (units) from below only: the engine
    /// only asks whether a response clock can exceed a constant.
    pub fn track_responses(&mut self, tracked: &[bool], horizon: i64) {
        for i in 0..self.sys.len() {
            if !tracked.get(i).copied().unwrap_or(false) {
                continue;
            }
            let s = self.sys.service(i);
            let main = self.clocks.add(ClockRole::Response(s), Some(horizon), None);
            let self_stop = self.c.services[s].stops.iter().any(|r| r.id == s);
            let pend = if self_stop {
                self.clocks
                    .add(ClockRole::ResponsePending(s), Some(horizon), None)
            } else {
                main
            };
            self.response[i] = Some((main, pend));
        }
    }

    /// The response clocks of member `i`'s instances that have not replied:
    /// the main clock while the main instance lives (or the pending one
    /// when the main slot is idle), the pending clock while a pending
    /// instance waits for the main one to stop.
    pub fn live_responses(&self, cfg: &Config, i: usize) -> Vec<usize> {
        let Some((main, pend)) = self.response[i] else {
            return Vec::new();
        };
        let mut out = Vec::new();
        if cfg.main[i] != IDLE || cfg.pending[i].is_some() {
            out.push(main);
        }
        if pend != main && cfg.pending[i].is_some() && cfg.main[i] != IDLE {
            out.push(pend);
        }
        out
    }

    /// Response clocks: reset at acknowledgment, carried along when the
    /// pending instance starts, freed when no instance uses them.
    pub(super) fn response_clocks(&self, before: &Config, st: &mut TState, i: usize, ch: Change) {
        let Some((main, pend)) = self.response[i] else {
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
        let live = self.live_responses(&st.cfg, i);
        if !live.contains(&main) {
            st.zone.free(main);
        }
        if pend != main && !live.contains(&pend) {
            st.zone.free(pend);
        }
    }

    /// Whether member `i`'s instance (main or pending) can stay alive
    /// forever from `st`, and why.
    pub fn never_replies(&self, st: &TState, i: usize) -> Option<Forever> {
        let cfg = &st.cfg;
        if st.violation.is_some() {
            return None;
        }
        if self.endless(cfg, i) {
            return Some(Forever::Loops(i));
        }
        // A pending instance with a watchdog timed exactly is ended by it.
        if cfg.pending[i].is_none() || (self.sys.machine_of(i).watchdog && self.watch_exact[i]) {
            return None;
        }
        if let Some((t, _)) = self
            .sys
            .blockers(cfg, i)
            .into_iter()
            .find(|&(t, _)| self.endless(cfg, t))
        {
            return Some(Forever::Loops(t));
        }
        let quiet = st.ctl.is_none()
            && cfg.main.iter().all(|&p| p == IDLE)
            && (0..self.sys.len()).all(|j| self.watch_invariants(cfg, j).is_empty());
        quiet.then_some(Forever::Blocked)
    }

    /// Member `t`'s main instance may stay active forever in the model: it
    /// can loop without watchdog, or it is an active instance of a looping
    /// service whose watchdog the model times approximately (it fires at
    /// any time from its horizon on, so need never fire: the results of
    /// such an exploration are only bounds, see `timed::response`).
    fn endless(&self, cfg: &Config, t: usize) -> bool {
        if self.sys.may_never_end(cfg, t) {
            return true;
        }
        let p = self.sys.position(cfg, t);
        !self.watch_exact[t]
            && self.sys.machine_of(t).active_loop
            && p != genom_model::behaviour::Position::Idle
            && !p.is_interrupted()
    }

    /// Frees the response clock of an instance that may never reply: its
    /// response time is unbounded already, and a clock counting on would
    /// unroll the loop (or the wake-ups of a blocked state) up to the
    /// horizon.
    pub(super) fn free_endless_responses(&self, st: &mut TState) {
        for i in 0..self.sys.len() {
            let Some((main, pend)) = self.response[i] else {
                continue;
            };
            let clock = match self.never_replies(st, i) {
                None => continue,
                Some(Forever::Loops(t)) if t == i => main,
                Some(_) if st.cfg.main[i] == IDLE => main,
                Some(_) => pend,
            };
            st.zone.free(clock);
        }
    }
}
