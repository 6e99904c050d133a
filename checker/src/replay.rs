//! An independent replay of the execution semantics (LANGUAGE.md section 3)
//! against a verdict's trace.
//!
//! The explorer (`crate::engine`) and this module are two readings of the
//! same text; this one is written from the specification alone and shares
//! no code with the explorer nor with `genom_model::behaviour`: it reads
//! only the resolved [`Component`] (services, codels and their `next`,
//! `on-inter`, `stops`/`delays`/`forbids`, `max-time`, kinds, threads and
//! [`Component::conflicts`]). It trusts nothing in the trace: every step is
//! checked to be allowed in the current state, and the state after the last
//! step is checked to show the claimed violation ([`ReplayEnd::exhibits`]).
//!
//! # State
//!
//! For each service, a list of *instances* ([`Instance`]): `pending`
//! (acknowledged, not started, with the interrupted instances it still
//! waits for), `active` at a codel (ready, or running, possibly with the
//! interrupt noted), or `stopping` at a codel (ready or running). Plus
//! whether initialisation is done.
//!
//! # How steps are read
//!
//! - `component-start` is the first step, and only the first. Without an
//!   `init` service, initialisation is done at once.
//! - `request` S (thread `control`) opens a request, closed by `reject` or
//!   `acknowledge`; one request at a time. The rules of section 3 are
//!   applied in order: a `reject`
//!   must give (in `outcome`) the reason of the first rule that applies
//!   (`NOT_INITIALIZED`, `FORBIDDEN`, `BUSY`); when none applies, only the
//!   control codel can reject (with one of S's reports) or `accept`, and it
//!   must be able to take its locks (no conflicting codel is running) from
//!   the `request` step on. The control codel runs on the control thread
//!   from `request` to its `accept` or `reject`, which may be later (a
//!   timed trace): meanwhile the other threads go on (`wake-up`,
//!   `codel-start` of a codel that does not conflict with it, `codel-end`,
//!   `start`, `reply`, `watchdog`), but no other request is handled. Then
//!   every instance of the services of `S.stops` must be interrupted
//!   (`interrupt` steps; `codel` is `null` for a pending instance, else the
//!   instance's current codel) before `acknowledge` creates the pending
//!   instance, which waits for the stopped instances still running.
//! - `start` S: S's pending instance starts; it must not be delayed (no
//!   other service with an instance lists S in `delays`) nor wait for a
//!   stopped instance. Starting is urgent: no other step than `start`,
//!   `reply`, `acknowledge` or the steps of an open request may happen
//!   while some pending instance can start.
//! - `codel-start` S `codel`: S's instance is ready at that codel; its
//!   thread runs no other codel, and no codel running on another thread
//!   conflicts with it.
//! - `codel-end` S `codel` `outcome`: the running codel ends; the outcome
//!   must be in its `next` (`end` for an empty `next`). An interrupted
//!   active instance goes to the codel's `on-inter` instead (the outcome may
//!   then be `null`), or ends with `INTERRUPTED`.
//! - `interrupt` only inside a request, for a service of the requester's
//!   `stops`; `watchdog` only for a service with `max-time`. A stopping
//!   instance (or one whose running codel was already interrupted) is not
//!   interrupted again.
//! - Every ending is followed at once by the `reply` step of that instance
//!   with its value: `end`, a report, `INTERRUPTED`, or `TIMEOUT` when the
//!   watchdog interrupted it (an inter codel's report outcome replies that
//!   report). A reply must carry its value, and there is exactly one per
//!   instance.
//! - When initialisation completes (at `component-start` without an `init`
//!   service, else when the `init` service replies `end`), every `auto`
//!   service starts (`start` with no request: it becomes active at its start
//!   codel, or completes at once without one) before anything else happens,
//!   whatever `delays` or `forbids` the autos list about each other: autos
//!   are never pending.
//! - `wake-up` and `delay` change nothing in this untimed reading; `time_ns`
//!   must not decrease.
//! - `violation` is the last step, and there is one.
//!
//! With `loop_start`, the steps from there to the violation must lead back
//! to the state they start from (instances compared by service, phase and
//! codel), so that they can repeat forever.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::fmt;

use genom_model::component::{CodelId, Component, Outcome, ServiceId};
use genom_model::kinds::ServiceKind;
use genom_model::trace::{Event, Trace, TraceStep};

/// Identity of one instance within a replay.
pub type InstanceId = u32;

/// Where an instance is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Phase {
    /// Acknowledged, not started; still waiting for these interrupted
    /// instances to end (step 7b).
    Pending {
        /// Instances (of services in its `stops`) it waits for.
        waits_for: BTreeSet<InstanceId>,
    },
    /// Active at `codel`.
    Active {
        /// The next codel (ready) or the running one.
        codel: CodelId,
        /// Its thread runs `codel` now.
        running: bool,
        /// The codel it ran last (`None` before its start codel ran).
        last_ran: Option<CodelId>,
        /// Interrupted while `codel` runs.
        interrupted: bool,
    },
    /// Interrupted, following its inter codels.
    Stopping {
        /// The next codel (ready) or the running one.
        codel: CodelId,
        /// Its thread runs `codel` now.
        running: bool,
    },
}

/// One service instance.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Instance {
    /// Its identity in this replay.
    pub id: InstanceId,
    /// Where it is.
    pub phase: Phase,
    /// Interrupted by the max-time watchdog (it will reply `TIMEOUT`).
    pub by_watchdog: bool,
}

impl Instance {
    /// True while acknowledged and not started.
    pub fn is_pending(&self) -> bool {
        matches!(self.phase, Phase::Pending { .. })
    }

    /// The codel it is at, if started.
    pub fn codel(&self) -> Option<CodelId> {
        match self.phase {
            Phase::Pending { .. } => None,
            Phase::Active { codel, .. } | Phase::Stopping { codel, .. } => Some(codel),
        }
    }

    /// The codel its thread runs now, if any.
    pub fn running(&self) -> Option<CodelId> {
        match self.phase {
            Phase::Active {
                codel,
                running: true,
                ..
            }
            | Phase::Stopping {
                codel,
                running: true,
            } => Some(codel),
            _ => None,
        }
    }

