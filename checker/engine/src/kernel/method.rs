//! Which method explores an untimed model (`--engine explicit|symbolic|
//! auto`), for any semantics: the explicit explorer ([`super::explore`]),
//! the symbolic sets ([`super::sets`]), or the explicit one with the
//! symbolic sets as the fallback of an exploration that stopped on its
//! state or memory limit (`auto`), and the result of either behind one
//! type ([`Explored`]).

use std::time::{Duration, Instant};

use super::explore::{Exploration, Found, Limits, Model, Stop, explore_until};
use super::sets::{SetExploration, SetLimits, explore_sets_until};
use super::store::{Footprint, StateId};

/// How an untimed model is explored (`--engine`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// The explicit explorer alone.
    Explicit,
    /// The symbolic sets alone.
    Symbolic,
    /// The explicit explorer, then the symbolic sets when it stopped on
    /// its state or memory limit ([`falls_back`]): the default.
    Auto,
}

/// The least time a symbolic exploration after an unfinished explicit one
/// gets when the check has no time limit (`auto`), and the multiple of the
/// explicit exploration's time it gets when that is longer: without a
/// `--timeout`, `auto` must still answer in a time of the order of what the
/// explicit explorer took.
pub const FALLBACK_MIN: Duration = Duration::from_secs(10);
const FALLBACK_FACTOR: u32 = 2;

/// Whether `auto` tries the symbolic method after an explicit exploration
/// that stopped for `stop`: the state or memory limit (the time limit
/// leaves it no time).
pub fn falls_back(stop: Option<Stop>) -> bool {
    matches!(stop, Some(Stop::States | Stop::Memory))
}

/// The deadline of `auto`'s symbolic exploration after an explicit one
/// that took `explicit`: the check's own, or else a bounded time.
pub fn fallback_deadline(limits: &Limits, explicit: Duration) -> Instant {
    limits.deadline.unwrap_or_else(|| {
        Instant::now() + FALLBACK_MIN.max(explicit.saturating_mul(FALLBACK_FACTOR))
    })
}

/// The limits of a symbolic exploration under `limits` (the state limit,
/// a bound on an explicit store, does not apply; the BDD's nodes are
/// bounded instead).
pub fn set_limits(limits: &Limits, deadline: Option<Instant>) -> SetLimits {
    SetLimits {
        deadline,
        max_bytes: limits.max_bytes,
        ..SetLimits::default()
    }
}

/// What explored a model, and what it found.
#[derive(Debug)]
pub enum Explored<A> {
    /// The explicit explorer.
    Explicit(Box<Exploration<A>>),
    /// The symbolic sets.
    Sets(SetExploration),
}

impl<A: Copy> Explored<A> {
    /// Explores `model` explicitly, or (`symbolic`) with the symbolic sets
    /// until `limits`' deadline.
    pub fn run<M: Model<Action = A, Zone = ()>>(
        model: &M,
        symbolic: bool,
        limits: Limits,
        visit: impl FnMut(StateId, &M::State) -> Found,
    ) -> Self {
        if symbolic {
            let sets = set_limits(&limits, limits.deadline);
            Explored::Sets(explore_sets_until(model, sets, visit))
        } else {
            Explored::Explicit(Box::new(explore_until(model, limits, visit)))
        }
    }

    /// The actions from an initial state to `id`.
    pub fn path<M: Model<Action = A, Zone = ()>>(&self, model: &M, id: StateId) -> Vec<A> {
        match self {
            Explored::Explicit(e) => e.path(model, id),
            Explored::Sets(s) => s.path(model, id),
        }
    }

    /// States reached.
    pub fn states(&self) -> u64 {
        match self {
            Explored::Explicit(e) => e.store.len() as u64,
            Explored::Sets(s) => s.states,
        }
    }

    /// Transitions fired.
    pub fn transitions(&self) -> u64 {
        match self {
            Explored::Explicit(e) => e.transitions,
            Explored::Sets(s) => s.transitions,
        }
    }

    /// Why it stopped early, if it did.
    pub fn stopped(&self) -> Option<Stop> {
        match self {
            Explored::Explicit(e) => e.stopped,
            Explored::Sets(s) => s.stopped,
        }
    }

    /// Time spent.
    pub fn elapsed(&self) -> Duration {
        match self {
            Explored::Explicit(e) => e.elapsed,
            Explored::Sets(s) => s.elapsed,
        }
    }

    /// Whether the symbolic sets explored it.
    pub fn is_symbolic(&self) -> bool {
        matches!(self, Explored::Sets(_))
    }

    /// Counts its store's bytes per state (an explicit store only: the
    /// symbolic sets have none).
    pub fn add_footprint(&self, footprint: &mut Footprint) {
        if let Explored::Explicit(e) = self {
            footprint.add(&e.store);
        }
    }
}
