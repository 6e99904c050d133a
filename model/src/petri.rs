//! The component's Petri net: a place/transition net with inhibitor arcs,
//! read (test) arcs and transition priorities whose reachable *stable*
//! markings are exactly the configurations of the untimed explorer
//! (`checker/src/engine/system.rs`, LANGUAGE.md section 3). It is built from
//! the [`Component`] and its [`Behaviour`] (the per-service local machines),
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

use crate::behaviour::{Behaviour, Effect, Ending, IDLE, PosId, Position, ServiceMachine};
use crate::component::{CodelId, Component, Idx, Outcome, Ref, Service, ServiceId, ThreadId};
use crate::define_id;
use crate::kinds::ServiceKind;
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
    fn new(name: String, label: String, span: Span, priority: u8, kind: TransitionKind) -> Self {
        Transition {
            name,
            label,
            span,
            priority,
            kind,
            pre: Vec::new(),
            post: Vec::new(),
            read: Vec::new(),
            inhibit: Vec::new(),
        }
    }

    fn pre(mut self, p: PlaceId) -> Self {
        self.pre.push((p, 1));
        self
    }

    fn post(mut self, p: PlaceId) -> Self {
        self.post.push((p, 1));
        self
    }

    fn read(mut self, p: PlaceId) -> Self {
        self.read.push((p, 1));
        self
    }

    fn inhibit(mut self, places: impl IntoIterator<Item = PlaceId>) -> Self {
        for p in places {
            if !self.inhibit.iter().any(|&(q, _)| q == p) {
                self.inhibit.push((p, 1));
            }
        }
        self
    }

    /// Whether the transition may fire in `marking` (ignoring priorities).
    pub fn enabled(&self, marking: &[u32]) -> bool {
        let count = |p: PlaceId| marking.get(p.index()).copied().unwrap_or(0);
        self.pre.iter().all(|&(p, w)| count(p) >= w)
            && self.read.iter().all(|&(p, w)| count(p) >= w)
            && self.inhibit.iter().all(|&(p, w)| count(p) < w)
    }
}

impl PetriNet {
    /// Builds the net of a component from its local machines.
    pub fn build(c: &Component, b: &Behaviour) -> PetriNet {
        let net = PetriNet {
            places: Vec::new(),
            transitions: Vec::new(),
            initial: Vec::new(),
            services: Vec::new(),
            init_done: PlaceId(0),
            init_not_done: PlaceId(0),
        };
        let mut builder = Builder { c, b, net };
        builder.places();
        for s in c.services.ids() {
            builder.service_transitions(s);
        }
        builder.net
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

/// Builds a net.
struct Builder<'a> {
    c: &'a Component,
    b: &'a Behaviour,
    net: PetriNet,
}

/// The identifier of a position, unique within its service.
fn position_name(c: &Component, p: Position) -> String {
    let name = |k: CodelId| c.codels[k].name.name.clone();
    match p {
        Position::Idle => "idle".to_owned(),
        Position::Ready {
            codel,
            on_inter: None,
        } => format!("ready.{}", name(codel)),
        Position::Ready {
            codel,
            on_inter: Some(i),
        } => {
            format!("ready.{}.{}", name(codel), name(i))
        }
        Position::Running {
            codel,
            interrupted: false,
        } => format!("run.{}", name(codel)),
        Position::Running {
            codel,
            interrupted: true,
        } => format!("runint.{}", name(codel)),
        Position::StopReady { codel } => format!("stopready.{}", name(codel)),
        Position::StopRunning { codel } => format!("stoprun.{}", name(codel)),
    }
}

/// Where a service is, in words (`running goto`).
fn position_text(c: &Component, p: Position) -> String {
    let name = |k: CodelId| c.codels[k].name.name.as_str();
    match p {
        Position::Idle => "idle".to_owned(),
        Position::Ready {
            codel,
            on_inter: None,
        } => format!("at {} (ready)", name(codel)),
        Position::Ready {
            codel,
            on_inter: Some(i),
        } => {
            format!("at {} (ready, on-inter: {})", name(codel), name(i))
        }
        Position::Running {
            codel,
            interrupted: false,
        } => format!("running {}", name(codel)),
        Position::Running {
            codel,
            interrupted: true,
        } => {
            format!("running {} (interrupted)", name(codel))
        }
        Position::StopReady { codel } => format!("stopping at {} (ready)", name(codel)),
        Position::StopRunning { codel } => format!("stopping, running {}", name(codel)),
    }
}

impl<'a> Builder<'a> {
    fn name(&self, s: ServiceId) -> &'a str {
        &self.c.services[s].name.name
    }