    /// True once interrupted: stopping, or running with the interrupt noted.
    pub fn is_interrupted(&self) -> bool {
        matches!(
            self.phase,
            Phase::Stopping { .. }
                | Phase::Active {
                    interrupted: true,
                    ..
                }
        )
    }
}

/// The replayed state of the component.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct State {
    /// The `init` service has completed successfully (always true without
    /// one).
    pub init_done: bool,
    /// The instances of each service, by service index.
    pub instances: Vec<Vec<Instance>>,
    next_id: InstanceId,
}

/// One instance as compared between the two ends of a loop: identities
/// are forgotten; an active instance between codels is described by what
/// an interrupt would do to it.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
enum Shape {
    Pending(Vec<(ServiceId, Option<CodelId>)>),
    Ready {
        codel: CodelId,
        interrupt_leads_to: Option<CodelId>,
    },
    Running {
        codel: CodelId,
        interrupted: bool,
        by_watchdog: bool,
    },
    Stopping {
        codel: CodelId,
        running: bool,
        by_watchdog: bool,
    },
}

impl State {
    /// The instances of `s`.
    pub fn of(&self, s: ServiceId) -> &[Instance] {
        self.instances.get(s.0 as usize).map_or(&[], Vec::as_slice)
    }

    /// The pending instance of `s`, if any.
    pub fn pending(&self, s: ServiceId) -> Option<&Instance> {
        self.of(s).iter().find(|i| i.is_pending())
    }

    /// The started (active or stopping) instance of `s`, if any.
    pub fn started(&self, s: ServiceId) -> Option<&Instance> {
        self.of(s).iter().find(|i| !i.is_pending())
    }

    fn has_instance(&self, s: ServiceId) -> bool {
        !self.of(s).is_empty()
    }

    fn find(&self, id: InstanceId) -> Option<(ServiceId, &Instance)> {
        self.instances.iter().enumerate().find_map(|(k, v)| {
            let s = ServiceId(u32::try_from(k).ok()?);
            v.iter().find(|i| i.id == id).map(|i| (s, i))
        })
    }

    fn shape(&self, c: &Component) -> Vec<Vec<Shape>> {
        let owner = |id: InstanceId| self.find(id).map(|(s, i)| (s, i.codel()));
        self.instances
            .iter()
            .map(|v| {
                let mut shapes: Vec<Shape> = v
                    .iter()
                    .map(|i| match &i.phase {
                        Phase::Pending { waits_for } => {
                            let mut w: Vec<_> =
                                waits_for.iter().filter_map(|&id| owner(id)).collect();
                            w.sort();
                            Shape::Pending(w)
                        }
                        &Phase::Active {
                            codel,
                            running: false,
                            last_ran,
                            ..
                        } => Shape::Ready {
                            codel,
                            interrupt_leads_to: interrupt_target(c, last_ran),
                        },
                        &Phase::Active {
                            codel,
                            running: true,
                            interrupted,
                            ..
                        } => Shape::Running {
                            codel,
                            interrupted,
                            by_watchdog: i.by_watchdog,
                        },
                        &Phase::Stopping { codel, running } => Shape::Stopping {
                            codel,
                            running,
                            by_watchdog: i.by_watchdog,
                        },
                    })
                    .collect();
                shapes.sort();
                shapes
            })
            .collect()
    }

    fn describe(&self, c: &Component) -> String {
        let mut parts = Vec::new();
        for (k, v) in self.instances.iter().enumerate() {
            let Some(svc) = u32::try_from(k)
                .ok()
                .and_then(|k| c.services.get(ServiceId(k)))
            else {
                continue;
            };
            for i in v {
                let what = match &i.phase {
                    Phase::Pending { .. } => "pending".to_owned(),
                    Phase::Active {
                        codel,
                        running,
                        interrupted,
                        ..
                    } => format!(
                        "active {} `{}`{}",
                        if *running { "running" } else { "at" },
                        c.codels[*codel].name.name,
                        if *interrupted { " (interrupted)" } else { "" }
                    ),
                    Phase::Stopping { codel, running } => {
                        format!(
                            "stopping, {} `{}`",
                            if *running { "running" } else { "at" },
                            c.codels[*codel].name.name
                        )
                    }
                };
                parts.push(format!("`{}` {what}", svc.name.name));
            }
        }
        if parts.is_empty() {
            "no instance".to_owned()
        } else {
            parts.join(", ")
        }
    }
}

/// The inter codel an interrupt leads to for an active instance between
/// codels: the `on-inter` of the codel it ran last (none before its start
/// codel ran: it then ends at once).
fn interrupt_target(c: &Component, last_ran: Option<CodelId>) -> Option<CodelId> {
    last_ran.and_then(|k| c.codels[k].on_inter.map(|r| r.id))
}

/// Why a step (or the trace as a whole) is not allowed by the semantics.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReplayError {
    /// The 1-based number of the failing step (as the trace is displayed);
    /// 0 when the problem is the trace as a whole.
    pub step: usize,
    /// The failing step, described.
    pub what: String,
    /// Why it is wrong.
    pub why: String,
}

impl fmt::Display for ReplayError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.step == 0 {
            write!(f, "trace: {}", self.why)
        } else {
            write!(f, "step {} ({}): {}", self.step, self.what, self.why)
        }
    }
}

impl std::error::Error for ReplayError {}

/// What a request led to, as the trace says.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Fate {
    /// Rejected with this reason.
    Rejected(String),
    /// Acknowledged (the instance became pending).
    Acknowledged,
}

