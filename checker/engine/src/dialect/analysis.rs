//! Runs the explorations (pre-init phase, then each cluster) and reads the
//! behavioural properties off the reachable states, keeping for each
//! violation the first (hence shortest) state that shows it and a trace
//! replayed in the whole component.

use std::collections::{BTreeMap, BTreeSet};
use std::time::Duration;

use genom_model::behaviour::Behaviour;
use genom_model::component::{CodelId, Component, ServiceId};
use genom_model::stats::Method as Decider;
use genom_model::trace::{Event, Trace, TraceStep};

pub use super::clusters::clusters;
use super::compose::{self, Composed, Env, Step};
use super::system::{Action, Config, System};
use super::witness::replay;
use crate::kernel::explore::{Exploration, Limits, Stop, explore};
use crate::kernel::store::{Footprint, StateId, Subsumes};

mod visit;
pub(crate) use visit::{Found, visit};

/// Pending instances waiting on each other forever.
#[derive(Debug, Clone)]
pub struct Deadlock {
    /// The services of the cycle, sorted.
    pub services: Vec<ServiceId>,
    /// How to get there.
    pub trace: Trace,
}

/// A pending instance waiting on an instance that may never end.
#[derive(Debug, Clone)]
pub struct Starvation {
    /// The pending service.
    pub waiter: ServiceId,
    /// The service whose instance may never end.
    pub blocker: ServiceId,
    /// Blocked through `delays` (else waiting for an interrupted instance).
    pub via_delays: bool,
    /// How to get there, ending with the loop that may repeat forever.
    pub trace: Trace,
}

/// An interrupted instance whose inter codels may loop forever.
#[derive(Debug, Clone)]
pub struct Unbounded {
    /// The service.
    pub service: ServiceId,
    /// How to get there, ending with the loop.
    pub trace: Trace,
}

/// A service that never starts, with what stops it.
#[derive(Debug, Clone)]
pub struct Blocked {
    /// The service.
    pub service: ServiceId,
    /// Why, in words.
    pub reason: String,
    /// A trace showing it blocked or rejected.
    pub trace: Trace,
}

/// What decided one cluster (or the pre-init phase).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Decided {
    /// The services explored.
    pub services: Vec<ServiceId>,
    /// How.
    pub method: Decider,
    /// States stored (symbolic: configurations in the reachable set).
    pub states: u64,
    /// Whether that exploration finished.
    pub complete: bool,
}

/// Everything the explorations established.
#[derive(Debug, Clone, Default)]
pub struct Analysis {
    /// Codels some execution runs (control codels: some request reaches them).
    pub reached: BTreeSet<CodelId>,
    /// Services some execution starts (or, without start codel, accepts).
    pub started: BTreeSet<ServiceId>,
    /// Deadlocks found.
    pub deadlocks: Vec<Deadlock>,
    /// Starvations found.
    pub starvations: Vec<Starvation>,
    /// Unbounded interrupts found.
    pub unbounded: Vec<Unbounded>,
    /// Services proven never to start.
    pub dead: Vec<Blocked>,
    /// Services whose exploration did not finish: nothing negative is
    /// claimed about them.
    pub unproven: BTreeSet<ServiceId>,
    /// Why exploration stopped early, if it did.
    pub stopped: Option<Stop>,
    /// States stored over all explorations.
    pub states: u64,
    /// Transitions fired.
    pub transitions: u64,
    /// Time spent exploring.
    pub elapsed: Duration,
    /// Bytes per stored state of the largest exploration (a small one's
    /// fixed overhead per state says nothing about the store).
    pub footprint: Footprint,
    /// States expanded with a reduced set of actions (partial-order
    /// reduction).
    pub reduced: u64,
    /// Parts explored compositionally (clusters split by
    /// [`super::compose`]).
    pub parts: u64,
    /// What explored each cluster, in order.
    pub decided: Vec<Decided>,
    /// Services not started in their exploration, with why and a trace
    /// (they are dead unless another exploration starts them).
    dead_candidates: BTreeMap<ServiceId, Blocked>,
}

