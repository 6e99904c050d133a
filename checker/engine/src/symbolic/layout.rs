//! The BDD variables of a configuration and the static facts of each
//! member that the symbolic steps read.
//!
//! The variables follow the explicit engine's packing (`system::steps`):
//! `init_done`, then per member its main position in binary (least
//! significant bit first), its pending bit and wait mask when it can have
//! a pending instance, and its `timed_out` bit when it has a max-time. A
//! wait mask is all zero whenever its pending bit is, as in the explicit
//! encoding, so a set of valuations counts exactly the configurations the
//! explicit store would hold.

use biodivine_lib_bdd::{Bdd, BddValuation, BddVariable, BddVariableSet};
use genom_model::behaviour::{IDLE, PosId};
use genom_model::component::{CodelId, StructureId, ThreadId};

use crate::dialect::system::{Config, System};

/// The variables of one member.
#[derive(Debug, Clone)]
pub(crate) struct Slot {
    /// Position bits, least significant first.
    pub(crate) pos: Vec<BddVariable>,
    /// The pending bit (members that can never stay pending have none).
    pub(crate) pend: Option<BddVariable>,
    /// Wait-mask bits: bit `k` is the member's `k`-th `stops` target.
    pub(crate) mask: Vec<BddVariable>,
    /// The `timed_out` bit of a member with a max-time.
    pub(crate) tout: Option<BddVariable>,
}

/// Static facts about one member, read off the component as the explicit
/// system reads them.
#[derive(Debug, Clone)]
pub(crate) struct Facts {
    pub(crate) stops: Vec<usize>,
    pub(crate) delayers: Vec<usize>,
    pub(crate) forbidders: Vec<usize>,
    pub(crate) self_stop: bool,
    pub(crate) control: Vec<(StructureId, bool)>,
    pub(crate) thread: Option<ThreadId>,
    /// The running positions and their codels.
    pub(crate) running: Vec<(PosId, CodelId)>,
}

/// The variables and facts of a system.
#[derive(Debug)]
pub(crate) struct Layout {
    pub(crate) vars: BddVariableSet,
    pub(crate) init_done: BddVariable,
    pub(crate) slots: Vec<Slot>,
    pub(crate) facts: Vec<Facts>,
}

/// Why a system cannot be explored symbolically.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Refusal {
    /// The system has input members (a composed part): only whole clusters
    /// are supported.
    Inputs,
    /// More BDD variables than the library allows.
    TooManyVariables,
    /// A member stops more than 64 services.
    TooManyStops,
    /// The initial configuration has not completed initialisation (the
    /// pre-init phase is left to the explicit engine).
    PreInit,
    /// The time limit passed while the steps were being built (a cluster of
    /// thousands of codels has millions of lock conflicts to encode).
    OutOfTime,
}

impl Layout {
    /// The layout of `sys`.
    pub(crate) fn new(sys: &System<'_>) -> Result<Layout, Refusal> {
        if (0..sys.len()).any(|i| sys.is_input(i)) {
            return Err(Refusal::Inputs);
        }
        if sys.too_many_stops() {
            return Err(Refusal::TooManyStops);
        }
        let facts: Vec<Facts> = (0..sys.len()).map(|i| facts(sys, i)).collect();
        let mut next = 1usize;
        let mut take = |n: usize| {
            let v: Vec<BddVariable> = (next..next + n).map(BddVariable::from_index).collect();
            next += n;
            v
        };
        let mut slots = Vec::with_capacity(sys.len());
        for (i, f) in facts.iter().enumerate() {
            let m = sys.machine_of(i);
            let positions = m.positions.len();
            let bits = (usize::BITS - positions.saturating_sub(1).leading_zeros()) as usize;
            let pos = take(bits);
            let can_pend = !f.delayers.is_empty() || !f.stops.is_empty();
            let (pend, mask) = if can_pend {
                let p = take(1);
                (p.first().copied(), take(f.stops.len()))
            } else {
                (None, Vec::new())
            };
            let watchdog = sys.component().services[sys.service(i)].max_time.is_some();
            let tout = if watchdog {
                take(1).first().copied()
            } else {
                None
            };
            slots.push(Slot {
                pos,
                pend,
                mask,
                tout,
            });
        }
        let n = u16::try_from(next).map_err(|_| Refusal::TooManyVariables)?;
        Ok(Layout {
            vars: BddVariableSet::new_anonymous(n),
            init_done: BddVariable::from_index(0),
            slots,
            facts,
        })
    }