/// A violation the end of a trace should show.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Claim<'a> {
    /// These services are pending and wait on each other through `delays`.
    Deadlock(&'a [&'a str]),
    /// `waiter` is pending, blocked by `blocker`'s instance, which the loop
    /// keeps running forever.
    Starvation {
        /// The pending service.
        waiter: &'a str,
        /// The service whose instance never ends.
        blocker: &'a str,
    },
    /// The service is stopping and the loop keeps it stopping forever.
    UnboundedInterrupt(&'a str),
    /// The service never started in the trace, and its last request was
    /// rejected or is still pending and cannot start.
    DeadService(&'a str),
}

/// The outcome of a successful replay: the final state and what the trace
/// showed on the way.
#[derive(Debug, Clone)]
pub struct ReplayEnd {
    /// The state when the violation is reported.
    pub state: State,
    /// With `loop_start`, the state before each step of the loop and the
    /// state after its last step (equal to the first).
    pub loop_states: Vec<State>,
    /// The steps of the loop (index into the trace, service involved).
    pub loop_steps: Vec<(usize, Event, Option<ServiceId>)>,
    /// Services that started (or, without start codel, completed) at some
    /// step.
    pub started: BTreeSet<ServiceId>,
    /// What the last request of each requested service led to (for an
    /// auto service, its acknowledgment when initialisation completes).
    pub fates: BTreeMap<ServiceId, Fate>,
    /// The 1-based number of the violation step.
    pub violation_step: usize,
}

/// Replays `trace` in `c` from component start; fails at the first step the
/// semantics does not allow (or if the trace is not shaped as a verdict's
/// trace: `component-start` first, `violation` last, a well-formed loop).
pub fn replay(c: &Component, trace: &Trace) -> Result<ReplayEnd, ReplayError> {
    Replayer::new(c).run(trace)
}

/// [`replay`], then [`ReplayEnd::exhibits`].
pub fn replay_claim(
    c: &Component,
    trace: &Trace,
    claim: Claim<'_>,
) -> Result<ReplayEnd, ReplayError> {
    let end = replay(c, trace)?;
    end.exhibits(c, claim)?;
    Ok(end)
}

/// A step as shown in error messages: `codel-end `move::start` → `brake``.
fn describe_step(step: &TraceStep) -> String {
    let mut s = step.event.as_str().to_owned();
    match (&step.service, &step.codel) {
        (Some(svc), Some(k)) => s.push_str(&format!(" `{svc}::{k}`")),
        (Some(svc), None) => s.push_str(&format!(" `{svc}`")),
        _ => {}
    }
    if let Some(o) = &step.outcome {
        s.push_str(&format!(" → `{o}`"));
    }
    s
}

/// An open request (between `request` and `acknowledge`/`reject`).
#[derive(Debug, Clone)]
struct OpenRequest {
    service: ServiceId,
    /// The first of rules 1–3 that rejects it.
    rule: Option<&'static str>,
    /// Past step 4 (accepted by the control codel, or none): interrupting.
    accepted: bool,
}

impl OpenRequest {
    /// The control codel of the request is running (step 4, which takes
    /// time on the control thread while the other threads go on).
    fn in_control_codel(&self, c: &Component) -> bool {
        self.rule.is_none() && !self.accepted && c.services[self.service].control.is_some()
    }
}

struct Replayer<'c> {
    c: &'c Component,
    state: State,
    replies: VecDeque<(ServiceId, String)>,
    autos_due: Vec<ServiceId>,
    request: Option<OpenRequest>,
    started: BTreeSet<ServiceId>,
    fates: BTreeMap<ServiceId, Fate>,
    last_time: Option<u64>,
}

type StepResult = Result<(), String>;

impl<'c> Replayer<'c> {
    fn new(c: &'c Component) -> Self {
        let init_done = c.init_service().is_none();
        Replayer {
            c,
            state: State {
                init_done,
                instances: vec![Vec::new(); c.services.len()],
                next_id: 0,
            },
            replies: VecDeque::new(),
            autos_due: Vec::new(),
            request: None,
            started: BTreeSet::new(),
            fates: BTreeMap::new(),
            last_time: None,
        }
    }

    fn run(mut self, trace: &Trace) -> Result<ReplayEnd, ReplayError> {
        let steps = &trace.steps;
        let whole = |why: String| ReplayError {
            step: 0,
            what: String::new(),
            why,
        };
        if steps.first().map(|s| s.event) != Some(Event::ComponentStart) {
            return Err(whole("the first step must be `component-start`".to_owned()));
        }
        let last = steps.len() - 1;
        if steps[last].event != Event::Violation {
            return Err(whole("the last step must be the `violation`".to_owned()));
        }
        if let Some(k) = trace.loop_start {
            if k == 0 || k >= last {
                return Err(whole(format!(
                    "loop_start {k} does not designate a step between component start and the violation (steps 2 to {last})"
                )));
            }
        }
        let mut loop_states = Vec::new();
        let mut loop_steps = Vec::new();
        for (k, step) in steps.iter().enumerate() {
            let fail = |why: String| ReplayError {
                step: k + 1,
                what: describe_step(step),
                why,
            };
            if trace.loop_start.is_some_and(|l| k >= l && k < last) {
                loop_states.push(self.state.clone());
                loop_steps.push((
                    k,
                    step.event,
                    step.service
                        .as_deref()
                        .and_then(|n| self.c.service_named(n)),
                ));
            }
            if let Some(t) = step.time_ns {
                if self.last_time.is_some_and(|p| t < p) {
                    return Err(fail(format!(
                        "time goes backwards ({t} ns after {} ns)",
                        self.last_time.unwrap_or(0)
                    )));
                }
                self.last_time = Some(t);
            }
            if step.event == Event::Violation && k != last {
                return Err(fail("a violation can only be the last step".to_owned()));
            }
            if step.event == Event::ComponentStart && k != 0 {
                return Err(fail(
                    "the component starts only once, at the first step".to_owned(),
                ));
            }
            self.step(step).map_err(fail)?;
        }
        if trace.loop_start.is_some() {
            loop_states.push(self.state.clone());
            let (first, end) = (&loop_states[0], &self.state);
            if first.shape(self.c) != end.shape(self.c) {
                return Err(ReplayError {
                    step: last + 1,
                    what: "violation".to_owned(),
                    why: format!(
                        "the steps from the loop start do not lead back to the state where the loop starts, so they cannot repeat forever: at the loop start {}; after the loop {}",
                        first.describe(self.c),
                        end.describe(self.c)
                    ),
                });
            }
        }
        Ok(ReplayEnd {
            state: self.state,
            loop_states,
            loop_steps,
            started: self.started,
            fates: self.fates,
            violation_step: last + 1,
        })
    }

