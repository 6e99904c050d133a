//! Runs the explorations (pre-init phase, then each cluster) and reads the
//! behavioural properties off the reachable states, keeping for each
//! violation the first (hence shortest) state that shows it and a trace
//! replayed in the whole component.

use std::collections::{BTreeMap, BTreeSet};
use std::time::Duration;

use genom_model::behaviour::{Behaviour, Effect, IDLE, PosId};
use genom_model::component::{CodelId, Component, ServiceId};
use genom_model::trace::{Event, Trace, TraceStep};

use super::explore::{Limits, Stop, explore};
use super::store::StateId;
use super::system::{Action, Config, System};

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
    /// Bytes per stored state (largest exploration).
    pub bytes_per_state: f64,
    /// For each service, the path to the first state where it is pending.
    pending_paths: BTreeMap<ServiceId, Vec<Action>>,
}

/// Witnesses found in one exploration, by state id.
#[derive(Default)]
struct Found {
    reached: BTreeSet<CodelId>,
    started: BTreeSet<ServiceId>,
    deadlocks: BTreeMap<Vec<ServiceId>, StateId>,
    starvations: BTreeMap<(ServiceId, ServiceId), (StateId, bool)>,
    unbounded: BTreeMap<ServiceId, StateId>,
    pending: BTreeMap<ServiceId, StateId>,
    init_success: Option<StateId>,
}

/// Explores the component and gathers every behavioural fact.
pub fn analyse(c: &Component, limits: Limits) -> Analysis {
    let b = Behaviour::new(c);
    let all: Vec<ServiceId> = c.services.ids().collect();
    let global = System::new(c, &b, &all, false);
    let mut out = Analysis::default();
    let mut budget = limits;
    let (prefix, post_init) = match c.init_service() {
        Some(init) => pre_init(c, &b, init, &global, &mut budget, &mut out),
        None => (Vec::new(), Some(true)),
    };
    match post_init {
        Some(true) => {
            for cluster in clusters(c) {
                explore_cluster(c, &b, &cluster, &prefix, &global, &mut budget, &mut out);
            }
        }
        Some(false) => {}
        None => out.unproven.extend(all.iter().copied()),
    }
    dead_services(c, &global, &prefix, post_init, &mut out);
    out
}

