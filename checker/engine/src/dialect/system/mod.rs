//! The untimed execution semantics of LANGUAGE.md section 3 over a set of
//! *member* services (the whole component, or one independent cluster of
//! it), as a [`Model`](crate::kernel::explore::Model) for the explorer.
//!
//! A configuration holds, per member, the position of its main instance
//! (see [`genom_model::behaviour`]) and its pending instance, if any, with
//! the set of `stops` targets whose interrupted instance it still waits for
//! (step 7b). Requests are handled atomically (steps 1–7); pending
//! instances start as soon as they can (urgent), in service order; codels
//! run in two steps (begin, finish) so that an interrupt can arrive while a
//! codel runs. One function, [`System::apply`], defines every transition;
//! with an event sink it also writes the trace.

mod layout;
mod locks;
mod model;
mod steps;
#[cfg(test)]
mod tests;

use std::collections::BTreeSet;

use genom_model::behaviour::{Behaviour, IDLE, PosId, Position, ServiceMachine};
use genom_model::component::{CodelId, Component, ServiceId, StructureId, ThreadId};
use genom_model::trace::TraceStep;
use locks::Who;

/// A configuration of the member services.
#[derive(Debug, PartialEq, Eq, Hash)]
pub struct Config {
    /// Whether the `init` service has completed successfully (always true
    /// without an init service).
    pub init_done: bool,
    /// Position of each member's main instance.
    pub main: Vec<PosId>,
    /// Each member's pending instance: the bits of the `stops` targets it
    /// still waits for.
    pub pending: Vec<Option<u64>>,
    /// Whether each member's main instance was interrupted by its max-time
    /// watchdog (it then replies `TIMEOUT` rather than `INTERRUPTED`).
    pub timed_out: Vec<bool>,
}

impl Clone for Config {
    fn clone(&self) -> Self {
        Config {
            init_done: self.init_done,
            main: self.main.clone(),
            pending: self.pending.clone(),
            timed_out: self.timed_out.clone(),
        }
    }

    /// Field by field, so that the explorer's successor buffer keeps its
    /// vectors (the derived `clone_from` would allocate new ones).
    fn clone_from(&mut self, source: &Self) {
        self.init_done = source.init_done;
        self.main.clone_from(&source.main);
        self.pending.clone_from(&source.pending);
        self.timed_out.clone_from(&source.timed_out);
    }
}

/// A transition.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Action {
    /// A client requests a service and the request is accepted.
    Request(ServiceId),
    /// The service's thread starts its next codel.
    Begin(ServiceId),
    /// The running codel finishes, the `k`-th way.
    Finish(ServiceId, u8),
    /// The max-time watchdog fires on the pending (`true`) or main
    /// instance.
    Watchdog(ServiceId, bool),
}

impl Action {
    /// The service the action is about.
    pub fn service(self) -> ServiceId {
        match self {
            Action::Request(s)
            | Action::Begin(s)
            | Action::Finish(s, _)
            | Action::Watchdog(s, _) => s,
        }
    }
}

/// Static facts about one member.
#[derive(Debug, Clone)]
struct Member {
    service: ServiceId,
    /// Member indices of its `stops` targets (bit `k` of a wait mask is
    /// `stops[k]`).
    stops: Vec<usize>,
    /// Members `T != S` whose instances delay it.
    delayers: Vec<usize>,
    /// Members `T != S` whose instances make its requests rejected.
    forbidders: Vec<usize>,
    /// It lists itself in `stops`.
    self_stop: bool,
    /// Structures of its control codel, with write access.
    control: Vec<(StructureId, bool)>,
    /// Bits for its position, and whether it has a pending slot.
    pos_bits: u32,
    can_pend: bool,
    /// Has a max-time watchdog (one bit of `timed_out` is stored).
    watchdog: bool,
    /// An *input*: a service of another part of the component whose
    /// instance only matters here through `delays`/`forbids`; it takes no
    /// step of its own. Its pending slot holds what the environment says:
    /// `Some(0)` has an instance, `Some(1)` has one that may never end.
    input: bool,
}