    fn name(&self, s: ServiceId) -> &'c str {
        &self.c.services[s].name.name
    }

    fn codel_name(&self, k: CodelId) -> &'c str {
        &self.c.codels[k].name.name
    }

    fn thread_name(&self, s: ServiceId) -> &'c str {
        self.c.services[s]
            .thread
            .map_or("control", |t| self.c.threads[t.id].name.name.as_str())
    }

    /// The service a step names.
    fn service_of(&self, step: &TraceStep) -> Result<ServiceId, String> {
        let name = step.service.as_deref().ok_or("the step names no service")?;
        self.c
            .service_named(name)
            .ok_or_else(|| format!("the component has no service `{name}`"))
    }

    fn codel_of(&self, s: ServiceId, step: &TraceStep) -> Result<Option<CodelId>, String> {
        match step.codel.as_deref() {
            None => Ok(None),
            Some(k) => self
                .c
                .codel_named(s, k)
                .map(Some)
                .ok_or_else(|| format!("service `{}` has no codel `{k}`", self.name(s))),
        }
    }

    fn check_thread(&self, step: &TraceStep, expected: &str) -> StepResult {
        match step.thread.as_deref() {
            Some(t) if t != expected => {
                Err(format!("this happens on thread `{expected}`, not `{t}`"))
            }
            _ => Ok(()),
        }
    }

    fn step(&mut self, step: &TraceStep) -> StepResult {
        if step.event != Event::Reply {
            if let Some((s, v)) = self.replies.front() {
                return Err(format!(
                    "`{}` has ended: its final reply `{v}` must come first",
                    self.name(*s)
                ));
            }
        }
        match step.event {
            Event::ComponentStart => {
                if self.state.init_done {
                    self.initialised();
                }
                Ok(())
            }
            Event::Request => self.request(step),
            Event::Accept => self.accept(step),
            Event::Reject => self.reject(step),
            Event::Interrupt => self.interrupt(step),
            Event::Acknowledge => self.acknowledge(step),
            Event::Start => self.start(step),
            Event::CodelStart => self.codel_start(step),
            Event::CodelEnd => self.codel_end(step),
            Event::Watchdog => self.watchdog(step),
            Event::Reply => self.reply(step),
            Event::WakeUp | Event::Delay | Event::Violation => self.settled(),
        }
    }

    /// Initialisation is complete: every auto service is due.
    fn initialised(&mut self) {
        self.autos_due = self
            .c
            .services
            .iter()
            .filter(|(_, s)| s.kind == ServiceKind::Auto)
            .map(|(id, _)| id)
            .collect();
    }

    /// The state is stable: no open request (except one whose control
    /// codel runs, while the other threads go on), no owed reply or auto
    /// acknowledgment, no pending instance that can start.
    fn settled(&self) -> StepResult {
        if let Some(r) = self
            .request
            .as_ref()
            .filter(|r| !r.in_control_codel(self.c))
        {
            return Err(format!(
                "the request for `{}` is still being handled (it must be acknowledged or rejected first)",
                self.name(r.service)
            ));
        }
        if let Some(&a) = self.autos_due.first() {
            return Err(format!(
                "initialisation is complete: auto service `{}` must start before anything else",
                self.name(a)
            ));
        }
        for (s, _) in self.c.services.iter() {
            if self.state.pending(s).is_some() && self.start_blocker(s).is_none() {
                return Err(format!(
                    "`{}` is pending and nothing stops it from starting: it must start first (step 7: as soon as it can)",
                    self.name(s)
                ));
            }
        }
        Ok(())
    }

    /// Why the pending instance of `s` cannot start, or `None` if it can.
    fn start_blocker(&self, s: ServiceId) -> Option<String> {
        let Some(Instance {
            phase: Phase::Pending { waits_for },
            ..
        }) = self.state.pending(s)
        else {
            return Some(format!("`{}` has no pending instance", self.name(s)));
        };
        for (t, ts) in self.c.services.iter() {
            if t != s && self.state.has_instance(t) && ts.delays.iter().any(|r| r.id == s) {
                return Some(format!(
                    "`{}` has an instance and delays `{}` (step 7a)",
                    ts.name.name,
                    self.name(s)
                ));
            }
        }
        for &id in waits_for {
            if let Some((t, i)) = self.state.find(id) {
                let at = i
                    .codel()
                    .map(|k| format!(" at `{}`", self.codel_name(k)))
                    .unwrap_or_default();
                return Some(format!(
                    "it still waits for the interrupted instance of `{}`{at} to end (step 7b)",
                    self.name(t)
                ));
            }
        }
        if let Some(i) = self.state.started(s) {
            let at = i
                .codel()
                .map(|k| format!(" at `{}`", self.codel_name(k)))
                .unwrap_or_default();
            return Some(format!("`{}` still has an instance{at}", self.name(s)));
        }
        None
    }

    /// The first of request rules 1–3 that rejects a request for `s`.
    fn rule(&self, s: ServiceId) -> Option<&'static str> {
        if let Some(init) = self.c.init_service() {
            if !self.state.init_done && init != s {
                return Some("NOT_INITIALIZED");
            }
        }
        let forbidden = self.c.services.iter().any(|(t, ts)| {
            t != s && self.state.has_instance(t) && ts.forbids.iter().any(|r| r.id == s)
        });
        if forbidden {
            return Some("FORBIDDEN");
        }
        let svc = &self.c.services[s];
        if self.state.has_instance(s) && !svc.stops.iter().any(|r| r.id == s) {
            return Some("BUSY");
        }
        None
    }

    fn request(&mut self, step: &TraceStep) -> StepResult {
        if let Some(r) = &self.request {
            return Err(format!(
                "the control thread still handles the request for `{}`: one request at a time",
                self.name(r.service)
            ));
        }
        self.settled()?;
        self.check_thread(step, "control")?;
        let s = self.service_of(step)?;
        let rule = self.rule(s);
        if rule.is_none() {
            self.control_locks(s)?;
        }
        let accepted = rule.is_none() && self.c.services[s].control.is_none();
        self.request = Some(OpenRequest {
            service: s,
            rule,
            accepted,
        });
        Ok(())
    }

    fn open_request(&self, step: &TraceStep, s: ServiceId) -> Result<OpenRequest, String> {
        match &self.request {
            Some(r) if r.service == s => Ok(r.clone()),
            Some(r) => Err(format!(
                "the open request is for `{}`, not `{}`",
                self.name(r.service),
                self.name(s)
            )),
            None => Err(format!(
                "no request for `{}` is being handled",
                step.service.as_deref().unwrap_or("?")
            )),
        }
    }

    /// The control codel of `s` can take its locks now.
    fn control_locks(&self, s: ServiceId) -> StepResult {
        let Some(control) = self.c.services[s].control else {
            return Ok(());
        };
        for (t, v) in self.c.services.iter().map(|(t, _)| (t, self.state.of(t))) {
            for k in v.iter().filter_map(Instance::running) {
                if self.c.conflicts(control, k) {
                    return Err(format!(
                        "the control codel of `{}` conflicts with `{}::{}`, which is running: it cannot run now",
                        self.name(s),
                        self.name(t),
                        self.codel_name(k)
                    ));
                }
            }
        }
        Ok(())
    }

    fn accept(&mut self, step: &TraceStep) -> StepResult {
        let s = self.service_of(step)?;
        let r = self.open_request(step, s)?;
        self.check_thread(step, "control")?;
        if let Some(reason) = r.rule {
            return Err(format!(
                "the request must be rejected with `{reason}` before any control codel runs"
            ));
        }
        let Some(control) = self.c.services[s].control else {
            return Err(format!(
                "`{}` has no control codel to accept the request",
                self.name(s)
            ));
        };
        if r.accepted {
            return Err("the request was already accepted".to_owned());
        }
        if self.codel_of(s, step)?.is_some_and(|k| k != control) {
            return Err("only the control codel accepts a request".to_owned());
        }
        self.control_locks(s)?;
        if let Some(r) = &mut self.request {
            r.accepted = true;
        }
        Ok(())
    }

    fn reject(&mut self, step: &TraceStep) -> StepResult {
        let s = self.service_of(step)?;
        let r = self.open_request(step, s)?;
        let Some(reason) = step.outcome.as_deref() else {
            return Err("a rejection must give its reason (NOT_INITIALIZED, FORBIDDEN, BUSY or a report) in `outcome`; none is given".to_owned());
        };
        match r.rule {
            Some(expected) if expected != reason => {
                return Err(format!(
                    "the request must be rejected with `{expected}` (the first rule of section 3 that applies), not `{reason}`"
                ));
            }
            Some(_) => {}
            None => {
                if r.accepted {
                    return Err(
                        "the request was already accepted: it cannot be rejected now".to_owned(),
                    );
                }
                if self.c.services[s].control.is_none() {
                    return Err(format!(
                        "no rule rejects this request (`{}` is not forbidden, not busy, initialisation is done) and it has no control codel: `{reason}` is not possible",
                        self.name(s)
                    ));
                }
                if self.c.services[s].report(reason).is_none() {
                    return Err(format!(
                        "no rule rejects this request, so only its control codel can, with one of `{}`'s reports; `{reason}` is not one",
                        self.name(s)
                    ));
                }
                self.control_locks(s)?;
            }
        }
        self.request = None;
        self.fates.insert(s, Fate::Rejected(reason.to_owned()));
        Ok(())
    }

    fn interrupt(&mut self, step: &TraceStep) -> StepResult {
        let t = self.service_of(step)?;
        let Some(r) = self.request.clone() else {
            return Err(format!(
                "`{}` is interrupted but no request is being handled: only a request (step 5) or the watchdog interrupts",
                self.name(t)
            ));
        };
        let requester = &self.c.services[r.service];
        if !r.accepted {
            return Err(format!(
                "the request for `{}` is not accepted yet: interrupts come after the control codel (step 5)",
                requester.name.name
            ));
        }
        if !requester.stops.iter().any(|x| x.id == t) {
            return Err(format!(
                "`{}` does not list `{}` in `stops`: it cannot interrupt it",
                requester.name.name,
                self.name(t)
            ));
        }
        let codel = self.codel_of(t, step)?;
        self.interrupt_instance(t, codel, false)
    }

    fn watchdog(&mut self, step: &TraceStep) -> StepResult {
        self.settled()?;
        let s = self.service_of(step)?;
        if self.c.services[s].max_time.is_none() {
            return Err(format!(
                "`{}` has no `max-time`: no watchdog can interrupt it",
                self.name(s)
            ));
        }
        let codel = self.codel_of(s, step)?;
        self.interrupt_instance(s, codel, true)
    }

    /// Interrupts the pending instance of `s` (`codel` is `None`) or its
    /// started one at `codel`.
    fn interrupt_instance(
        &mut self,
        s: ServiceId,
        codel: Option<CodelId>,
        watchdog: bool,
    ) -> StepResult {
        let reply = if watchdog { "TIMEOUT" } else { "INTERRUPTED" };
        let v = &self.state.instances[s.0 as usize];
        let pos = match codel {
            None => v.iter().position(Instance::is_pending).ok_or_else(|| {
                format!("`{}` has no pending instance (the step names no codel, so it is about a pending one)", self.name(s))
            })?,
            Some(k) => v.iter().position(|i| i.codel() == Some(k)).ok_or_else(|| {
                format!("`{}` has no instance at `{}`: {}", self.name(s), self.codel_name(k), self.state.describe(self.c))
            })?,
        };
        let inst = &v[pos];
        if inst.is_interrupted() {
            return Err(format!(
                "`{}` is already interrupted: a stopping service is not interrupted again",
                self.name(s)
            ));
        }
        let c = self.c;
        let ends = match inst.phase.clone() {
            Phase::Pending { .. } => true,
            Phase::Active { running: true, .. } => {
                let inst = &mut self.state.instances[s.0 as usize][pos];
                if let Phase::Active { interrupted, .. } = &mut inst.phase {
                    *interrupted = true;
                }
                inst.by_watchdog = watchdog;
                false
            }
            Phase::Active {
                running: false,
                last_ran,
                ..
            } => match interrupt_target(c, last_ran) {
                Some(x) => {
                    let inst = &mut self.state.instances[s.0 as usize][pos];
                    inst.phase = Phase::Stopping {
                        codel: x,
                        running: false,
                    };
                    inst.by_watchdog = watchdog;
                    false
                }
                None => true,
            },
            Phase::Stopping { .. } => {
                return Err(format!(
                    "`{}` is stopping: it is not interrupted again",
                    self.name(s)
                ));
            }
        };
        if ends {
            self.end(s, pos, reply.to_owned(), false);
        }
        Ok(())
    }

    fn acknowledge(&mut self, step: &TraceStep) -> StepResult {
        self.check_thread(step, "control")?;
        let s = self.service_of(step)?;
        if let Some(r) = self.request.clone() {
            if r.service != s {
                return Err(format!(
                    "the open request is for `{}`, not `{}`",
                    self.name(r.service),
                    self.name(s)
                ));
            }
            if let Some(reason) = r.rule {
                return Err(format!("the request must be rejected with `{reason}`"));
            }
            if !r.accepted {
                return Err(format!(
                    "`{}` has a control codel: it must accept the request first (step 4)",
                    self.name(s)
                ));
            }
            let mut waits_for = BTreeSet::new();
            for t in self.c.services[s].stops.iter().map(|x| x.id) {
                for i in self.state.of(t) {
                    if !i.is_interrupted() {
                        let at = i.codel().map_or_else(
                            || " (pending)".to_owned(),
                            |k| format!(" at `{}`", self.codel_name(k)),
                        );
                        return Err(format!(
                            "`{}` stops `{}`, whose instance{at} was not interrupted (step 5 comes before the acknowledgment)",
                            self.name(s),
                            self.name(t)
                        ));
                    }
                    waits_for.insert(i.id);
                }
            }
            if self.state.pending(s).is_some() {
                return Err(format!("`{}` already has a pending instance", self.name(s)));
            }
            self.new_pending(s, waits_for);
            self.request = None;
            self.fates.insert(s, Fate::Acknowledged);
            return Ok(());
        }
        Err(format!(
            "`{}` is acknowledged without a request: auto services are not acknowledged, they start when initialisation completes",
            self.name(s)
        ))
    }

    fn new_pending(&mut self, s: ServiceId, waits_for: BTreeSet<InstanceId>) {
        let id = self.state.next_id;
        self.state.next_id += 1;
        self.state.instances[s.0 as usize].push(Instance {
            id,
            phase: Phase::Pending { waits_for },
            by_watchdog: false,
        });
    }

    fn start(&mut self, step: &TraceStep) -> StepResult {
        let s = self.service_of(step)?;
        if let Some(at) = self.autos_due.iter().position(|&a| a == s) {
            // An auto service is not a request: it gets its instance and
            // starts at once, whatever delays or forbids it (section 3).
            self.autos_due.remove(at);
            if self.state.has_instance(s) {
                return Err(format!(
                    "auto service `{}` already has an instance",
                    self.name(s)
                ));
            }
            self.new_pending(s, BTreeSet::new());
            // No client requests an auto service: its start is its fate.
            self.fates.insert(s, Fate::Acknowledged);
        } else if let Some(why) = self.start_blocker(s) {
            return Err(format!("`{}` cannot start: {why}", self.name(s)));
        }
        let codel = self.codel_of(s, step)?;
        let svc = &self.c.services[s];
        let pos = self.state.instances[s.0 as usize]
            .iter()
            .position(Instance::is_pending)
            .unwrap_or_default();
        self.started.insert(s);
        match svc.start {
            Some(start) => {
                if codel.is_some_and(|k| k != start) {
                    return Err(format!(
                        "`{}` starts at its start codel, not at `{}`",
                        self.name(s),
                        step.codel.as_deref().unwrap_or("")
                    ));
                }
                self.state.instances[s.0 as usize][pos].phase = Phase::Active {
                    codel: start,
                    running: false,
                    last_ran: None,
                    interrupted: false,
                };
            }
            None => {
                if codel.is_some() {
                    return Err(format!(
                        "`{}` has no start codel: it completes at once",
                        self.name(s)
                    ));
                }
                self.end(s, pos, "end".to_owned(), true);
            }
        }
        Ok(())
    }

    fn codel_start(&mut self, step: &TraceStep) -> StepResult {
        self.settled()?;
        let s = self.service_of(step)?;
        let thread = self.thread_name(s);
        self.check_thread(step, thread)?;
        let Some(k) = self.codel_of(s, step)? else {
            return Err("the step names no codel".to_owned());
        };
        let pos = self.state.instances[s.0 as usize]
            .iter()
            .position(|i| i.codel() == Some(k) && i.running().is_none())
            .ok_or_else(|| {
                format!(
                    "`{}` is not ready to run `{}`: {}",
                    self.name(s),
                    self.codel_name(k),
                    self.state.describe(self.c)
                )
            })?;
        let my_thread = self.c.services[s].thread.map(|t| t.id);
        for (t, ts) in self.c.services.iter() {
            for running in self.state.of(t).iter().filter_map(Instance::running) {
                if ts.thread.map(|x| x.id) == my_thread {
                    return Err(format!(
                        "thread `{thread}` is busy running `{}::{}`: a thread runs one codel at a time",
                        ts.name.name,
                        self.codel_name(running)
                    ));
                }
                if self.c.conflicts(k, running) {
                    return Err(format!(
                        "`{}` conflicts with `{}::{}`, running on another thread: conflicting codels never run at the same time",
                        self.codel_name(k),
                        ts.name.name,
                        self.codel_name(running)
                    ));
                }
            }
        }
        if let Some(r) = self.request.as_ref().filter(|r| r.in_control_codel(self.c)) {
            let control = self.c.services[r.service].control;
            if control.is_some_and(|ctl| self.c.conflicts(k, ctl)) {
                return Err(format!(
                    "`{}` conflicts with the control codel of `{}`, running on the control thread: conflicting codels never run at the same time",
                    self.codel_name(k),
                    self.name(r.service)
                ));
            }
        }
        match &mut self.state.instances[s.0 as usize][pos].phase {
            Phase::Active { running, .. } | Phase::Stopping { running, .. } => *running = true,
            Phase::Pending { .. } => {}
        }
        Ok(())
    }

    fn codel_end(&mut self, step: &TraceStep) -> StepResult {
        self.settled()?;
        let s = self.service_of(step)?;
        self.check_thread(step, self.thread_name(s))?;
        let Some(k) = self.codel_of(s, step)? else {
            return Err("the step names no codel".to_owned());
        };
        let pos = self.state.instances[s.0 as usize]
            .iter()
            .position(|i| i.running() == Some(k))
            .ok_or_else(|| {
                format!(
                    "`{}` is not running `{}`: {}",
                    self.name(s),
                    self.codel_name(k),
                    self.state.describe(self.c)
                )
            })?;
        let codel = &self.c.codels[k];
        let outcome = match step.outcome.as_deref() {
            None => None,
            Some(o) => Some(self.outcome_named(s, k, o)?),
        };
        let inst = self.state.instances[s.0 as usize][pos].clone();
        let interrupted_reply = if inst.by_watchdog {
            "TIMEOUT"
        } else {
            "INTERRUPTED"
        };
        let report = |r: usize| {
            self.c.services[s]
                .reports
                .get(r)
                .map_or_else(String::new, |r| r.name.clone())
        };
        // Where the instance goes: a new phase, or an ending (reply, success).
        let next: Result<Phase, (String, bool)> = match inst.phase {
            Phase::Active {
                interrupted: true, ..
            } => match codel.on_inter {
                Some(x) => Ok(Phase::Stopping {
                    codel: x.id,
                    running: false,
                }),
                None => Err((interrupted_reply.to_owned(), false)),
            },
            Phase::Active { .. } => match outcome {
                None => {
                    return Err(format!(
                        "`{}` was not interrupted: the step must give its outcome",
                        self.codel_name(k)
                    ));
                }
                Some(Outcome::Codel(x)) => Ok(Phase::Active {
                    codel: x,
                    running: false,
                    last_ran: Some(k),
                    interrupted: false,
                }),
                Some(Outcome::End) => Err(("end".to_owned(), true)),
                Some(Outcome::Report(r)) => Err((report(r), false)),
            },
            Phase::Stopping { .. } => match outcome {
                None => {
                    return Err(format!(
                        "stopping services follow the `next` of their codels: the step must give the outcome of `{}`",
                        self.codel_name(k)
                    ));
                }
                Some(Outcome::Codel(x)) => Ok(Phase::Stopping {
                    codel: x,
                    running: false,
                }),
                Some(Outcome::End) => Err((interrupted_reply.to_owned(), false)),
                Some(Outcome::Report(r)) => Err((report(r), false)),
            },
            Phase::Pending { .. } => return Err("a pending instance runs no codel".to_owned()),
        };
        match next {
            Ok(phase) => self.state.instances[s.0 as usize][pos].phase = phase,
            Err((reply, success)) => self.end(s, pos, reply, success),
        }
        Ok(())
    }

    /// The outcome `o` of codel `k`, which must be in its `next`.
    fn outcome_named(&self, s: ServiceId, k: CodelId, o: &str) -> Result<Outcome, String> {
        let outcomes = self.c.codels[k].outcomes();
        let found = outcomes.iter().copied().find(|&x| match x {
            Outcome::End => o == "end",
            Outcome::Codel(x) => self.codel_name(x) == o,
            Outcome::Report(r) => self.c.services[s]
                .reports
                .get(r)
                .is_some_and(|r| r.name == o),
        });
        found.ok_or_else(|| {
            let names: Vec<String> = outcomes
                .iter()
                .map(|&x| match x {
                    Outcome::End => "`end`".to_owned(),
                    Outcome::Codel(x) => format!("`{}`", self.codel_name(x)),
                    Outcome::Report(r) => format!(
                        "`{}`",
                        self.c.services[s]
                            .reports
                            .get(r)
                            .map_or("?", |r| r.name.as_str())
                    ),
                })
                .collect();
            format!(
                "`{o}` is not an outcome of `{}` (its `next` is {})",
                self.codel_name(k),
                names.join(", ")
            )
        })
    }

    /// The instance at `pos` of `s` ends with `reply`.
    fn end(&mut self, s: ServiceId, pos: usize, reply: String, success: bool) {
        self.state.instances[s.0 as usize].remove(pos);
        self.replies.push_back((s, reply));
        if success && !self.state.init_done && self.c.init_service() == Some(s) {
            self.state.init_done = true;
            self.initialised();
        }
    }

    fn reply(&mut self, step: &TraceStep) -> StepResult {
        let s = self.service_of(step)?;
        let Some((owed, value)) = self.replies.front().cloned() else {
            return Err(format!(
                "no instance of `{}` has just ended: a final reply comes exactly once, when its instance ends",
                self.name(s)
            ));
        };
        if owed != s {
            return Err(format!(
                "`{}` has ended and must reply first (with `{value}`)",
                self.name(owed)
            ));
        }
        match step.outcome.as_deref() {
            None => {
                return Err(format!(
                    "a final reply must give its value (here `{value}`); none is given"
                ));
            }
            Some(v) if v != value => {
                return Err(format!(
                    "`{}` must reply `{value}` (how its instance ended), not `{v}`",
                    self.name(s)
                ));
            }
            Some(_) => {}
        }
        self.replies.pop_front();
        Ok(())
    }
}