/// Explores the init service alone until it completes. Returns the path to
/// its first success and whether it can succeed (`None`: unknown).
fn pre_init(
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
    account(
        out,
        budget,
        e.store.len(),
        e.transitions,
        e.elapsed,
        e.store.bytes_per_state(),
        e.stopped,
    );
    let prefix = found
        .init_success
        .map(|id| e.store.path(id))
        .unwrap_or_default();
    let path = |id: StateId| e.store.path(id);
    collect(global, &found, &[], &path, out);
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

fn explore_cluster(
    c: &Component,
    b: &Behaviour,
    cluster: &[ServiceId],
    prefix: &[Action],
    global: &System<'_>,
    budget: &mut Limits,
    out: &mut Analysis,
) {
    let sys = System::new(c, b, cluster, false);
    if sys.too_many_stops() {
        out.unproven.extend(cluster.iter().copied());
        out.stopped.get_or_insert(Stop::States);
        return;
    }
    let mut found = Found::default();
    let e = explore(&sys, *budget, |id, cfg| visit(&sys, id, cfg, &mut found));
    account(
        out,
        budget,
        e.store.len(),
        e.transitions,
        e.elapsed,
        e.store.bytes_per_state(),
        e.stopped,
    );
    if e.stopped.is_some() {
        out.unproven.extend(cluster.iter().copied());
    }
    let path = |id: StateId| e.store.path(id);
    collect(global, &found, prefix, &path, out);
}

fn account(
    out: &mut Analysis,
    budget: &mut Limits,
    states: usize,
    transitions: u64,
    elapsed: Duration,
    bps: f64,
    stopped: Option<Stop>,
) {
    out.states += states as u64;
    out.transitions += transitions;
    out.elapsed += elapsed;
    out.bytes_per_state = out.bytes_per_state.max(bps);
    budget.max_states = budget.max_states.saturating_sub(states).max(1);
    if stopped.is_some() {
        out.stopped = out.stopped.or(stopped);
    }
}

/// Reads the properties of one new state.
fn visit(sys: &System<'_>, id: StateId, cfg: &Config, found: &mut Found) {
    let c = sys.component();
    if cfg.init_done && found.init_success.is_none() && c.init_service().is_some() {
        found.init_success = Some(id);
    }
    let n = cfg.main.len();
    for i in 0..n {
        let s = sys.service(i);
        let m = sys.machine_of(i);
        let pos = sys.position(cfg, i);
        if let Some(codel) = pos.codel().filter(|_| pos.is_running()) {
            found.reached.insert(codel);
        }
        if cfg.main[i] != IDLE {
            found.started.insert(s);
        }
        if sys.request_enabled(cfg, i) {
            if let Some(k) = c.services[s].control {
                found.reached.insert(k);
            }
            if m.start.is_none() {
                found.started.insert(s);
            }
        }
        if m.stop_loops[usize::from(cfg.main[i])] {
            found.unbounded.entry(s).or_insert(id);
        }
        if cfg.pending[i].is_some() {
            found.pending.entry(s).or_insert(id);
            starving(sys, id, cfg, i, found);
        }
    }
    if cfg.pending.iter().filter(|p| p.is_some()).count() >= 2 {
        if let Some(cycle) = pending_cycle(sys, cfg) {
            found.deadlocks.entry(cycle).or_insert(id);
        }
    }
}

fn starving(sys: &System<'_>, id: StateId, cfg: &Config, i: usize, found: &mut Found) {
    if sys.machine_of(i).watchdog {
        return;
    }
    for (t, via_delays) in sys.blockers(cfg, i) {
        let main = usize::from(cfg.main[t]);
        if cfg.main[t] != IDLE && sys.machine_of(t).may_never_end[main] {
            found
                .starvations
                .entry((sys.service(i), sys.service(t)))
                .or_insert((id, via_delays));
        }
    }
}

/// Services of a cycle of pending instances blocking each other through
/// `delays`, none of which a watchdog can end.
fn pending_cycle(sys: &System<'_>, cfg: &Config) -> Option<Vec<ServiceId>> {
    let n = cfg.main.len();
    let node = |i: usize| cfg.pending[i].is_some() && !sys.machine_of(i).watchdog;
    let edges: Vec<Vec<usize>> = (0..n)
        .map(|i| {
            if !node(i) {
                return Vec::new();
            }
            sys.blockers(cfg, i)
                .into_iter()
                .filter(|&(t, d)| d && node(t))
                .map(|(t, _)| t)
                .collect()
        })
        .collect();
    let reach = |from: usize| {
        let mut seen = vec![false; n];
        let mut stack = edges[from].clone();
        while let Some(x) = stack.pop() {
            if !std::mem::replace(&mut seen[x], true) {
                stack.extend(edges[x].iter().copied());
            }
        }
        seen
    };
    let closure: Vec<Vec<bool>> = (0..n).map(reach).collect();
    let on_cycle: Vec<usize> = (0..n).filter(|&i| closure[i][i]).collect();
    let first = *on_cycle.first()?;
    let mut cycle: Vec<ServiceId> = on_cycle
        .iter()
        .filter(|&&j| closure[first][j] && closure[j][first])
        .map(|&j| sys.service(j))
        .collect();
    cycle.sort();
    Some(cycle)
}

/// Turns the witnesses of one exploration into traces.
fn collect(
    global: &System<'_>,
    found: &Found,
    prefix: &[Action],
    path: &dyn Fn(StateId) -> Vec<Action>,
    out: &mut Analysis,
) {
    let c = global.component();
    out.reached.extend(found.reached.iter().copied());
    out.started.extend(found.started.iter().copied());
    let full = |id: StateId| prefix.iter().copied().chain(path(id)).collect::<Vec<_>>();
    for (services, &id) in &found.deadlocks {
        let names = names(c, services);
        let text = format!("deadlock: {names} are pending and wait on each other forever");
        let trace = replay(global, &full(id), None, violation(text));
        out.deadlocks.push(Deadlock {
            services: services.clone(),
            trace,
        });
    }
    for (&(waiter, blocker), &(id, via_delays)) in &found.starvations {
        let (w, b) = (
            &c.services[waiter].name.name,
            &c.services[blocker].name.name,
        );
        let text = format!("`{w}` waits for `{b}`, whose instance may never end");
        let trace = replay(global, &full(id), Some(blocker), violation(text));
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
        let trace = replay(global, &full(id), Some(service), violation(text));
        out.unbounded.push(Unbounded { service, trace });
    }
    for (&s, &id) in &found.pending {
        out.pending_paths.entry(s).or_insert_with(|| full(id));
    }
}

fn violation(text: String) -> TraceStep {
    TraceStep::new(Event::Violation, text)
}

/// "`a`", "`a` and `b`", "`a`, `b` and `c`".
pub(crate) fn names(c: &Component, services: &[ServiceId]) -> String {
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

/// Replays `path` in the whole component from its start, recording every
/// event; with `looping`, appends that service's codel loop as the cycle
/// that may repeat forever.
pub(crate) fn replay(
    global: &System<'_>,
    path: &[Action],
    looping: Option<ServiceId>,
    last: TraceStep,
) -> Trace {
    let mut steps = vec![TraceStep::new(
        Event::ComponentStart,
        "the component starts",
    )];
    let mut cfg = global.initial(false, &mut Some(&mut steps));
    for &a in path {
        match global.apply(&cfg, a, &mut Some(&mut steps)) {
            Some(next) => cfg = next,
            None => break,
        }
    }
    let mut loop_start = None;
    if let Some(s) = looping.and_then(|s| global.member_index(s).map(|i| (s, i))) {
        let (before, cycle) = local_loop(global, &cfg, s.1);
        for a in before {
            if let Some(next) = global.apply(&cfg, a, &mut Some(&mut steps)) {
                cfg = next;
            }
        }
        let at = steps.len();
        let mut ok = !cycle.is_empty();
        for a in cycle {
            match global.apply(&cfg, a, &mut Some(&mut steps)) {
                Some(next) => cfg = next,
                None => ok = false,
            }
        }
        if ok {
            loop_start = Some(at);
        }
    }
    steps.push(last);
    Trace { steps, loop_start }
}

/// A path of codel steps of member `i` from its position to a position on a
/// cycle, and the cycle itself (empty when there is none).
fn local_loop(sys: &System<'_>, cfg: &Config, i: usize) -> (Vec<Action>, Vec<Action>) {
    let start = cfg.main[i];
    let mut seen = vec![start];
    let mut k = 0;
    while k < seen.len() {
        let p = seen[k];
        k += 1;
        if let Some(cycle) = local_path(sys, i, p, p) {
            let before = local_path(sys, i, start, p)
                .filter(|_| p != start)
                .unwrap_or_default();
            return (before, cycle);
        }
        for (_, q) in local_steps(sys, i, p) {
            if !seen.contains(&q) {
                seen.push(q);
            }
        }
    }
    (Vec::new(), Vec::new())
}

/// The codel steps of member `i` from position `p`.
fn local_steps(sys: &System<'_>, i: usize, p: PosId) -> Vec<(Action, PosId)> {
    let m = sys.machine_of(i);
    let s = sys.service(i);
    let mut v = Vec::new();
    if let Some(q) = m.begin[usize::from(p)] {
        v.push((Action::Begin(s), q));
    }
    for (k, f) in m.finish[usize::from(p)].iter().enumerate() {
        if let (Effect::Goto(q), Ok(k)) = (f.effect, u8::try_from(k)) {
            v.push((Action::Finish(s, k), q));
        }
    }
    v
}

/// The shortest non-empty path of codel steps from `from` to `to`.
fn local_path(sys: &System<'_>, i: usize, from: PosId, to: PosId) -> Option<Vec<Action>> {
    let mut prev: BTreeMap<PosId, (PosId, Action)> = BTreeMap::new();
    let mut queue = std::collections::VecDeque::from([from]);
    let mut visited = BTreeSet::from([from]);
    while let Some(p) = queue.pop_front() {
        for (a, q) in local_steps(sys, i, p) {
            if q == to {
                let mut acts = vec![a];
                let mut cur = p;
                while cur != from {
                    let &(back, act) = prev.get(&cur)?;
                    acts.push(act);
                    cur = back;
                }
                acts.reverse();
                return Some(acts);
            }
            if visited.insert(q) {
                prev.insert(q, (p, a));
                queue.push_back(q);
            }
        }
    }
    None
}

/// Services that never start, when the explorations that could start them
/// finished.
fn dead_services(
    c: &Component,
    global: &System<'_>,
    prefix: &[Action],
    post_init: Option<bool>,
    out: &mut Analysis,
) {
    let pending = std::mem::take(&mut out.pending_paths);
    for s in c.services.ids() {
        if out.started.contains(&s) || out.unproven.contains(&s) || post_init.is_none() {
            continue;
        }
        let name = &c.services[s].name.name;
        let (reason, trace) = if let Some(path) = pending.get(&s) {
            let reason = format!(
                "`{name}` is acknowledged but never starts: it is always delayed or waiting"
            );
            (
                reason.clone(),
                replay(global, path, None, violation(reason)),
            )
        } else {
            let (code, reason) = reject_reason(c, global, prefix, s, post_init == Some(true));
            let mut trace = replay(
                global,
                prefix,
                None,
                violation(format!("`{name}` never starts")),
            );
            let at = trace.steps.len().saturating_sub(1);
            let span = Some(c.services[s].name.span);
            let mut req = TraceStep::new(Event::Request, format!("a client requests `{name}`"));
            (req.service, req.span, req.thread) = (Some(name.clone()), span, Some("control".to_owned()));
            let mut rej =
                TraceStep::new(Event::Reject, format!("the request is rejected: {reason}"));
            (rej.service, rej.span, rej.outcome) = (Some(name.clone()), span, code.map(str::to_owned));
            rej.thread = Some("control".to_owned());
            trace.steps.splice(at..at, [req, rej]);
            (reason, trace)
        };
        out.dead.push(Blocked {
            service: s,
            reason,
            trace,
        });
    }
}

/// Why a request for `s` is rejected right after initialisation.
/// Returns the reject reason (the reply) and a sentence.
fn reject_reason(
    c: &Component,
    global: &System<'_>,
    prefix: &[Action],
    s: ServiceId,
    initialised: bool,
) -> (Option<&'static str>, String) {
    if !initialised {
        let init = c.init_service().map_or("init", |i| c.services[i].name.name.as_str());
        let text = format!("NOT_INITIALIZED, because `{init}` can never complete successfully");
        return (Some("NOT_INITIALIZED"), text);
    }
    let mut cfg = global.initial(false, &mut None);
    for &a in prefix {
        if let Some(next) = global.apply(&cfg, a, &mut None) {
            cfg = next;
        }
    }
    let forbidder = c.services.iter().find(|&(t, ts)| {
        t != s
            && ts.forbids.iter().any(|r| r.id == s)
            && global
                .member_index(t)
                .is_some_and(|j| cfg.main[j] != IDLE || cfg.pending[j].is_some())
    });
    match forbidder {
        Some((_, t)) => (Some("FORBIDDEN"), format!("FORBIDDEN by `{}`, which runs forever", t.name.name)),
        None => (None, "every request is rejected".to_owned()),
    }
}

/// The clusters: connected components of the `stops`/`delays`/`forbids`
/// relation, each sorted, in order of their first service.
pub fn clusters(c: &Component) -> Vec<Vec<ServiceId>> {
    let n = c.services.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(parent: &mut [usize], x: usize) -> usize {
        let mut r = x;
        while parent[r] != r {
            r = parent[r];
        }
        let mut y = x;
        while parent[y] != r {
            let next = parent[y];
            parent[y] = r;
            y = next;
        }
        r
    }
    for (s, svc) in c.services.iter() {
        for r in svc.stops.iter().chain(&svc.delays).chain(&svc.forbids) {
            let (a, b) = (
                find(&mut parent, s.0 as usize),
                find(&mut parent, r.id.0 as usize),
            );
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut groups: BTreeMap<usize, Vec<ServiceId>> = BTreeMap::new();
    for s in c.services.ids() {
        let root = find(&mut parent, s.0 as usize);
        groups.entry(root).or_default().push(s);
    }
    groups.into_values().collect()
}