/// The member services and their rules.
#[derive(Debug)]
pub struct System<'a> {
    c: &'a Component,
    b: &'a Behaviour,
    members: Vec<Member>,
    /// Member index of each service of the component.
    index: Vec<Option<usize>>,
    /// The component's init service.
    init: Option<ServiceId>,
    /// Stop expanding once init has completed (the pre-init phase).
    pre_init: bool,
    /// Structures used by each codel of a member, with write access (empty
    /// for the codels of other services).
    codel_structures: Vec<Vec<(StructureId, bool)>>,
    /// Where each field of an encoded configuration lies.
    layout: layout::Layout,
    /// Per member, per position: the codel running there, if any (read on
    /// every transition, so kept apart from the machines).
    running_codel: Vec<Box<[Option<CodelId>]>>,
    /// Per member: its thread (`None` for the control thread).
    threads: Vec<Option<ThreadId>>,
    /// Which codels exclude each other (`None`: too many codels, ask
    /// [`conflict`]).
    locks: Option<locks::Locks>,
    /// A reused buffer for the running codels of a configuration.
    scratch: std::cell::RefCell<Vec<(usize, CodelId)>>,
    /// The partial-order reduction, when reduction is on.
    reduction: Option<Box<dyn Reduce>>,
    /// With at most 64 members: per member, the bits of its `delayers`
    /// (empty with more members).
    delayer_bits: Vec<u64>,
    /// With at most 64 members: the bits of the members that may be on a
    /// deadlock cycle (neither input nor with a watchdog).
    cycle_members: u64,
}

/// What the probes of a system found, and the states they stored.
#[derive(Debug, Default)]
pub struct Probed {
    /// Codels seen running, or (control codels) whose request was enabled.
    pub reached: BTreeSet<CodelId>,
    /// Members seen started, with their service.
    pub started: BTreeSet<(usize, ServiceId)>,
    /// States stored over all probes.
    pub states: u64,
}

/// A partial-order reduction of a system's steps (the one of
/// `super::reduction` attaches itself with `System::with_reduction`).
pub trait Reduce: std::fmt::Debug {
    /// Moves a stubborn subset of `actions` (the actions enabled in `cfg`)
    /// to the front and returns its length; `actions.len()` when there is
    /// none smaller.
    fn stubborn(&self, sys: &System<'_>, cfg: &Config, actions: &mut [Action]) -> usize;
    /// Whether every fact the analysis reads has been found in the states
    /// given to [`Self::stubborn`] so far (exploring further changes
    /// nothing; default: never).
    fn finished(&self) -> bool {
        false
    }
    /// Notes the facts of an expanded state, where [`Self::stubborn`] is
    /// not called (default: nothing).
    fn note(&self, _sys: &System<'_>, _cfg: &Config) {}
    /// Runs the reduction's probes (default: none), which find facts
    /// without a trace before the search.
    fn probe(&self, _sys: &System<'_>, _limits: crate::kernel::explore::Limits) -> Option<Probed> {
        None
    }
}

impl<'a> System<'a> {
    /// The system of `members` (sorted service ids). With `pre_init`,
    /// states where init has completed are not expanded.
    pub fn new(c: &'a Component, b: &'a Behaviour, members: &[ServiceId], pre_init: bool) -> Self {
        Self::with_inputs(c, b, members, &[], pre_init)
    }

    /// The system of `members` and of the `inputs` (sorted service ids,
    /// disjoint): inputs take no steps; their instances are set by
    /// [`Self::set_input`] (see [`super::compose`]).
    pub fn with_inputs(
        c: &'a Component,
        b: &'a Behaviour,
        members: &[ServiceId],
        inputs: &[ServiceId],
        pre_init: bool,
    ) -> Self {
        let mut all: Vec<ServiceId> = members.iter().chain(inputs).copied().collect();
        all.sort();
        let members = all.as_slice();
        let mut index = vec![None; c.services.len()];
        for (i, &s) in members.iter().enumerate() {
            index[s.0 as usize] = Some(i);
        }
        let (delayers, forbidders) = reverse_rules(c, &index, members);
        let members: Vec<Member> = members
            .iter()
            .zip(delayers.into_iter().zip(forbidders))
            .map(|(&s, rules)| member(c, b, &index, s, rules, inputs.contains(&s)))
            .collect();
        // Only the codels of members are ever asked about: computing the
        // others for every cluster made many small clusters quadratic.
        let codel_structures = c
            .codels
            .values()
            .map(|k| match index[k.service.0 as usize] {
                Some(_) => k.structures(),
                None => Vec::new(),
            })
            .collect::<Vec<_>>();
        let layout = layout::Layout::new(&members);
        let running_codel = members
            .iter()
            .map(|m| {
                let positions = &b.machine(m.service).positions;
                positions
                    .iter()
                    .map(|p| p.codel().filter(|_| p.is_running()))
                    .collect()
            })
            .collect();
        let threads = members
            .iter()
            .map(|m| b.machine(m.service).thread)
            .collect();
        let controls: Vec<&[(StructureId, bool)]> =
            members.iter().map(|m| m.control.as_slice()).collect();
        let locks = locks::Locks::new(&codel_structures, &controls);
        let small = members.len() <= 64;
        let delayer_bits = members
            .iter()
            .filter(|_| small)
            .map(|m| m.delayers.iter().fold(0u64, |bits, &t| bits | 1 << t))
            .collect();
        let cycle_members = (0..members.len())
            .filter(|&i| small && !members[i].input && !b.machine(members[i].service).watchdog)
            .fold(0u64, |bits, i| bits | 1 << i);
        System {
            c,
            b,
            members,
            index,
            init: c.init_service(),
            pre_init,
            codel_structures,
            layout,
            running_codel,
            threads,
            locks,
            scratch: std::cell::RefCell::new(Vec::new()),
            reduction: None,
            delayer_bits,
            cycle_members,
        }
    }

    /// The same system, explored with the partial-order reduction `r`.
    #[must_use]
    pub fn reduced_by(mut self, r: impl Reduce + 'static) -> Self {
        self.reduction = Some(Box::new(r));
        self
    }

    /// Notes the facts of an expanded state `cfg` for the reduction (for a
    /// model built on this system that computes no stubborn sets).
    pub fn note_facts(&self, cfg: &Config) {
        if let Some(r) = &self.reduction {
            r.note(self, cfg);
        }
    }

    /// Runs the reduction's probes, if any (see
    /// [`crate::dialect::reduction::probe`]).
    pub fn probe(&self, limits: crate::kernel::explore::Limits) -> Option<Probed> {
        self.reduction.as_ref().and_then(|r| r.probe(self, limits))
    }

    /// Whether the reduction found every fact (exploring further changes
    /// nothing the analysis reads).
    pub fn all_found(&self) -> bool {
        self.reduction.as_ref().is_some_and(|r| r.finished())
    }

    /// Member indices of the `stops` targets of member `i` (itself
    /// included when it stops itself).
    pub fn stops_of(&self, i: usize) -> &[usize] {
        &self.members[i].stops
    }

    /// Member indices whose instances delay member `i` (its `delayers`).
    pub fn delayers_of(&self, i: usize) -> &[usize] {
        &self.members[i].delayers
    }

    /// Member indices whose instances make member `i`'s requests rejected.
    pub fn forbidders_of(&self, i: usize) -> &[usize] {
        &self.members[i].forbidders
    }

    /// Whether member `i` lists itself in `stops` (its requests are
    /// accepted while it has an instance).
    pub fn stops_itself(&self, i: usize) -> bool {
        self.members[i].self_stop
    }

    /// The component's init service.
    pub fn init(&self) -> Option<ServiceId> {
        self.init
    }

    /// The component.
    pub fn component(&self) -> &'a Component {
        self.c
    }

    /// The member services (inputs excluded).
    pub fn services(&self) -> impl Iterator<Item = ServiceId> + '_ {
        self.members.iter().filter(|m| !m.input).map(|m| m.service)
    }

