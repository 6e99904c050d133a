//! Probes: short explorations of a system in which clients request only a
//! few services (one member and those that stop it). Every state a probe
//! reaches is reachable in the system (a probe only leaves steps out), so
//! the codels it sees running and the services it sees started are facts
//! of the system; found cheaply before the breadth-first search, they let
//! the search stop as soon as the remaining facts are found (a codel deep
//! in one service's graph is otherwise only seen after every shallower
//! interleaving of every service). Probes only give facts without a trace.

use super::tables::{Set, bit, members};
pub use crate::dialect::system::Probed;
use crate::dialect::system::{Action, Config, System};
use crate::kernel::explore::{Limits, Model, explore};
use crate::kernel::store::StateId;

/// States a probe of one member stores at most.
pub const PROBE_STATES: usize = 20_000;

/// The system with requests only for the members of `allowed`.
struct Restricted<'s, 'a> {
    sys: &'s System<'a>,
    allowed: Set,
}

impl Model for Restricted<'_, '_> {
    type State = Config;
    type Action = Action;
    type Zone = ();

    fn width(&self) -> usize {
        self.sys.width()
    }
    fn init_states(&self) -> Vec<Config> {
        self.sys.init_states()
    }
    fn actions(&self, cfg: &Config, out: &mut Vec<Action>) {
        self.sys.actions(cfg, out);
        out.retain(|a| match a {
            Action::Request(s) => self
                .sys
                .member_index(*s)
                .is_some_and(|i| i < 64 && self.allowed & bit(i) != 0),
            _ => true,
        });
    }
    fn next_state(&self, cfg: &Config, action: Action) -> Option<Config> {
        self.sys.next_state(cfg, action)
    }
    fn step_into(&self, cfg: &Config, action: Action, out: &mut Option<Config>) -> bool {
        self.sys.step_into(cfg, action, out)
    }
    fn encode(&self, cfg: &Config, out: &mut Vec<u64>) {
        self.sys.encode(cfg, out);
    }
    fn decode(&self, words: &[u64], zone: &()) -> Config {
        self.sys.decode(words, zone)
    }
    fn decode_into(&self, words: &[u64], zone: &(), out: &mut Option<Config>) {
        self.sys.decode_into(words, zone, out);
    }
    fn zone(&self, _: &Config) {}
}

/// Probes each member of `wanted` (members of `sys`, at most 64, no
/// inputs): clients request only it and those that stop it (`stoppers`),
/// so that its inter codels run too.
/// `limits` bounds each probe too (its deadline and memory).
pub fn probe(sys: &System<'_>, stoppers: &[Set], wanted: Set, limits: Limits) -> Probed {
    let mut out = Probed::default();
    let limits = Limits {
        max_states: PROBE_STATES.min(limits.max_states),
        ..limits
    };
    let c = sys.component();
    for i in members(wanted) {
        let model = Restricted {
            sys,
            allowed: bit(i) | stoppers[i],
        };
        let e = explore(&model, limits, |_: StateId, cfg: &Config| {
            sys.with_running(cfg, |running| {
                for &(_, k) in running {
                    out.reached.insert(k);
                }
                for j in members(model.allowed) {
                    let s = sys.service(j);
                    if cfg.main[j] != genom_model::behaviour::IDLE {
                        out.started.insert((j, s));
                    }
                    let request = || sys.request_enabled_among(cfg, j, running);
                    let control = c.services[s].control;
                    let no_start = sys.machine_of(j).start.is_none();
                    if (control.is_some_and(|k| !out.reached.contains(&k)) || no_start) && request()
                    {
                        out.reached.extend(control);
                        if no_start {
                            out.started.insert((j, s));
                        }
                    }
                }
            });
        });
        out.states += e.store.len() as u64;
    }
    out
}