/// How to turn the witnesses of one exploration into traces: the
/// exploration's untimed system, the configuration of a state, and the trace
/// to a state (with, optionally, a service whose loop ends it, and the last
/// step).
pub(crate) struct Witnesses<'w> {
    pub(crate) sys: &'w System<'w>,
    pub(crate) config: &'w dyn Fn(StateId) -> Config,
    pub(crate) trace: &'w dyn Fn(StateId, Option<ServiceId>, TraceStep) -> Trace,
    /// Whether the exploration finished. A stopped one leaves its members
    /// unproven, so no dead-service candidate (and no costly trace) is
    /// gathered from it.
    pub(crate) complete: bool,
}

/// Explores the init service alone until it completes. Returns the path to
/// its first success and whether it can succeed (`None`: unknown).
pub(super) fn pre_init(
    c: &Component,
    b: &Behaviour,
    init: ServiceId,
    global: &System<'_>,
    budget: &mut Limits,
    out: &mut Analysis,
) -> (Vec<Action>, Option<bool>) {
    let sys = System::new(c, b, &[init], true);
    let mut found = Found::default();
    let e = explore(&sys, *budget, |id, cfg| visit(&sys, id, cfg, &mut found));
    out.account(budget, &e);
    out.decided.push(Decided {
        services: vec![init],
        method: Decider::Exhaustive,
        states: e.store.len() as u64,
        complete: e.stopped.is_none(),
    });
    let prefix = found
        .init_success
        .map(|id| e.store.path(id))
        .unwrap_or_default();
    let config = |id: StateId| e.store_config(&sys, id);
    let trace = |id: StateId, looping: Option<ServiceId>, last: TraceStep| {
        replay(global, &e.store.path(id), looping, last)
    };
    collect(
        &Witnesses {
            sys: &sys,
            config: &config,
            trace: &trace,
            complete: true,
        },
        &found,
        out,
    );
    let complete = e.stopped.is_none();
    if !complete {
        out.unproven.insert(init);
    }
    let post = match (found.init_success, complete) {
        (Some(_), _) => Some(true),
        (None, true) => Some(false),
        (None, false) => None,
    };
    (prefix, post)
}

pub(super) fn explore_cluster(
    sys: &System<'_>,
    prefix: &[Action],
    global: &System<'_>,
    budget: &mut Limits,
    out: &mut Analysis,
) {
    if sys.too_many_stops() {
        out.unproven.extend(sys.services());
        out.stopped.get_or_insert(Stop::States);
        return;
    }
    let mut found = Found::default();
    if let Some(probed) = sys.probe(*budget) {
        probed.reached.iter().for_each(|&k| found.reach(k));
        probed.started.iter().for_each(|&(i, s)| found.start(i, s));
        out.states += probed.states;
    }
    let e = explore(sys, *budget, |id, cfg| visit(sys, id, cfg, &mut found));
    out.account(budget, &e);
    if e.stopped.is_some() {
        out.unproven.extend(sys.services());
    }
    let config = |id: StateId| e.store_config(sys, id);
    let path = |id: StateId| e.store.path(id);
    collect_cluster(sys, (prefix, global), (&config, &path), &found, out);
}

/// A witness's configuration and its path from the cluster's initial one.
pub(crate) type WitnessFns<'f> = (
    &'f dyn Fn(StateId) -> Config,
    &'f dyn Fn(StateId) -> Vec<Action>,
);