impl ReplayEnd {
    /// Checks that the end of the trace shows `claim`.
    pub fn exhibits(&self, c: &Component, claim: Claim<'_>) -> Result<(), ReplayError> {
        let fail = |why: String| ReplayError {
            step: self.violation_step,
            what: "violation".to_owned(),
            why,
        };
        let service = |name: &str| {
            c.service_named(name)
                .ok_or_else(|| fail(format!("the component has no service `{name}`")))
        };
        match claim {
            Claim::Deadlock(names) => {
                let set = names
                    .iter()
                    .map(|n| service(n))
                    .collect::<Result<Vec<_>, _>>()?;
                self.deadlock(c, &set).map_err(fail)
            }
            Claim::Starvation { waiter, blocker } => {
                let (w, b) = (service(waiter)?, service(blocker)?);
                self.starvation(c, w, b).map_err(fail)
            }
            Claim::UnboundedInterrupt(name) => {
                let s = service(name)?;
                self.unbounded(c, s).map_err(fail)
            }
            Claim::DeadService(name) => {
                let s = service(name)?;
                self.dead(c, s).map_err(fail)
            }
        }
    }

    fn deadlock(&self, c: &Component, set: &[ServiceId]) -> Result<(), String> {
        if set.len() < 2 {
            return Err("a circular wait needs at least two services".to_owned());
        }
        let name = |s: ServiceId| c.services[s].name.name.as_str();
        for &s in set {
            if self.state.pending(s).is_none() {
                return Err(format!(
                    "`{}` has no pending instance: {}",
                    name(s),
                    self.state.describe(c)
                ));
            }
            if c.services[s].max_time.is_some() {
                return Err(format!(
                    "`{}` has a max-time: its watchdog ends the pending instance, no deadlock",
                    name(s)
                ));
            }
        }
        // `s` waits for `t`: `t` is in the set, pending, and delays `s`.
        let waits = |s: ServiceId, t: ServiceId| {
            s != t
                && self.state.pending(t).is_some()
                && c.services[t].delays.iter().any(|r| r.id == s)
        };
        for &s in set {
            let mut seen = BTreeSet::from([s]);
            let mut stack = vec![s];
            while let Some(x) = stack.pop() {
                for &t in set {
                    if waits(x, t) && seen.insert(t) {
                        stack.push(t);
                    }
                }
            }
            if let Some(&t) = set.iter().find(|t| !seen.contains(t)) {
                return Err(format!(
                    "the pending instances do not wait on each other: `{}` does not wait, through `delays` of pending instances, for `{}`",
                    name(s),
                    name(t)
                ));
            }
        }
        Ok(())
    }