    /// Number of BDD variables.
    pub(crate) fn num_vars(&self) -> usize {
        usize::from(self.vars.num_vars())
    }

    /// Member `i` is at position `p`.
    pub(crate) fn pos_eq(&self, i: usize, p: PosId) -> Bdd {
        let mut out = self.vars.mk_true();
        for (k, &v) in self.slots[i].pos.iter().enumerate() {
            out = out.and(&self.vars.mk_literal(v, (p >> k) & 1 == 1));
        }
        out
    }

    /// Member `i` has a pending instance.
    pub(crate) fn pend(&self, i: usize) -> Bdd {
        self.slots[i]
            .pend
            .map_or_else(|| self.vars.mk_false(), |v| self.vars.mk_var(v))
    }

    /// Member `i` has an instance (main or pending).
    pub(crate) fn has_instance(&self, i: usize) -> Bdd {
        self.pos_eq(i, IDLE).not().or(&self.pend(i))
    }

    /// The configuration `cfg` as a single-valuation BDD.
    pub(crate) fn encode(&self, cfg: &Config) -> Bdd {
        self.valuation(cfg).mk_bdd()
    }

    fn valuation(&self, cfg: &Config) -> BddValuation {
        let mut val = BddValuation::all_false(self.vars.num_vars());
        val.set_value(self.init_done, cfg.init_done);
        for (i, s) in self.slots.iter().enumerate() {
            for (k, &v) in s.pos.iter().enumerate() {
                val.set_value(v, (cfg.main[i] >> k) & 1 == 1);
            }
            if let Some(v) = s.pend {
                val.set_value(v, cfg.pending[i].is_some());
            }
            let mask = cfg.pending[i].unwrap_or(0);
            for (k, &v) in s.mask.iter().enumerate() {
                val.set_value(v, (mask >> k) & 1 == 1);
            }
            if let Some(v) = s.tout {
                val.set_value(v, cfg.timed_out[i]);
            }
        }
        val
    }

    /// The configuration of a valuation.
    pub(crate) fn decode(&self, val: &BddValuation) -> Config {
        let n = self.slots.len();
        let mut cfg = Config {
            init_done: val.value(self.init_done),
            main: Vec::with_capacity(n),
            pending: Vec::with_capacity(n),
            timed_out: Vec::with_capacity(n),
        };
        for s in &self.slots {
            let pos = u16::try_from(bits(&s.pos, val)).unwrap_or(u16::MAX);
            cfg.main.push(pos);
            let mask = bits(&s.mask, val);
            let pending = s.pend.is_some_and(|v| val.value(v));
            cfg.pending.push(pending.then_some(mask));
            cfg.timed_out.push(s.tout.is_some_and(|v| val.value(v)));
        }
        cfg
    }

    /// Some configuration of a non-empty set, decoded.
    pub(crate) fn pick(&self, set: &Bdd) -> Option<Config> {
        set.sat_witness().map(|v| self.decode(&v))
    }
}

/// The facts of member `i`: `delays` and `forbids` reversed over the
/// members, as `System` does.
fn facts(sys: &System<'_>, i: usize) -> Facts {
    let c = sys.component();
    let s = sys.service(i);
    let names = |t: usize, delays: bool| {
        let svc = &c.services[sys.service(t)];
        let rule = if delays { &svc.delays } else { &svc.forbids };
        t != i && rule.iter().any(|r| r.id == s)
    };
    let delayers = (0..sys.len()).filter(|&t| names(t, true)).collect();
    let forbidders = (0..sys.len()).filter(|&t| names(t, false)).collect();
    let m = sys.machine_of(i);
    let running = m
        .positions
        .iter()
        .enumerate()
        .filter(|(_, p)| p.is_running())
        .filter_map(|(q, p)| Some((PosId::try_from(q).ok()?, p.codel()?)))
        .collect();
    Facts {
        stops: sys.stops_of(i).to_vec(),
        delayers,
        forbidders,
        self_stop: c.services[s].stops.iter().any(|r| r.id == s),
        control: sys.control_uses(i).to_vec(),
        thread: m.thread,
        running,
    }
}

/// The number whose bit `k` is the value of `vars[k]` in `val`.
fn bits(vars: &[BddVariable], val: &BddValuation) -> u64 {
    vars.iter()
        .enumerate()
        .filter(|&(_, &v)| val.value(v))
        .fold(0, |acc, (k, _)| acc | (1 << k))
}
