//! The component's Petri net: a place/transition net with inhibitor arcs,
//! read (test) arcs and transition priorities whose reachable *stable*
//! markings are exactly the configurations of the untimed explorer
//! (`checker/engine/src/dialect/system/`, LANGUAGE.md section 3). The
//! `genom-translate` crate builds it from the
//! [`Component`](crate::component::Component) and its
//! [`Behaviour`](crate::behaviour::Behaviour) (the per-service local machines),
//! so the codel steps are those of the one table every engine reads.
//!
//! Places, per service `S`:
//! - one place per position of `S`'s machine (`Idle`, `Ready`, `Running`,
//!   `StopReady`, `StopRunning`); exactly one of them holds a token;
//! - `S.pending`: `S` has an acknowledged instance that has not started;
//! - `S.wait.T`, one per `stops` target `T`: the pending instance still
//!   waits for the instance of `T` it interrupted (step 7b);
//! - `S.dropping` (when `S` stops something): a removed pending instance is
//!   discarding its wait tokens;
//! - `S.req.N`: the stages of the control thread handling a request of `S`.
//!
//! and one `init_done`/`init_not_done` pair for the component.
//!
//! Transitions and their priorities (higher fires first: when transitions
//! of several levels are enabled only those of the highest level may fire;
//! a marking where no transition above [`PRIORITY_STEP`] is enabled is
//! *stable*, and stable markings are the explorer's configurations):
//!
//! | level | transitions |
//! |---|---|
//! | [`PRIORITY_DROP`] (4) | discard the wait tokens of a removed pending instance |
//! | [`PRIORITY_REQUEST`] (3) | the micro-steps of a request (steps 5–6) |
//! | [`PRIORITY_CLEAR`] (2) | clear a wait token once its target is idle |
//! | [`PRIORITY_START`] (1) | start a pending instance (step 7, urgent) |
//! | [`PRIORITY_STEP`] (0) | client requests (steps 1–4), codel begin and finish, watchdogs |
//!
//! A request of `S` is one step-level transition whose arcs are the gates of
//! steps 1–4 (read `init_done`; inhibitors on every instance place of the
//! services that forbid `S` and, unless `S` stops itself, of `S`; inhibitors
//! on the running places whose codel conflicts with `S`'s control codel).
//! It marks the first stage of a chain of request-level micro-steps: remove
//! `S`'s own pending instance (self-stop), then for each `stops` target `T`
//! remove `T`'s pending instance and interrupt `T`'s main instance (one
//! micro-step per position of `T`, which also marks `S.wait.T` when `T`
//! does not end at once), then acknowledge (`S.pending`). Clearing a wait
//! token ranks above starting so that an instance that ends and the new
//! instance of the same service are never confused.
//!
//! This module holds the net's types and its queries (what the exports
//! print and a token game reads); `translate/src/petri/` builds it from a
//! component (places, requests, the other transitions).

use crate::behaviour::PosId;
use crate::component::{Idx, ServiceId};
use crate::define_id;
use crate::span::Span;

define_id!(
    /// A place of a [`PetriNet`].
    PlaceId
);
define_id!(
    /// A transition of a [`PetriNet`].
    TransitionId
);

/// Client requests, codel begin and finish, watchdogs: the free choices.
pub const PRIORITY_STEP: u8 = 0;
/// Urgent start of a pending instance (step 7).
pub const PRIORITY_START: u8 = 1;
/// Urgent clearing of a wait token whose target is idle.
pub const PRIORITY_CLEAR: u8 = 2;
/// The atomic chain of a request (steps 5–6).
pub const PRIORITY_REQUEST: u8 = 3;
/// Discarding the wait tokens of a removed pending instance.
pub const PRIORITY_DROP: u8 = 4;

/// GenoM3: the steps of docs/genom3-semantics.md 14.2 (free choices).
pub const G3_PRIORITY_STEP: u8 = 0;
/// GenoM3: the boot order and the shutdown sequence (10.1, 10.2).
pub const G3_PRIORITY_SETTLE: u8 = 1;
/// GenoM3: pending interrupters re-examine after an end (5.3).
pub const G3_PRIORITY_REEXAMINE: u8 = 2;
/// GenoM3: the micro-steps of an atomic sequence.
pub const G3_PRIORITY_MICRO: u8 = 3;

/// An arc: a place and its weight.
pub type Arc = (PlaceId, u32);