    /// Whether member `i` is an input (takes no steps here).
    pub fn is_input(&self, i: usize) -> bool {
        self.members[i].input
    }

    /// Sets input member `i`: no instance (`None`), an instance, or one that
    /// may never end.
    pub fn set_input(cfg: &mut Config, i: usize, instance: Option<bool>) {
        cfg.pending[i] = instance.map(u64::from);
    }

    /// Whether member `i` has an instance that may never end by itself (an
    /// active loop without watchdog; for inputs, what the environment says).
    pub fn may_never_end(&self, cfg: &Config, i: usize) -> bool {
        if self.members[i].input {
            return cfg.pending[i] == Some(1);
        }
        cfg.main[i] != IDLE && self.machine(i).may_never_end[usize::from(cfg.main[i])]
    }

    /// The member index of a service.
    pub fn member_index(&self, s: ServiceId) -> Option<usize> {
        self.index.get(s.0 as usize).copied().flatten()
    }

    fn machine(&self, i: usize) -> &'a ServiceMachine {
        self.b.machine(self.members[i].service)
    }

    /// The codel member `i` runs in `cfg`, if any.
    pub fn running_codel(&self, cfg: &Config, i: usize) -> Option<CodelId> {
        self.running_codel[i]
            .get(usize::from(cfg.main[i]))
            .copied()
            .flatten()
    }

    /// With at most 64 members: the bits of member `i`'s `delayers`.
    pub fn delayer_bits(&self, i: usize) -> u64 {
        self.delayer_bits.get(i).copied().unwrap_or(0)
    }

    /// With at most 64 members: the bits of the members that may be on a
    /// cycle of pending instances (neither inputs nor with a watchdog).
    pub fn cycle_members(&self) -> u64 {
        self.cycle_members
    }

    /// The position of member `i`.
    pub fn position(&self, cfg: &Config, i: usize) -> Position {
        self.machine(i).positions[usize::from(cfg.main[i])]
    }

    /// Whether member `i` has an instance (main or pending).
    pub fn has_instance(cfg: &Config, i: usize) -> bool {
        cfg.main[i] != IDLE || cfg.pending[i].is_some()
    }

    /// The configuration where nothing has happened yet: autos are
    /// acknowledged when there is no init service (or `init_done`).
    pub fn initial(&self, init_done: bool, events: &mut Option<&mut Vec<TraceStep>>) -> Config {
        self.initial_with(init_done, |_| {}, events)
    }

    /// [`Self::initial`], with the inputs set by `inputs` first.
    pub fn initial_with(
        &self,
        init_done: bool,
        inputs: impl FnOnce(&mut Config),
        events: &mut Option<&mut Vec<TraceStep>>,
    ) -> Config {
        let n = self.members.len();
        let mut cfg = Config {
            init_done: init_done || self.init.is_none(),
            main: vec![IDLE; n],
            pending: vec![None; n],
            timed_out: vec![false; n],
        };
        inputs(&mut cfg);
        if cfg.init_done {
            self.start_autos(&mut cfg, events);
            self.closure(&mut cfg, events);
        }
        cfg
    }

    /// Steps 1–3: whether a request for member `i` gets to its control
    /// codel, and the control codel can take its locks now.
    pub fn request_enabled(&self, cfg: &Config, i: usize) -> bool {
        self.request_allowed(cfg, i) && !self.locked(cfg, Who::Control(i), None)
    }

    /// [`Self::request_enabled`] given the codels [`Self::running`] in
    /// `cfg`: callers asking for every member compute them once (a scan of
    /// all members per call made each visited state quadratic).
    pub fn request_enabled_among(
        &self,
        cfg: &Config,
        i: usize,
        running: &[(usize, CodelId)],
    ) -> bool {
        self.request_allowed(cfg, i)
            && !self.locked_by(running.iter().copied(), Who::Control(i), None)
    }

    /// Steps 1–2 (init, `forbids`, an instance already there).
    fn request_allowed(&self, cfg: &Config, i: usize) -> bool {
        let m = &self.members[i];
        if !cfg.init_done && self.init != Some(m.service) {
            return false;
        }
        if m.forbidders.iter().any(|&t| Self::has_instance(cfg, t)) {
            return false;
        }
        !Self::has_instance(cfg, i) || m.self_stop
    }

    /// The members running a codel in `cfg`, with that codel.
    pub fn running(&self, cfg: &Config) -> Vec<(usize, CodelId)> {
        self.running_iter(cfg).collect()
    }

    /// Calls `f` with [`Self::running`], gathered in a reused buffer.
    pub fn with_running<R>(&self, cfg: &Config, f: impl FnOnce(&[(usize, CodelId)]) -> R) -> R {
        match self.scratch.try_borrow_mut() {
            Ok(mut scratch) => {
                scratch.clear();
                scratch.extend(self.running_iter(cfg));
                f(scratch.as_slice())
            }
            Err(_) => f(&self.running(cfg)),
        }
    }

    fn running_iter<'c>(&'c self, cfg: &'c Config) -> impl Iterator<Item = (usize, CodelId)> + 'c {
        self.running_codel
            .iter()
            .zip(&cfg.main)
            .enumerate()
            .filter_map(|(j, (table, &p))| {
                table
                    .get(usize::from(p))
                    .copied()
                    .flatten()
                    .map(|codel| (j, codel))
            })
    }

    /// Whether some running codel of another thread (or of `thread`)
    /// conflicts with `who`.
    fn locked(&self, cfg: &Config, who: Who, thread: Option<(usize, ThreadId)>) -> bool {
        self.locked_by(self.running_iter(cfg), who, thread)
    }

    /// [`Self::locked`] over the given running codels.
    fn locked_by(
        &self,
        mut running: impl Iterator<Item = (usize, CodelId)>,
        who: Who,
        thread: Option<(usize, ThreadId)>,
    ) -> bool {
        running.any(|(j, codel)| {
            if let Some((me, t)) = thread {
                if j == me {
                    return false;
                }
                if self.threads[j] == Some(t) {
                    return true;
                }
            }
            match &self.locks {
                Some(locks) => locks.conflicts(who, codel),
                None => {
                    let uses = match who {
                        Who::Codel(k) => &self.codel_structures[k.0 as usize],
                        Who::Control(i) => &self.members[i].control,
                    };
                    conflict(uses, &self.codel_structures[codel.0 as usize])
                }
            }
        })
    }

    /// Whether member `i` may begin `codel` now: its thread is free and no
    /// running codel of another thread conflicts with it.
    pub fn can_begin(&self, cfg: &Config, i: usize, codel: CodelId) -> bool {
        let thread = self.threads[i].map(|t| (i, t));
        !self.locked(cfg, Who::Codel(codel), thread)
    }

    /// The structures a codel of a member uses, with write access (empty
    /// for a codel of another service).
    pub fn codel_uses(&self, codel: CodelId) -> &[(StructureId, bool)] {
        &self.codel_structures[codel.0 as usize]
    }

    /// The structures member `i`'s control codel uses, with write access.
    pub fn control_uses(&self, i: usize) -> &[(StructureId, bool)] {
        &self.members[i].control
    }

    /// Number of members.
    pub fn len(&self) -> usize {
        self.members.len()
    }

    /// True without members.
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
    }

    /// The service of member `i`.
    pub fn service(&self, i: usize) -> ServiceId {
        self.members[i].service
    }

    /// The local machine of member `i`.
    pub fn machine_of(&self, i: usize) -> &'a ServiceMachine {
        self.machine(i)
    }
}