    fn blocked_by(
        c: &Component,
        state: &State,
        w: ServiceId,
        b: ServiceId,
    ) -> Result<InstanceId, String> {
        let name = |s: ServiceId| c.services[s].name.name.as_str();
        let Some(Instance {
            phase: Phase::Pending { waits_for },
            ..
        }) = state.pending(w)
        else {
            return Err(format!(
                "`{}` is not pending: {}",
                name(w),
                state.describe(c)
            ));
        };
        let Some(blocker) = state.started(b) else {
            return Err(format!(
                "`{}` has no started instance: {}",
                name(b),
                state.describe(c)
            ));
        };
        let delays = b != w && c.services[b].delays.iter().any(|r| r.id == w);
        if !delays && !waits_for.contains(&blocker.id) {
            return Err(format!(
                "`{}`'s pending instance is not blocked by `{}`: it neither delays it nor is an interrupted instance it waits for",
                name(w),
                name(b)
            ));
        }
        Ok(blocker.id)
    }

    fn starvation(&self, c: &Component, w: ServiceId, b: ServiceId) -> Result<(), String> {
        let name = |s: ServiceId| c.services[s].name.name.as_str();
        if c.services[w].max_time.is_some() {
            return Err(format!(
                "`{}` has a max-time: its watchdog ends the wait, it does not starve",
                name(w)
            ));
        }
        if self.loop_states.is_empty() {
            return Err(
                "a starvation trace must end with a loop that repeats forever (no loop_start)"
                    .to_owned(),
            );
        }
        let mut ids = BTreeSet::new();
        let mut waiter_ids = BTreeSet::new();
        for st in self.loop_states.iter().chain([&self.state]) {
            ids.insert(Self::blocked_by(c, st, w, b)?);
            waiter_ids.extend(st.pending(w).map(|i| i.id));
        }
        if ids.len() != 1 || waiter_ids.len() != 1 {
            return Err(
                "the loop does not keep the same instances: the blocker or the waiter changes"
                    .to_owned(),
            );
        }
        let blocker_stopping = self.loop_states[0]
            .started(b)
            .is_some_and(Instance::is_interrupted);
        if c.services[b].max_time.is_some() && !blocker_stopping {
            return Err(format!(
                "`{}` has a max-time: its watchdog would end it",
                name(b)
            ));
        }
        if !self
            .loop_steps
            .iter()
            .any(|&(_, e, s)| e == Event::CodelEnd && s == Some(b))
        {
            return Err(format!("the loop runs no codel of `{}`", name(b)));
        }
        Ok(())
    }

