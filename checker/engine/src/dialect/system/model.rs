//! The system as a [`Model`] for the explorer: enabled actions,
//! successors, the bit encoding of configurations and the partial-order
//! reduction hook.

use genom_model::component::CodelId;

use super::{Action, Config, System};
use crate::kernel::explore::Model;

impl Model for System<'_> {
    type State = Config;
    type Zone = ();
    type Action = Action;

    fn width(&self) -> usize {
        self.layout.width
    }

    fn init_states(&self) -> Vec<Config> {
        vec![self.initial(!self.pre_init, &mut None)]
    }

    fn actions(&self, cfg: &Config, out: &mut Vec<Action>) {
        self.with_running(cfg, |running| self.actions_among(cfg, running, out));
    }
    fn next_state(&self, cfg: &Config, action: Action) -> Option<Config> {
        self.apply(cfg, action, &mut None)
    }

    fn step_into(&self, cfg: &Config, action: Action, out: &mut Option<Config>) -> bool {
        match out {
            Some(next) => next.clone_from(cfg),
            None => *out = Some(cfg.clone()),
        }
        out.as_mut()
            .is_some_and(|next| self.apply_in_place(next, action, &mut None))
    }

    fn decode_into(&self, words: &[u64], (): &(), out: &mut Option<Config>) {
        match out {
            Some(cfg) => self.layout.decode(words, cfg),
            None => *out = Some(self.decode(words, &())),
        }
    }

    fn encode(&self, cfg: &Config, out: &mut Vec<u64>) {
        self.layout.encode(cfg, out);
    }

    fn zone(&self, _: &Config) {}

    fn decode(&self, words: &[u64], (): &()) -> Config {
        let n = self.members.len();
        let mut cfg = Config {
            init_done: false,
            main: Vec::with_capacity(n),
            pending: Vec::with_capacity(n),
            timed_out: Vec::with_capacity(n),
        };
        self.layout.decode(words, &mut cfg);
        cfg
    }

    fn expand(&self, cfg: &Config) -> bool {
        !(self.pre_init && cfg.init_done)
    }

    fn finished(&self) -> bool {
        self.all_found()
    }

    fn reduce(&self, cfg: &Config, actions: &mut [Action]) -> usize {
        match &self.reduction {
            Some(r) => r.stubborn(self, cfg, actions),
            None => actions.len(),
        }
    }
}

impl System<'_> {
    /// [`Model::actions`] given the running codels.
    fn actions_among(&self, cfg: &Config, running: &[(usize, CodelId)], out: &mut Vec<Action>) {
        for (i, m) in self.members.iter().enumerate().filter(|(_, m)| !m.input) {
            let s = m.service;
            if self.request_enabled_among(cfg, i, running) {
                out.push(Action::Request(s));
            }
            let mach = self.machine(i);
            let p = usize::from(cfg.main[i]);
            if mach.begin[p].is_some() {
                out.push(Action::Begin(s));
            }
            for k in 0..mach.finish[p].len() {
                out.push(Action::Finish(s, u8::try_from(k).unwrap_or(u8::MAX)));
            }
            if mach.watchdog && cfg.pending[i].is_some() {
                out.push(Action::Watchdog(s, true));
            }
            if mach.watchdog && mach.interrupt[p].is_some() {
                out.push(Action::Watchdog(s, false));
            }
        }
    }
}
