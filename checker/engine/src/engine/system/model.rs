//! The system as a [`Model`] for the explorer: enabled actions,
//! successors, the bit encoding of configurations and the partial-order
//! reduction hook.

use genom_model::behaviour::{IDLE, PosId};

use super::{Action, BitReader, BitWriter, Config, System, stop_bits};
use crate::engine::explore::Model;

impl Model for System<'_> {
    type State = Config;
    type Zone = ();
    type Action = Action;

    fn width(&self) -> usize {
        self.width
    }

    fn init_states(&self) -> Vec<Config> {
        vec![self.initial(!self.pre_init, &mut None)]
    }

    fn actions(&self, cfg: &Config, out: &mut Vec<Action>) {
        let running = self.running(cfg);
        for (i, m) in self.members.iter().enumerate().filter(|(_, m)| !m.input) {
            let s = m.service;
            if self.request_enabled_among(cfg, i, &running) {
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

    fn next_state(&self, cfg: &Config, action: Action) -> Option<Config> {
        self.apply(cfg, action, &mut None)
    }

    fn encode(&self, cfg: &Config, out: &mut Vec<u64>) {
        let start = out.len();
        let mut w = BitWriter { out, used: 0 };
        w.put(u64::from(cfg.init_done), 1);
        for (i, m) in self.members.iter().enumerate() {
            w.put(u64::from(cfg.main[i]), m.pos_bits);
            if m.can_pend {
                w.put(u64::from(cfg.pending[i].is_some()), 1);
                w.put(cfg.pending[i].unwrap_or(0), stop_bits(m));
            }
            w.put(u64::from(cfg.timed_out[i]), u32::from(m.watchdog));
        }
        out.resize(start + self.width, 0);
    }

    fn zone(&self, _: &Config) {}

    fn decode(&self, words: &[u64], (): &()) -> Config {
        let mut r = BitReader {
            words,
            word: 0,
            used: 0,
            started: false,
        };
        let init_done = r.get(1) == 1;
        let n = self.members.len();
        let mut cfg = Config {
            init_done,
            main: Vec::with_capacity(n),
            pending: Vec::with_capacity(n),
            timed_out: Vec::with_capacity(n),
        };
        for m in &self.members {
            cfg.main
                .push(PosId::try_from(r.get(m.pos_bits)).unwrap_or(IDLE));
            let pending = m.can_pend && r.get(1) == 1;
            let mask = if m.can_pend { r.get(stop_bits(m)) } else { 0 };
            cfg.pending.push(pending.then_some(mask));
            cfg.timed_out.push(m.watchdog && r.get(1) == 1);
        }
        cfg
    }

    fn expand(&self, cfg: &Config) -> bool {
        !(self.pre_init && cfg.init_done)
    }

    fn reduce(&self, cfg: &Config, actions: &mut [Action]) -> usize {
        match &self.reduction {
            Some(r) => r.stubborn(self, cfg, actions),
            None => actions.len(),
        }
    }
}