/// Whether two uses conflict: a shared structure written by one of them.
pub use genom_model::component::uses_conflict as conflict;

/// For each member (in order), the other members whose `delays`, and
/// those whose `forbids`, name it: ascending, without repetition. One pass
/// over the members' rules (scanning every service for every member was
/// quadratic in the size of the component).
fn reverse_rules(
    c: &Component,
    index: &[Option<usize>],
    members: &[ServiceId],
) -> (Vec<Vec<usize>>, Vec<Vec<usize>>) {
    let mut delayers = vec![Vec::new(); members.len()];
    let mut forbidders = vec![Vec::new(); members.len()];
    for (j, &t) in members.iter().enumerate() {
        let ts = &c.services[t];
        for (rule, out) in [(&ts.delays, &mut delayers), (&ts.forbids, &mut forbidders)] {
            for r in rule.iter().filter(|r| r.id != t) {
                let Some(list) = index
                    .get(r.id.0 as usize)
                    .copied()
                    .flatten()
                    .and_then(|i| out.get_mut(i))
                else {
                    continue;
                };
                if list.last() != Some(&j) {
                    list.push(j);
                }
            }
        }
    }
    (delayers, forbidders)
}

fn member(
    c: &Component,
    b: &Behaviour,
    index: &[Option<usize>],
    s: ServiceId,
    (delayers, forbidders): (Vec<usize>, Vec<usize>),
    input: bool,
) -> Member {
    let svc = &c.services[s];
    let idx = |t: ServiceId| index.get(t.0 as usize).copied().flatten();
    let mut stops: Vec<usize> = Vec::new();
    for t in svc.stops.iter().filter_map(|r| idx(r.id)) {
        if !stops.contains(&t) {
            stops.push(t);
        }
    }
    let control = svc
        .control
        .map(|k| c.codels[k].structures())
        .unwrap_or_default();
    let positions = b.machine(s).positions.len();
    let pos_bits = usize::BITS - positions.saturating_sub(1).leading_zeros();
    let can_pend = !delayers.is_empty() || !stops.is_empty();
    if input {
        // Only its pending slot is stored: one bit of presence, one of
        // "may never end".
        return Member {
            service: s,
            self_stop: false,
            stops: Vec::new(),
            delayers: Vec::new(),
            forbidders: Vec::new(),
            control: Vec::new(),
            pos_bits: 0,
            can_pend: true,
            watchdog: false,
            input,
        };
    }
    Member {
        service: s,
        self_stop: svc.stops.iter().any(|r| r.id == s),
        stops,
        delayers,
        forbidders,
        control,
        pos_bits,
        can_pend,
        watchdog: svc.max_time.is_some(),
        input,
    }
}

/// Bits of a member's wait mask (at most 64 `stops` targets are tracked;
/// the analysis refuses larger ones as incomplete).
fn stop_bits(m: &Member) -> u32 {
    if m.input {
        return 1;
    }
    u32::try_from(m.stops.len()).unwrap_or(64).min(64)
}

impl System<'_> {
    /// Whether some member stops more than 64 services (not representable).
    pub fn too_many_stops(&self) -> bool {
        self.members.iter().any(|m| m.stops.len() > 64)
    }
}