    fn span(&self, s: ServiceId) -> Span {
        self.c.services[s].name.span
    }

    fn machine(&self, s: ServiceId) -> &'a ServiceMachine {
        self.b.machine(s)
    }

    fn sp(&self, s: ServiceId) -> &ServicePlaces {
        &self.net.services[s.index()]
    }

    fn pos(&self, s: ServiceId, p: PosId) -> PlaceId {
        self.sp(s).positions[usize::from(p)]
    }

    fn idle(&self, s: ServiceId) -> PlaceId {
        self.pos(s, IDLE)
    }

    fn add_place(&mut self, name: String, label: String, span: Span, kind: PlaceKind) -> PlaceId {
        let id = PlaceId::new(self.net.places.len());
        self.net.places.push(Place {
            name,
            label,
            span,
            kind,
        });
        self.net.initial.push(0);
        id
    }

    fn add(&mut self, t: Transition) {
        self.net.transitions.push(t);
    }

    fn mark(&mut self, p: PlaceId) {
        if let Some(n) = self.net.initial.get_mut(p.index()) {
            *n += 1;
        }
    }

    // ----- places -----

    fn places(&mut self) {
        for s in self.c.services.ids() {
            let sp = self.service_places(s);
            self.net.services.push(sp);
        }
        let (init, span) = match self.c.init_service() {
            Some(i) => (Some(i), self.span(i)),
            None => (None, self.c.name.span),
        };
        let done = "initialisation has completed".to_owned();
        self.net.init_done = self.add_place("init_done".into(), done, span, PlaceKind::InitDone);
        let not_done = "initialisation has not completed".to_owned();
        self.net.init_not_done = self.add_place(
            "init_not_done".into(),
            not_done,
            span,
            PlaceKind::InitNotDone,
        );
        self.initial_marking(init.is_some());
    }

    fn service_places(&mut self, s: ServiceId) -> ServicePlaces {
        let (name, span) = (self.name(s), self.span(s));
        let mut positions = Vec::new();
        for (k, &p) in self.machine(s).positions.iter().enumerate() {
            let pspan = p.codel().map_or(span, |k| self.c.codels[k].name.span);
            let label = format!("{name} {}", position_text(self.c, p));
            let kind = PlaceKind::Position(s, PosId::try_from(k).unwrap_or(PosId::MAX));
            positions.push(self.add_place(
                format!("{name}.{}", position_name(self.c, p)),
                label,
                pspan,
                kind,
            ));
        }
        let label = format!("{name} pending (acknowledged, not started)");
        let pending = self.add_place(
            format!("{name}.pending"),
            label,
            span,
            PlaceKind::Pending(s),
        );
        let mut waits = Vec::new();
        for t in stop_targets(self.c, s) {
            let (tn, tspan) = (self.name(t.0), t.1);
            let label = format!("pending {name} waits for the interrupted {tn} to end");
            let w = self.add_place(
                format!("{name}.wait.{tn}"),
                label,
                tspan,
                PlaceKind::Wait(s, t.0),
            );
            waits.push((t.0, w));
        }
        let dropping = (!waits.is_empty()).then(|| {
            let label = format!("the removed pending {name} discards its wait tokens");
            self.add_place(
                format!("{name}.dropping"),
                label,
                span,
                PlaceKind::Dropping(s),
            )
        });
        ServicePlaces {
            positions,
            pending,
            waits,
            dropping,
        }
    }

    /// Every service idle; without an init service, initialisation is done
    /// and the autos are active at their start codel (autos are never
    /// pending; one without start codel has completed at once).
    fn initial_marking(&mut self, has_init: bool) {
        let started: Vec<(ServiceId, Option<PosId>)> = if has_init {
            Vec::new()
        } else {
            self.autos()
                .into_iter()
                .map(|a| (a, self.machine(a).start))
                .collect()
        };
        for s in self.c.services.ids() {
            let place = match started.iter().find(|(a, _)| *a == s) {
                Some(&(a, Some(p))) => self.pos(a, p),
                _ => self.idle(s),
            };
            self.mark(place);
        }
        let p = if has_init {
            self.net.init_not_done
        } else {
            self.net.init_done
        };
        self.mark(p);
    }

    fn autos(&self) -> Vec<ServiceId> {
        self.c
            .services
            .iter()
            .filter(|(_, s)| s.kind == ServiceKind::Auto)
            .map(|(id, _)| id)
            .collect()
    }

    /// Every place that holds an instance of `t`: non-idle positions and
    /// the pending place.
    fn instance_places(&self, t: ServiceId) -> Vec<PlaceId> {
        let sp = self.sp(t);
        sp.positions
            .iter()
            .skip(1)
            .copied()
            .chain([sp.pending])
            .collect()
    }

    /// Running places of `t` with their codel.
    fn running_places(&self, t: ServiceId) -> Vec<(PlaceId, CodelId)> {
        let m = self.machine(t);
        let running = m
            .positions
            .iter()
            .enumerate()
            .filter(|(_, p)| p.is_running());
        running
            .filter_map(|(k, p)| Some((self.sp(t).positions[k], p.codel()?)))
            .collect()
    }

    // ----- transitions -----

    fn service_transitions(&mut self, s: ServiceId) {
        self.request(s);
        self.start(s);
        self.clears(s);
        self.drops(s);
        self.codel_steps(s);
        self.watchdogs(s);
    }

    /// Steps 1–4 as the arcs of one transition, then the chain.
    fn request(&mut self, s: ServiceId) {
        let name = self.name(s);
        let svc = &self.c.services[s];
        let span = svc
            .control
            .map_or(self.span(s), |k| self.c.codels[k].name.span);
        let label = format!("request {name} (accepted)");
        let mut t = Transition::new(
            format!("{name}.request"),
            label,
            span,
            PRIORITY_STEP,
            TransitionKind::Request(s),
        );
        if self.c.init_service().is_some_and(|i| i != s) {
            t = t.read(self.net.init_done);
        }
        for f in others(self.c, s, |x| &x.forbids) {
            t = t.inhibit(self.instance_places(f));
        }
        if !svc.stops.iter().any(|r| r.id == s) {
            t = t.inhibit(self.instance_places(s));
        }
        if let Some(control) = svc.control {
            t = t.inhibit(self.locked_by(control, None));
        }
        self.request_chain(s, t);
    }

    /// Running places whose codel conflicts with `codel`, or that belong to
    /// another service of `thread` (given as the service `codel` belongs to
    /// and its thread; that service's own places are left out).
    fn locked_by(&self, codel: CodelId, thread: Option<(ServiceId, ThreadId)>) -> Vec<PlaceId> {
        let mut out = Vec::new();
        for j in self.c.services.ids() {
            let same = match thread {
                Some((me, _)) if me == j => continue,
                Some((_, th)) => self.machine(j).thread == Some(th),
                None => false,
            };
            for (p, d) in self.running_places(j) {
                if same || self.c.conflicts(codel, d) {
                    out.push(p);
                }
            }
        }
        out
    }

    fn stage(&mut self, s: ServiceId, what: &str) -> PlaceId {
        let n = self
            .net
            .places
            .iter()
            .filter(|p| matches!(p.kind, PlaceKind::Request(x, _) if x == s))
            .count();
        let n = u16::try_from(n).unwrap_or(u16::MAX);
        let name = self.name(s);
        let label = format!("request {name} accepted, next: {what}");
        self.add_place(
            format!("{name}.req.{n}"),
            label,
            self.span(s),
            PlaceKind::Request(s, n),
        )
    }

    /// The micro-steps of a request after its gate `gate`: own pending
    /// instance (self-stop), then each target, then the acknowledgment.
    fn request_chain(&mut self, s: ServiceId, gate: Transition) {
        let targets = stop_targets(self.c, s);
        if targets.is_empty() {
            let p = self.sp(s).pending;
            self.add(gate.post(p));
            return;
        }
        let self_stop = targets.iter().find(|t| t.0 == s).copied();
        let first = match self_stop {
            Some(_) => format!("interrupt the pending {}", self.name(s)),
            None => self.step_text(s, &targets, 0),
        };
        let mut stage = self.stage(s, &first);
        self.add(gate.post(stage));
        if let Some(me) = self_stop {
            let what = self.step_text(s, &targets, 0);
            stage = self.remove_pending(s, me, stage, &what);
        }
        for (k, &target) in targets.iter().enumerate() {
            if target.0 != s {
                let what = format!("interrupt {}", self.name(target.0));
                stage = self.remove_pending(s, target, stage, &what);
            }
            let what = self.step_text(s, &targets, k + 1);
            stage = self.interrupt_main(s, k, target, stage, &what);
        }
        self.acknowledge(s, stage);
    }

    /// What the chain of `s` does at target `k` (or acknowledges).
    fn step_text(&self, s: ServiceId, targets: &[(ServiceId, Span)], k: usize) -> String {
        match targets.get(k) {
            Some(&(u, _)) if u != s => format!("interrupt the pending {}", self.name(u)),
            Some(&(u, _)) => format!("interrupt {}", self.name(u)),
            None => "acknowledge".to_owned(),
        }
    }

    fn acknowledge(&mut self, s: ServiceId, stage: PlaceId) {
        let name = self.name(s);
        let label = format!("request {name}: acknowledge (pending)");
        let kind = TransitionKind::Acknowledge(s);
        let t = Transition::new(
            format!("{name}.ack"),
            label,
            self.span(s),
            PRIORITY_REQUEST,
            kind,
        );
        let p = self.sp(s).pending;
        self.add(t.pre(stage).post(p));
    }

    /// Removes the pending instance of `t` if any; returns the next stage,
    /// labelled `what`.
    fn remove_pending(
        &mut self,
        s: ServiceId,
        target: (ServiceId, Span),
        stage: PlaceId,
        what: &str,
    ) -> PlaceId {
        let (t, span) = target;
        let (name, tn) = (self.name(s), self.name(t));
        let next = self.stage(s, what);
        let n = self.stage_number(stage);
        let kind = TransitionKind::RequestStep(s);
        let label = format!("request {name}: interrupt the pending {tn}");
        let id = format!("{name}.req.{n}.pending.{tn}");
        let yes = Transition::new(id, label, span, PRIORITY_REQUEST, kind);
        let pending = self.sp(t).pending;
        let mut yes = yes.pre(stage).pre(pending).post(next);
        if let Some(d) = self.sp(t).dropping {
            yes = yes.post(d);
        }
        self.add(yes);
        let label = format!("request {name}: {tn} has no pending instance");
        let id = format!("{name}.req.{n}.nopending.{tn}");
        let no = Transition::new(id, label, span, PRIORITY_REQUEST, kind);
        self.add(no.pre(stage).inhibit([pending]).post(next));
        next
    }

    fn stage_number(&self, stage: PlaceId) -> u16 {
        match self.net.places.get(stage.index()).map(|p| p.kind) {
            Some(PlaceKind::Request(_, n)) => n,
            _ => 0,
        }
    }

    /// Step 5 on the main instance of the `k`-th target: one micro-step per
    /// position of the target; marks the wait place unless the target is
    /// (then) idle. Returns the next stage, labelled `what`.
    fn interrupt_main(
        &mut self,
        s: ServiceId,
        k: usize,
        target: (ServiceId, Span),
        stage: PlaceId,
        what: &str,
    ) -> PlaceId {
        let (t, span) = target;
        let next = self.stage(s, what);
        let n = self.stage_number(stage);
        let wait = self.sp(s).waits[k].1;
        let m = self.machine(t);
        for (pi, &p) in m.positions.iter().enumerate() {
            let place = self.sp(t).positions[pi];
            let tr = self.interrupt_step(s, t, p, n, span).pre(stage).post(next);
            let tr = match m.interrupt[pi] {
                Some(Effect::Goto(q)) => tr.pre(place).post(self.pos(t, q)).post(wait),
                Some(Effect::End(_)) => tr.pre(place).post(self.idle(t)),
                None if pi == usize::from(IDLE) => tr.read(place),
                None => tr.read(place).post(wait),
            };
            self.add(tr);
        }
        next
    }

    fn interrupt_step(
        &self,
        s: ServiceId,
        t: ServiceId,
        p: Position,
        n: u16,
        span: Span,
    ) -> Transition {
        let (name, tn) = (self.name(s), self.name(t));
        let at = position_text(self.c, p);
        let m = self.machine(t);
        let effect = m.find(p).and_then(|k| m.interrupt[usize::from(k)]);
        let label = match (effect, p) {
            (Some(Effect::End(_)), _) => {
                format!("request {name}: interrupt {tn} {at}: it ends (INTERRUPTED)")
            }
            (Some(_), _) => format!("request {name}: interrupt {tn} {at}"),
            (None, Position::Idle) => format!("request {name}: {tn} is idle"),
            (None, _) => format!("request {name}: {tn} {at} is already interrupted; wait for it"),
        };
        let id = format!("{name}.req.{n}.{tn}.{}", position_name(self.c, p));
        Transition::new(
            id,
            label,
            span,
            PRIORITY_REQUEST,
            TransitionKind::RequestStep(s),
        )
    }

    /// Step 7: the urgent start of a pending instance.
    fn start(&mut self, s: ServiceId) {
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
    fn success(&mut self, s: ServiceId, t: Transition) {
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
    fn clears(&mut self, s: ServiceId) {
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
    fn drops(&mut self, s: ServiceId) {
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
    fn codel_steps(&mut self, s: ServiceId) {
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

    fn begin(&mut self, s: ServiceId, p: PosId, q: PosId) {
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

    fn finish(&mut self, s: ServiceId, pid: PosId, p: Position, k: usize) {
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

    fn finish_label(
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

    fn report(&self, s: ServiceId, r: usize) -> &'a str {
        self.c.services[s]
            .reports
            .get(r)
            .map_or("?", |n| n.name.as_str())
    }

    fn outcome(&self, s: ServiceId, o: Outcome) -> String {
        match o {
            Outcome::Codel(k) => self.c.codels[k].name.name.clone(),
            Outcome::End => "end".to_owned(),
            Outcome::Report(r) => self.report(s, r).to_owned(),
        }
    }

    /// The max-time watchdog: on the pending instance, and at every
    /// interruptible position.
    fn watchdogs(&mut self, s: ServiceId) {
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

/// The distinct `stops` targets of `s`, in order, with the span of each.
fn stop_targets(c: &Component, s: ServiceId) -> Vec<(ServiceId, Span)> {
    let mut out: Vec<(ServiceId, Span)> = Vec::new();
    for r in &c.services[s].stops {
        if !out.iter().any(|&(t, _)| t == r.id) {
            out.push((r.id, r.span));
        }
    }
    out
}

/// The services `T != s` that list `s` in `rule(T)`.
fn others(
    c: &Component,
    s: ServiceId,
    rule: fn(&Service) -> &Vec<Ref<ServiceId>>,
) -> Vec<ServiceId> {
    c.services
        .iter()
        .filter(|&(t, ts)| t != s && rule(ts).iter().any(|r| r.id == s))
        .map(|(t, _)| t)
        .collect()
}