/// [`collect`] for a cluster explored after initialisation: the witness
/// `id` is configuration `config(id)`, reached by `path(id)` after the
/// `prefix` to the end of initialisation; its trace is replayed in the
/// whole component `global`.
pub(crate) fn collect_cluster(
    sys: &System<'_>,
    (prefix, global): (&[Action], &System<'_>),
    (config, path): WitnessFns<'_>,
    found: &Found,
    out: &mut Analysis,
) {
    let trace = |id: StateId, looping: Option<ServiceId>, last: TraceStep| {
        let full: Vec<Action> = prefix.iter().copied().chain(path(id)).collect();
        replay(global, &full, looping, last)
    };
    collect(
        &Witnesses {
            sys,
            config,
            trace: &trace,
            complete: true,
        },
        found,
        out,
    );
}

/// The share of the remaining state budget a first, whole exploration of
/// a cluster with the partial-order reduction may use: it ends as soon as
/// every fact the cluster can show is found, which is often early; past
/// this share the cluster is explored part by part instead.
const WHOLE_FIRST_SHARE: usize = 4;

/// Explores the cluster whole with the partial-order reduction, within a
/// share of the budget; `true`, with the results in `out`, when it
/// finished (the states it stored are charged to the budget either way).
pub(super) fn first_try_whole(
    w: &Whole<'_>,
    cluster: &[ServiceId],
    budget: &mut Limits,
    out: &mut Analysis,
) -> bool {
    let sys = System::new(w.c, w.b, cluster, false).with_reduction();
    if sys.too_many_stops() {
        return false;
    }
    let mut share = Limits {
        max_states: (budget.max_states / WHOLE_FIRST_SHARE).max(1),
        ..*budget
    };
    let mut tmp = Analysis::default();
    explore_cluster(&sys, w.prefix, w.global, &mut share, &mut tmp);
    let spent = usize::try_from(tmp.states).unwrap_or(usize::MAX);
    budget.max_states = budget.max_states.saturating_sub(spent).max(1);
    if tmp.stopped.is_some() {
        return false;
    }
    out.absorb(tmp);
    true
}

/// What every exploration of a cluster shares.
pub(super) struct Whole<'w> {
    pub(super) c: &'w Component,
    pub(super) b: &'w Behaviour,
    /// The path to the end of initialisation.
    pub(super) prefix: &'w [Action],
    /// The whole component, to replay traces in.
    pub(super) global: &'w System<'w>,
}

/// Largest environment automaton kept between parts.
const MAX_ENV_STATES: usize = 4096;

/// Largest search for a concrete execution of one witness of a part.
const CONCRETE_MAX_STATES: usize = 1_000_000;

/// Explores a cluster part by part (see [`compose`]). Returns `false`, with
/// `out` untouched, when the cluster has one part, an interface is too wide,
/// an environment too large, or a part's witness cannot be made concrete:
/// the caller then explores the cluster whole.
pub(super) fn explore_parts(
    w: &Whole<'_>,
    cluster: &[ServiceId],
    budget: &mut Limits,
    out: &mut Analysis,
) -> bool {
    let plan = compose::Plan::new(w.c, cluster);
    if plan.parts.len() < 2 || !plan.fits() {
        return false;
    }
    let mut env = Env::empty();
    let mut tmp = Analysis::default();
    let mut local = *budget;
    for (k, part) in plan.parts.iter().enumerate() {
        let sys = System::with_inputs(w.c, w.b, part, &plan.inputs[k], false);
        // The last part's graph is not projected: it may stop once every
        // fact it can show is found.
        let sys = match plan.interface(k) {
            [] => sys.with_fact_tracking(),
            _ => sys,
        };
        if sys.too_many_stops() {
            return false;
        }
        let Some(model) = Composed::new(sys, &env) else {
            return false;
        };
        let cone = System::new(w.c, w.b, &plan.cone(k), false);
        let Some(e) = explore_part(w, &model, &cone, &mut local, &mut tmp) else {
            return false;
        };
        if e.stopped.is_some() {
            // A limit stopped it: what earlier parts established stands;
            // later parts, explored with its projection, would not be exact.
            tmp.unproven
                .extend(plan.parts[k..].iter().flatten().copied());
            break;
        }
        let next = match plan.interface(k) {
            [] => Env::empty(),
            later => match compose::project(&model, &e, later, MAX_ENV_STATES) {
                Some(next) => next,
                None => return false,
            },
        };
        drop(model);
        env = next;
    }
    tmp.parts += plan.parts.len() as u64;
    out.absorb(tmp);
    *budget = local;
    true
}

/// Explores one composed part and collects its witnesses, made concrete in
/// `cone` (the part and its upstream). `None` when a witness cannot be made
/// concrete.
fn explore_part(
    w: &Whole<'_>,
    model: &Composed<'_>,
    cone: &System<'_>,
    budget: &mut Limits,
    out: &mut Analysis,
) -> Option<Exploration<Step>> {
    let sys = &model.sys;
    let mut found = Found::default();
    let e = explore(model, *budget, |id, st| visit(sys, id, &st.0, &mut found));
    out.account(budget, &e);
    let failed = std::cell::Cell::new(false);
    // Making witnesses concrete is trace production, not exploration: it
    // has its own bound (past it, the cluster is explored whole).
    let cap = CONCRETE_MAX_STATES;
    let config = |id: StateId| e.store_config(model, id).0;
    let trace = |id: StateId, looping: Option<ServiceId>, last: TraceStep| match compose::concretize(
        model,
        cone,
        &e.store.path(id),
        cap,
    ) {
        Some(path) => {
            let full: Vec<Action> = w.prefix.iter().copied().chain(path).collect();
            replay(w.global, &full, looping, last)
        }
        None => {
            failed.set(true);
            Trace::default()
        }
    };
    collect(
        &Witnesses {
            sys,
            config: &config,
            trace: &trace,
            complete: true,
        },
        &found,
        out,
    );
    (!failed.get()).then_some(e)
}