/// The net.
#[derive(Debug, Clone)]
pub struct PetriNet {
    /// Places, by [`PlaceId`].
    pub places: Vec<Place>,
    /// Transitions, by [`TransitionId`].
    pub transitions: Vec<Transition>,
    /// The initial marking, one count per place.
    pub initial: Vec<u32>,
    /// The places of each service, by service id.
    pub services: Vec<ServicePlaces>,
    /// Marked once the `init` service has completed successfully (from the
    /// start without an init service).
    pub init_done: PlaceId,
    /// Marked until then.
    pub init_not_done: PlaceId,
}

/// The places that hold one service's state.
#[derive(Debug, Clone)]
pub struct ServicePlaces {
    /// One place per position of the service's machine, by [`PosId`].
    pub positions: Vec<PlaceId>,
    /// The pending instance.
    pub pending: PlaceId,
    /// One wait place per `stops` target, in `stops` order.
    pub waits: Vec<(ServiceId, PlaceId)>,
    /// Where a removed pending instance discards its wait tokens.
    pub dropping: Option<PlaceId>,
}

/// What a place stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlaceKind {
    /// The service's main instance is at this position.
    Position(ServiceId, PosId),
    /// The service has a pending instance.
    Pending(ServiceId),
    /// The pending instance of the first service waits for the second.
    Wait(ServiceId, ServiceId),
    /// A removed pending instance discards its wait tokens.
    Dropping(ServiceId),
    /// The control thread is at this stage of a request of the service.
    Request(ServiceId, u16),
    /// Initialisation has completed.
    InitDone,
    /// Initialisation has not completed yet.
    InitNotDone,
    /// A place of a GenoM3 component's net.
    Genom3(G3Place),
}

/// What a place of a GenoM3 component's net stands for
/// (`translate/src/petri_genom3/`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum G3Place {
    /// A phase of the component's life (boot at one task, run, drain, a
    /// stop path, stopped, failed) or `live` (run, drain or a stop path).
    Phase,
    /// A task's permanent activity: off, or at one of its states.
    Task,
    /// An activity's instance: idle, delayed, ready, or running or
    /// stopping at one of its states.
    Activity,
    /// A service some `after`/`before` reads has (or has not) completed.
    Done,
    /// An instance ended in this step (or not): pending interrupters
    /// re-examine.
    Ended,
    /// A stage of an atomic sequence of micro-steps.
    Stage,
}

/// What a transition of a GenoM3 component's net stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum G3Step {
    /// A permanent codel runs (one of its outcomes).
    Permanent,
    /// A request of an activity is accepted.
    Accept,
    /// A function or attribute succeeds.
    Call,
    /// An accepted instance starts and runs its first codel.
    Start,
    /// An instance's codel runs (one of its outcomes).
    Codel,
    /// A micro-step of an atomic sequence.
    Micro,
    /// What follows every step at once: the boot order, re-examination,
    /// the shutdown sequence.
    Settle,
}

/// A place.
#[derive(Debug, Clone)]
pub struct Place {
    /// A unique identifier (`moveDistance.run.goto`): letters, digits, `_`
    /// and `.`.
    pub name: String,
    /// What it means (`moveDistance running goto`).
    pub label: String,
    /// The service or codel it stands for.
    pub span: Span,
    /// Its role.
    pub kind: PlaceKind,
}

/// What a transition stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TransitionKind {
    /// A client requests the service and the control thread accepts it.
    Request(ServiceId),
    /// A micro-step of the request of the service (interrupting others).
    RequestStep(ServiceId),
    /// The request of the service is acknowledged.
    Acknowledge(ServiceId),
    /// The pending instance starts (or completes at once).
    Start(ServiceId),
    /// The pending instance of the first service stops waiting for the
    /// second.
    ClearWait(ServiceId, ServiceId),
    /// A removed pending instance discards a wait token, or is done.
    Drop(ServiceId),
    /// The service's thread begins the codel of this position.
    Begin(ServiceId, PosId),
    /// The codel of this position finishes, the `k`-th way of its
    /// [`Finish`](crate::behaviour::Finish) list.
    Finish(ServiceId, PosId, usize),
    /// The watchdog interrupts the instance at this position (`None`: the
    /// pending instance).
    Watchdog(ServiceId, Option<PosId>),
    /// A transition of a GenoM3 component's net.
    Genom3(G3Step),
}