    fn unbounded(&self, c: &Component, s: ServiceId) -> Result<(), String> {
        let name = c.services[s].name.name.as_str();
        if self.loop_states.is_empty() {
            return Err("an unbounded-interrupt trace must end with a loop that repeats forever (no loop_start)".to_owned());
        }
        let mut ids = BTreeSet::new();
        for st in self.loop_states.iter().chain([&self.state]) {
            match st.started(s) {
                Some(
                    i @ Instance {
                        phase: Phase::Stopping { .. },
                        ..
                    },
                ) => {
                    ids.insert(i.id);
                }
                _ => {
                    return Err(format!(
                        "`{name}` is not stopping at every step of the loop: {}",
                        st.describe(c)
                    ));
                }
            }
        }
        if ids.len() != 1 {
            return Err(format!(
                "the loop does not keep the same instance of `{name}`"
            ));
        }
        if !self
            .loop_steps
            .iter()
            .any(|&(_, e, x)| e == Event::CodelEnd && x == Some(s))
        {
            return Err(format!("the loop runs no codel of `{name}`"));
        }
        Ok(())
    }

    fn dead(&self, c: &Component, s: ServiceId) -> Result<(), String> {
        let name = c.services[s].name.name.as_str();
        if self.started.contains(&s) {
            return Err(format!("`{name}` starts in this trace"));
        }
        match self.fates.get(&s) {
            None => Err(format!("the trace never requests `{name}`")),
            Some(Fate::Rejected(_)) => Ok(()),
            Some(Fate::Acknowledged) => {
                if self.state.pending(s).is_none() {
                    return Err(format!(
                        "`{name}` was acknowledged but is no longer pending: {}",
                        self.state.describe(c)
                    ));
                }
                Ok(())
            }
        }
    }
}