impl Analysis {
    /// Adds everything `other` established (explorations of disjoint
    /// services).
    pub(super) fn absorb(&mut self, other: Analysis) {
        self.reached.extend(other.reached);
        self.started.extend(other.started);
        self.deadlocks.extend(other.deadlocks);
        self.starvations.extend(other.starvations);
        self.unbounded.extend(other.unbounded);
        self.dead.extend(other.dead);
        self.unproven.extend(other.unproven);
        self.stopped = self.stopped.or(other.stopped);
        self.states += other.states;
        self.transitions += other.transitions;
        self.elapsed += other.elapsed;
        self.footprint.join(other.footprint);
        self.reduced += other.reduced;
        self.parts += other.parts;
        self.decided.extend(other.decided);
        for (s, b) in other.dead_candidates {
            self.dead_candidates.entry(s).or_insert(b);
        }
    }

    /// Adds the figures of one exploration and charges its states to the
    /// remaining budget.
    pub(crate) fn account<A: Copy, Z: Subsumes>(
        &mut self,
        budget: &mut Limits,
        e: &Exploration<A, Z>,
    ) {
        let states = e.store.len();
        self.states += states as u64;
        self.transitions += e.transitions;
        self.elapsed += e.elapsed;
        self.reduced += e.reduced;
        self.footprint.add(&e.store);
        budget.max_states = budget.max_states.saturating_sub(states).max(1);
        if e.stopped.is_some() {
            self.stopped = self.stopped.or(e.stopped);
        }
    }
}

/// Turns the witnesses of one exploration into traces.
pub(crate) fn collect(w: &Witnesses<'_>, found: &Found, out: &mut Analysis) {
    let c = w.sys.component();
    out.reached.extend(found.reached.iter().copied());
    out.started.extend(found.started.iter().copied());
    for (services, &id) in &found.deadlocks {
        let text = format!(
            "deadlock: {} are pending and wait on each other forever",
            names(c, services)
        );
        let trace = (w.trace)(id, None, violation(text));
        out.deadlocks.push(Deadlock {
            services: services.clone(),
            trace,
        });
    }
    for (&(waiter, blocker), &(id, via_delays)) in &found.starvations {
        let (wn, bn) = (
            &c.services[waiter].name.name,
            &c.services[blocker].name.name,
        );
        let text = format!("`{wn}` waits for `{bn}`, whose instance may never end");
        let trace = (w.trace)(id, Some(blocker), violation(text));
        out.starvations.push(Starvation {
            waiter,
            blocker,
            via_delays,
            trace,
        });
    }
    for (&service, &id) in &found.unbounded {
        let text = format!(
            "`{}` is interrupted and its inter codels may loop forever",
            c.services[service].name.name
        );
        let trace = (w.trace)(id, Some(service), violation(text));
        out.unbounded.push(Unbounded { service, trace });
    }
    for s in w.sys.services().filter(|_| w.complete) {
        if !found.started.contains(&s) && !out.dead_candidates.contains_key(&s) {
            if let Some(blocked) = never_started(w, found, s) {
                out.dead_candidates.insert(s, blocked);
            }
        }
    }
}

/// Why `s` never starts in this exploration, with a trace: it stays
/// pending, or its requests are rejected once initialisation is done.
fn never_started(w: &Witnesses<'_>, found: &Found, s: ServiceId) -> Option<Blocked> {
    let c = w.sys.component();
    let name = &c.services[s].name.name;
    if let Some(&id) = found.pending.get(&s) {
        let reason =
            format!("`{name}` is acknowledged but never starts: it is always delayed or waiting");
        let trace = (w.trace)(id, None, violation(reason.clone()));
        return Some(Blocked {
            service: s,
            reason,
            trace,
        });
    }
    let at = found.init_success.or(found.root)?;
    let cfg = (w.config)(at);
    let (code, reason) = reject_reason(w.sys, &cfg, s);
    let mut trace = (w.trace)(at, None, violation(format!("`{name}` never starts")));
    splice_rejection(c, &mut trace, s, code, &reason);
    Some(Blocked {
        service: s,
        reason,
        trace,
    })
}