/// A transition.
#[derive(Debug, Clone)]
pub struct Transition {
    /// A unique identifier (`moveDistance.finish.run.goto.0`).
    pub name: String,
    /// What it does (`moveDistance::goto ends with stop`).
    pub label: String,
    /// The service, codel or attribute it stands for.
    pub span: Span,
    /// Its priority level (`PRIORITY_*`).
    pub priority: u8,
    /// Its role.
    pub kind: TransitionKind,
    /// Tokens consumed.
    pub pre: Vec<Arc>,
    /// Tokens produced.
    pub post: Vec<Arc>,
    /// Read arcs: the place must hold at least this many tokens.
    pub read: Vec<Arc>,
    /// Inhibitor arcs: the place must hold fewer than this many tokens.
    pub inhibit: Vec<Arc>,
}

impl Transition {
    /// Whether the transition may fire in `marking` (ignoring priorities).
    pub fn enabled(&self, marking: &[u32]) -> bool {
        let count = |p: PlaceId| marking.get(p.index()).copied().unwrap_or(0);
        self.pre.iter().all(|&(p, w)| count(p) >= w)
            && self.read.iter().all(|&(p, w)| count(p) >= w)
            && self.inhibit.iter().all(|&(p, w)| count(p) < w)
    }
}

impl PetriNet {
    /// A net without places or transitions, for a builder to fill.
    pub fn empty() -> PetriNet {
        PetriNet {
            places: Vec::new(),
            transitions: Vec::new(),
            initial: Vec::new(),
            services: Vec::new(),
            init_done: PlaceId(0),
            init_not_done: PlaceId(0),
        }
    }

    /// The place with this id.
    pub fn place(&self, p: PlaceId) -> Option<&Place> {
        self.places.get(p.index())
    }

    /// The transition with this id.
    pub fn transition(&self, t: TransitionId) -> Option<&Transition> {
        self.transitions.get(t.index())
    }

    /// The position of a service's main instance in `marking` (the first
    /// marked position place).
    pub fn position(&self, marking: &[u32], s: ServiceId) -> Option<PosId> {
        let places = &self.services.get(s.index())?.positions;
        let at = places
            .iter()
            .position(|p| marking.get(p.index()).is_some_and(|&n| n > 0))?;
        PosId::try_from(at).ok()
    }

    /// A service's pending instance in `marking`, as the bits (in `stops`
    /// order) of the targets it still waits for.
    pub fn pending(&self, marking: &[u32], s: ServiceId) -> Option<u64> {
        let sp = self.services.get(s.index())?;
        let marked = |p: PlaceId| marking.get(p.index()).is_some_and(|&n| n > 0);
        if !marked(sp.pending) {
            return None;
        }
        let bits = sp
            .waits
            .iter()
            .enumerate()
            .filter(|&(_, &(_, w))| marked(w));
        Some(bits.fold(0u64, |m, (k, _)| {
            m | u32::try_from(k)
                .ok()
                .and_then(|k| 1u64.checked_shl(k))
                .unwrap_or(0)
        }))
    }

    /// Whether initialisation has completed in `marking`.
    pub fn is_init_done(&self, marking: &[u32]) -> bool {
        marking.get(self.init_done.index()).is_some_and(|&n| n > 0)
    }

    /// A plain-text listing of every place and transition with its arcs,
    /// for documentation and debugging.
    pub fn listing(&self) -> String {
        let mut out = String::from("places:\n");
        for (p, place) in self.places.iter().enumerate() {
            let tokens = self.initial.get(p).copied().unwrap_or(0);
            let mark = if tokens > 0 {
                format!(" [{tokens}]")
            } else {
                String::new()
            };
            out.push_str(&format!("  {}{mark}: {}\n", place.name, place.label));
        }
        out.push_str("transitions:\n");
        for t in &self.transitions {
            out.push_str(&format!(
                "  {} (priority {}): {}\n",
                t.name, t.priority, t.label
            ));
            out.push_str(&self.arcs_line(t));
        }
        out
    }

    fn arcs_line(&self, t: &Transition) -> String {
        let names = |arcs: &[Arc]| {
            let v: Vec<&str> = arcs
                .iter()
                .filter_map(|&(p, _)| self.place(p).map(|x| x.name.as_str()))
                .collect();
            v.join(", ")
        };
        let mut parts = vec![format!("pre {{{}}}", names(&t.pre))];
        parts.push(format!("post {{{}}}", names(&t.post)));
        if !t.read.is_empty() {
            parts.push(format!("read {{{}}}", names(&t.read)));
        }
        if !t.inhibit.is_empty() {
            parts.push(format!("inhibit {{{}}}", names(&t.inhibit)));
        }
        format!("      {}\n", parts.join("  "))
    }
}