/// Inserts a request of `s` and its rejection before the last step.
fn splice_rejection(
    c: &Component,
    trace: &mut Trace,
    s: ServiceId,
    code: Option<&'static str>,
    reason: &str,
) {
    let name = &c.services[s].name.name;
    let at = trace.steps.len().saturating_sub(1);
    let time = trace.steps.get(at).and_then(|st| st.time_ns);
    let span = Some(c.services[s].name.span);
    let mut req = TraceStep::new(Event::Request, format!("a client requests `{name}`"));
    (req.service, req.span, req.thread, req.time_ns) =
        (Some(name.clone()), span, Some("control".to_owned()), time);
    let mut rej = TraceStep::new(Event::Reject, format!("the request is rejected: {reason}"));
    (rej.service, rej.span, rej.outcome, rej.time_ns) =
        (Some(name.clone()), span, code.map(str::to_owned), time);
    rej.thread = Some("control".to_owned());
    trace.steps.splice(at..at, [req, rej]);
}

fn violation(text: String) -> TraceStep {
    TraceStep::new(Event::Violation, text)
}

/// "`a`", "`a` and `b`", "`a`, `b` and `c`".
pub fn names(c: &Component, services: &[ServiceId]) -> String {
    let list: Vec<String> = services
        .iter()
        .map(|&s| format!("`{}`", c.services[s].name.name))
        .collect();
    match list.as_slice() {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// Services that never start, after timed explorations (each with the init
/// service): every candidate not started elsewhere and fully explored.
pub(crate) fn finish_dead(c: &Component, global: &System<'_>, out: &mut Analysis) {
    dead_services(c, global, Some(true), out);
}

/// Services that never start, when the explorations that could start them
/// finished. When initialisation can never complete, every other service is
/// dead: its requests are rejected with `NOT_INITIALIZED`.
pub(super) fn dead_services(
    c: &Component,
    global: &System<'_>,
    post_init: Option<bool>,
    out: &mut Analysis,
) {
    let mut candidates = std::mem::take(&mut out.dead_candidates);
    for s in c.services.ids() {
        if out.started.contains(&s) || out.unproven.contains(&s) || post_init.is_none() {
            continue;
        }
        let blocked = match candidates.remove(&s) {
            Some(b) => b,
            None => {
                let cfg = global.initial(false, &mut None);
                let (code, reason) = reject_reason(global, &cfg, s);
                let name = &c.services[s].name.name;
                let mut trace = replay(
                    global,
                    &[],
                    None,
                    violation(format!("`{name}` never starts")),
                );
                splice_rejection(c, &mut trace, s, code, &reason);
                Blocked {
                    service: s,
                    reason,
                    trace,
                }
            }
        };
        out.dead.push(blocked);
    }
}

/// Returns the reject reason (the reply) and a sentence, for a request of
/// `s` in `cfg` of `sys`.
pub(crate) fn reject_reason(
    sys: &System<'_>,
    cfg: &Config,
    s: ServiceId,
) -> (Option<&'static str>, String) {
    let c = sys.component();
    if !cfg.init_done {
        let init = c
            .init_service()
            .map_or("init", |i| c.services[i].name.name.as_str());
        let text = format!("NOT_INITIALIZED, because `{init}` can never complete successfully");
        return (Some("NOT_INITIALIZED"), text);
    }
    let forbidder = c.services.iter().find(|&(t, ts)| {
        t != s
            && ts.forbids.iter().any(|r| r.id == s)
            && sys
                .member_index(t)
                .is_some_and(|j| System::has_instance(cfg, j))
    });
    match forbidder {
        Some((_, t)) => (
            Some("FORBIDDEN"),
            format!("FORBIDDEN by `{}`, which runs forever", t.name.name),
        ),
        None => (None, "every request is rejected".to_owned()),
    }
}
