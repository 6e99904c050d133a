//! Explores a GenoM3 component under GenoM3's semantics and reads the
//! verdicts off the reachable states: which services are ever accepted,
//! which codels ever run, and which unpaused cycles (a task spinning
//! without `pause::` or `async`) are entered, each with its trace.

use std::collections::{BTreeMap, BTreeSet};

use genom_model::component::{Component, Idx, ServiceId};
use genom_model::trace::{Event, Trace, TraceStep};
use petgraph::algo::tarjan_scc;
use petgraph::graphmap::DiGraphMap;

use super::machine::{Fsm, Machine, Owner, Target};
use super::parts::parts;
use super::state::{G3State, Inst, Phase, Status};
use super::steps::{Engine, G3Action};
use super::trace::describe;
use crate::kernel;
use crate::kernel::explore::{Found, Limits, Model, Stop};
use crate::kernel::method::{Explored, Method};
use crate::kernel::store::{Footprint, StateId};

/// A cycle of unpaused transitions of one state machine, through no
/// `async` codel.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Cycle {
    /// Whose machine.
    pub owner: Owner,
    /// Its states, in the order a run goes round (first: the entry).
    pub states: Vec<u8>,
    /// Whether the task may leave the spinning states around it: some
    /// codel of its strongly connected part (of the unpaused graph without
    /// async states) may yield `ether`, `pause::`, or a state outside that
    /// part (an async one included).
    pub has_exit: bool,
}

/// A reachable unpaused cycle, with the trace that enters it and goes
/// round once.
#[derive(Debug, Clone)]
pub struct Livelock {
    /// The cycle, its first state the one the trace enters.
    pub cycle: Cycle,
    /// The trace (a lasso: `loop_start` opens the round).
    pub trace: Trace,
}

/// What the GenoM3 engine found.
#[derive(Debug, Clone, Default)]
pub struct G3Analysis {
    /// States stored.
    pub states: u64,
    /// Transitions fired.
    pub transitions: u64,
    /// Bytes per stored state, of the largest part.
    pub footprint: Footprint,
    /// Why exploration stopped early, if it did.
    pub stopped: Option<Stop>,
    /// Services some execution accepts (an activity: starts).
    pub started: BTreeSet<ServiceId>,
    /// Services some execution completes successfully (`after` counts
    /// them).
    pub completed: BTreeSet<ServiceId>,
    /// States whose codel some execution runs, per owner.
    pub reached: BTreeSet<(Owner, u8)>,
    /// Reachable unpaused cycles.
    pub livelocks: Vec<Livelock>,
    /// The boot: the steps of the permanent activities that lead to the
    /// first state where requests are handled.
    pub boot: Vec<G3Action>,
    /// What each part's exploration covered, in exploration order.
    pub parts: Vec<PartRecord>,
}

/// One part's exploration ([`super::parts`]): what it requested and how
/// far it went.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PartRecord {
    /// The services it requests, but the built-in ones every part has.
    pub services: Vec<ServiceId>,
    /// The tasks whose permanent activity it runs.
    pub tasks: Vec<usize>,
    /// States stored.
    pub states: u64,
    /// Whether it finished.
    pub complete: bool,
    /// Whether the symbolic sets explored it (`--engine symbolic`, or
    /// `auto` after an explicit exploration that stopped on a limit).
    pub symbolic: bool,
    /// An explicit exploration stopped by a limit, which the symbolic
    /// sets' record that follows finished (`auto`).
    pub superseded: bool,
}

/// Explores `c` (a GenoM3 component; `None` otherwise) with at most
/// `max_instances` instances of each activity, part by part
/// ([`super::parts`]).
pub fn analyse_genom3(c: &Component, max_instances: usize, limits: Limits) -> Option<G3Analysis> {
    Some(analyse_machine(&Machine::new(c, max_instances)?, limits))
}

/// [`analyse_genom3`] of a machine already read, each part explored
/// explicitly, or symbolically when the explicit exploration stopped on
/// its state or memory limit (`--engine auto`).
pub fn analyse_machine(m: &Machine<'_>, limits: Limits) -> G3Analysis {
    analyse_machine_by(m, limits, true, Method::Auto)
}

/// [`analyse_machine`], explicitly, with or without the early stop of
/// each part once every fact it can show is found ([`Targets`]; without,
/// for tests that compare, and for the bench that measures a whole
/// exploration's store).
pub fn analyse_machine_with(m: &Machine<'_>, limits: Limits, early: bool) -> G3Analysis {
    analyse_machine_by(m, limits, early, Method::Explicit)
}

/// [`analyse_machine_with`], each part explored by `method`.
pub fn analyse_machine_by(
    m: &Machine<'_>,
    limits: Limits,
    early: bool,
    method: Method,
) -> G3Analysis {
    let c = m.c;
    let whole = Engine::new(m.clone());
    let cycles = unpaused_cycles(&whole.m);
    let mut out = G3Analysis::default();
    let mut done = vec![0u64; c.services.len().div_ceil(64).max(1)];
    let mut boot: Vec<G3Action> = Vec::new();
    let mut footprint = Footprint::default();
    for part in parts(&whole.m) {
        let perms = part.perms;
        let engine = Engine::part(
            whole.m.clone(),
            part.acts.clone(),
            part.ctls.clone(),
            part.perms,
        );
        let look = Look {
            engine: &engine,
            part: &part,
            cycles: &cycles,
            early,
        };
        let run = look.explore(method, limits, &mut out, &mut done);
        for (w, d) in done.iter_mut().zip(engine.completions_seen()) {
            *w |= d;
        }
        if let Some(path) = run.boot {
            boot = path;
        }
        for (k, (tail, owner, state)) in run.entered {
            let mut path = if perms { Vec::new() } else { boot.clone() };
            path.extend(tail);
            let cycle = rotate(&cycles[k], state);
            out.livelocks.push(Livelock {
                trace: lasso(&whole, &path, owner, &cycle),
                cycle,
            });
        }
        let record = PartRecord {
            services: engine.m.requested(&part.acts, &part.ctls),
            tasks: (0..engine.m.tasks.len())
                .filter(|&t| perms && engine.m.tasks[t].perm.is_some())
                .collect(),
            states: run.states,
            complete: run.stopped.is_none(),
            symbolic: run.symbolic,
            superseded: false,
        };
        let (tried, tried_transitions) = run.attempt.unwrap_or_default();
        if let Some((states, _)) = run.attempt {
            out.parts.push(PartRecord {
                states,
                complete: false,
                symbolic: false,
                superseded: true,
                ..record.clone()
            });
        }
        out.parts.push(record);
        out.states += run.states + tried;
        out.transitions += run.transitions + tried_transitions;
        footprint.join(run.footprint);
        out.stopped = out.stopped.or(run.stopped);
        if out.stopped.is_some() {
            break;
        }
    }
    out.footprint = footprint;
    out.boot = boot;
    out.completed = c
        .services
        .ids()
        .filter(|s| done[s.index() / 64] >> (s.index() % 64) & 1 == 1)
        .collect();
    out.started.extend(out.completed.iter().copied());
    out.livelocks
        .sort_by(|a, b| (a.cycle.owner, &a.cycle.states).cmp(&(b.cycle.owner, &b.cycle.states)));
    out
}

/// One part to explore, and what its visits look for.
struct Look<'l, 'a> {
    engine: &'l Engine<'a>,
    part: &'l super::parts::Part,
    cycles: &'l [Cycle],
    early: bool,
}

/// One part's exploration and the paths to the states its facts were
/// seen in (found while the exploration was at hand: its store is freed
/// before a symbolic one starts).
struct PartRun {
    /// The path to the first state where requests are handled (the
    /// permanent activities' part).
    boot: Option<Vec<G3Action>>,
    /// Per unpaused cycle: the path to the first state it is entered in.
    entered: BTreeMap<usize, (Vec<G3Action>, Owner, u8)>,
    /// Why it stopped early, if it did.
    stopped: Option<Stop>,
    /// Whether the symbolic sets explored it.
    symbolic: bool,
    /// Bytes per state of its store (none for the sets).
    footprint: Footprint,
    /// Its time.
    elapsed: std::time::Duration,
    /// States and transitions of this exploration.
    states: u64,
    transitions: u64,
    /// The states and transitions of the explicit exploration the
    /// symbolic one finished after (`auto`): they count too.
    attempt: Option<(u64, u64)>,
}

impl Look<'_, '_> {
    /// Explores the part by `method`: `auto` explores symbolically again
    /// a part whose explicit exploration stopped on its state or memory
    /// limit, and keeps that when it finished. Facts seen by an unfinished
    /// exploration are facts: they stay in `out`.
    fn explore(
        &self,
        method: Method,
        limits: Limits,
        out: &mut G3Analysis,
        done: &mut [u64],
    ) -> PartRun {
        let symbolic = method == Method::Symbolic;
        let run = self.run(symbolic, limits, out, done);
        if method != Method::Auto || !kernel::method::falls_back(run.stopped) {
            return run;
        }
        let deadline = kernel::method::fallback_deadline(&limits, run.elapsed);
        let sets = Limits {
            deadline: Some(deadline),
            ..limits
        };
        let mut again = self.run(true, sets, out, done);
        if again.stopped.is_some() {
            return run;
        }
        again.attempt = Some((run.states, run.transitions));
        again
    }

    /// One exploration of the part, explicit or symbolic.
    fn run(
        &self,
        symbolic: bool,
        limits: Limits,
        out: &mut G3Analysis,
        done: &mut [u64],
    ) -> PartRun {
        let engine = self.engine;
        let mut entered: BTreeMap<usize, (StateId, Owner, u8)> = BTreeMap::new();
        let mut booted: Option<StateId> = None;
        let mut open = Targets::new(&engine.m, self.part, self.cycles);
        let explored = Explored::run(engine, symbolic, limits, |id, s: &G3State| {
            for (w, d) in done.iter_mut().zip(&s.done) {
                *w |= d;
            }
            if self.part.perms && booted.is_none() && s.phase == Phase::Run {
                booted = Some(id);
                open.boot = false;
            }
            for a in ready(s) {
                let act = &engine.m.activities[a];
                open.started(out, act.service);
                if let Some(st) = act.fsm.start {
                    open.reached(out, (Owner::Activity(a), st));
                }
            }
            for (owner, i) in running(s) {
                open.reached(out, (owner, i.state));
                if !may_run(s, owner) {
                    continue;
                }
                if let Owner::Activity(a) = owner {
                    open.started(out, engine.m.activities[a].service);
                }
                for (k, cy) in self.cycles.iter().enumerate() {
                    if cy.owner == owner && cy.states.contains(&i.state) {
                        entered.entry(k).or_insert((id, owner, i.state));
                        open.cycles.remove(&k);
                    }
                }
            }
            if self.early {
                open.found(engine)
            } else {
                Found::Open
            }
        });
        let mut footprint = Footprint::default();
        explored.add_footprint(&mut footprint);
        PartRun {
            boot: booted.map(|id| explored.path(engine, id)),
            entered: entered
                .into_iter()
                .map(|(k, (id, owner, state))| (k, (explored.path(engine, id), owner, state)))
                .collect(),
            stopped: explored.stopped(),
            symbolic: explored.is_symbolic(),
            footprint,
            elapsed: explored.elapsed(),
            states: explored.states(),
            transitions: explored.transitions(),
            attempt: None,
        }
    }
}

/// The facts one part can show at most, less those found so far: once none
/// is left, exploring further changes nothing the analysis reads (every
/// fact is a state or a step some exploration shows, and the first one
/// found, breadth-first, is the one reported), so the exploration stops and
/// counts as complete (the kernel's early stop, [`Found::All`]).
struct Targets {
    /// Activities' services never seen started.
    started: BTreeSet<ServiceId>,
    /// Codel states never seen running or about to run.
    reached: BTreeSet<(Owner, u8)>,
    /// Unpaused cycles never seen entered.
    cycles: BTreeSet<usize>,
    /// The boot (the permanent activities' part) not seen ended.
    boot: bool,
    /// The services whose completion was never seen, as bits.
    completions: Vec<u64>,
    /// Visits since every fact but the completions was found (these are
    /// compared every 256 visits).
    visits: u32,
}

impl Targets {
    /// Service `sid` seen started: kept in `out`, no longer awaited.
    fn started(&mut self, out: &mut G3Analysis, sid: ServiceId) {
        out.started.insert(sid);
        self.started.remove(&sid);
    }

    /// A codel state seen running or about to run: kept in `out`, no longer
    /// awaited.
    fn reached(&mut self, out: &mut G3Analysis, state: (Owner, u8)) {
        out.reached.insert(state);
        self.reached.remove(&state);
    }

    /// Every fact the part of `m` explores could show.
    fn new(m: &Machine<'_>, part: &super::parts::Part, cycles: &[Cycle]) -> Self {
        let mut owners: Vec<Owner> = (0..m.activities.len())
            .filter(|&a| part.acts[a])
            .map(Owner::Activity)
            .collect();
        if part.perms {
            owners.extend(
                (0..m.tasks.len())
                    .filter(|&t| m.tasks[t].perm.is_some())
                    .map(Owner::Task),
            );
        }
        let services = (0..m.activities.len())
            .filter(|&a| part.acts[a])
            .map(|a| m.activities[a].service)
            .chain(
                (0..m.controls.len())
                    .filter(|&k| part.ctls[k])
                    .map(|k| m.controls[k].service),
            );
        let mut completions = vec![0u64; m.c.services.len().div_ceil(64).max(1)];
        for sid in services {
            completions[sid.index() / 64] |= 1 << (sid.index() % 64);
        }
        Targets {
            started: owners
                .iter()
                .filter_map(|&o| match o {
                    Owner::Activity(a) => Some(m.activities[a].service),
                    Owner::Task(_) => None,
                })
                .collect(),
            reached: owners
                .iter()
                .flat_map(|&o| (0..m.fsm(o).states.len()).map(move |k| (o, k as u8)))
                .collect(),
            cycles: (0..cycles.len())
                .filter(|&k| owners.contains(&cycles[k].owner))
                .collect(),
            boot: part.perms,
            completions,
            visits: 0,
        }
    }

    /// Whether every fact has been found: the states' facts, then (every
    /// 256 visits, as they are read off the steps fired) the completions.
    fn found(&mut self, engine: &Engine<'_>) -> Found {
        if self.boot
            || !self.started.is_empty()
            || !self.reached.is_empty()
            || !self.cycles.is_empty()
        {
            return Found::Open;
        }
        self.visits += 1;
        if self.visits % 256 != 1 {
            return Found::Open;
        }
        let seen = engine.completions_seen();
        let all = self
            .completions
            .iter()
            .zip(&seen)
            .all(|(want, got)| want & !got == 0);
        if all { Found::All } else { Found::Open }
    }
}

/// Whether `owner` may run its codel in `s`: during the boot, a task's
/// permanent activity waits until the tasks before it started.
fn may_run(s: &G3State, owner: Owner) -> bool {
    match owner {
        Owner::Task(t) => s.phase != Phase::Boot || t <= usize::from(s.booted),
        Owner::Activity(_) => true,
    }
}

/// The activities with an instance ready to start in `s` (its start step,
/// which runs its `start` codel, is enabled).
fn ready(s: &G3State) -> impl Iterator<Item = usize> + '_ {
    s.inst
        .iter()
        .enumerate()
        .filter(|(_, v)| v.iter().any(|i| i.status == Status::Ready))
        .map(|(a, _)| a)
}

/// Every started instance and permanent activity of a state.
fn running(s: &G3State) -> impl Iterator<Item = (Owner, Inst)> + '_ {
    let acts = s.inst.iter().enumerate().flat_map(|(a, v)| {
        v.iter()
            .filter(|i| i.running())
            .map(move |i| (Owner::Activity(a), *i))
    });
    let perms = s
        .perm
        .iter()
        .enumerate()
        .filter_map(|(t, p)| p.map(|i| (Owner::Task(t), i)));
    acts.chain(perms)
}

/// The cycles of unpaused transitions of every state machine that go
/// through no `async` codel (an async codel blocks: the task does not
/// spin, so it exempts the cycles through it and no other). The states
/// that spin are those of the strongly connected parts of the unpaused
/// graph without its async states; each such part is covered by rounds
/// ([`cover`]), one [`Cycle`] each. A round has a way out when some codel
/// of its part may yield `ether`, `pause::`, or a state outside the part
/// (an async one included): the task may then leave the spinning states.
pub fn unpaused_cycles(m: &Machine<'_>) -> Vec<Cycle> {
    let owners = (0..m.activities.len())
        .map(Owner::Activity)
        .chain((0..m.tasks.len()).map(Owner::Task));
    let mut out = Vec::new();
    for owner in owners {
        let fsm = m.fsm(owner);
        let spins = |s: &u8| !fsm.states[usize::from(*s)].is_async;
        let mut g: DiGraphMap<u8, (), std::hash::RandomState> = DiGraphMap::new();
        for s in (0..fsm.states.len()).map(|s| s as u8).filter(spins) {
            g.add_node(s);
            for t in fsm.unpaused(s).filter(spins) {
                g.add_edge(s, t, ());
            }
        }
        let mut sccs = tarjan_scc(&g);
        for scc in &mut sccs {
            scc.sort_unstable();
        }
        sccs.sort_unstable();
        for scc in sccs {
            let cyclic = scc.len() > 1 || g.contains_edge(scc[0], scc[0]);
            if !cyclic {
                continue;
            }
            let has_exit = scc.iter().any(|&s| {
                fsm.states[usize::from(s)].yields.iter().any(|t| match *t {
                    Target::State { state, pause } => pause || !scc.contains(&state),
                    Target::Ether => true,
                })
            });
            out.extend(cover(fsm, &scc).into_iter().map(|states| Cycle {
                owner,
                states,
                has_exit,
            }));
        }
    }
    out
}

/// Rounds that together go through every state of `scc` (a strongly
/// connected set of spinning states, sorted): for each state in turn that
/// no round so far goes through, the shortest round through it. A round
/// whose states are all covered already is never added.
fn cover(fsm: &Fsm, scc: &[u8]) -> Vec<Vec<u8>> {
    let mut covered: BTreeSet<u8> = BTreeSet::new();
    let mut out = Vec::new();
    for &s in scc {
        if covered.contains(&s) {
            continue;
        }
        let round = round_from(fsm, scc, s);
        covered.extend(round.iter().copied());
        out.push(round);
    }
    out
}

/// The cycle as the same round, begun at `entry` (one of its states).
fn rotate(cycle: &Cycle, entry: u8) -> Cycle {
    let mut states = cycle.states.clone();
    if let Some(k) = states.iter().position(|&s| s == entry) {
        states.rotate_left(k);
    }
    Cycle {
        states,
        ..cycle.clone()
    }
}

/// A shortest path of unpaused yields inside `scc` from `entry` back to
/// it, as the states visited (starting with `entry`).
fn round_from(fsm: &Fsm, scc: &[u8], entry: u8) -> Vec<u8> {
    let mut parent: BTreeMap<u8, u8> = BTreeMap::new();
    let mut queue = std::collections::VecDeque::from([entry]);
    while let Some(s) = queue.pop_front() {
        for t in fsm.unpaused(s).filter(|t| scc.contains(t)) {
            if t == entry {
                let mut path = vec![s];
                let mut cur = s;
                while cur != entry {
                    let Some(&p) = parent.get(&cur) else { break };
                    cur = p;
                    path.push(cur);
                }
                path.reverse();
                return path;
            }
            if let std::collections::btree_map::Entry::Vacant(e) = parent.entry(t) {
                e.insert(s);
                queue.push_back(t);
            }
        }
    }
    vec![entry]
}

/// The trace of `path`, then one round of `cycle` by the owner's instance
/// standing at its entry, then the violation.
fn lasso(engine: &Engine<'_>, path: &[G3Action], owner: Owner, cycle: &Cycle) -> Trace {
    let mut trace = super::trace::render(engine, path);
    let fsm = engine.m.fsm(owner);
    let loop_start = trace.steps.len();
    let task = &engine.m.tasks[engine.m.task_of(owner)];
    let (again, never) = if task.period_ns.is_some() {
        (
            "the task sweeps again at once".to_owned(),
            format!("task `{}` never waits for its next wake-up", task.name),
        )
    } else {
        (
            format!(
                "task `{}` has no period and runs it at once, without waiting for an event",
                task.name
            ),
            format!(
                "task `{}`, which has no period, busy-spins between events",
                task.name
            ),
        )
    };
    let task = &task.name;
    for (k, &s) in cycle.states.iter().enumerate() {
        let next = cycle.states[(k + 1) % cycle.states.len()];
        let state = &fsm.states[usize::from(s)];
        let to = &fsm.states[usize::from(next)].name;
        let mut step = super::trace::codel_step(engine, owner, s, to);
        step.text = format!(
            "task `{task}` runs codel `{}` of {} in state `{}`, which yields `{to}` without `pause::`: {again}",
            state.function,
            describe(engine, owner),
            state.name
        );
        trace.steps.push(step);
    }
    let mut v = TraceStep::new(
        Event::Violation,
        format!(
            "{} can go round states {} forever without `pause::`: {never}",
            describe(engine, owner),
            names(fsm, &cycle.states)
        ),
    );
    v.thread = Some(task.clone());
    trace.steps.push(v);
    trace.loop_start = Some(loop_start);
    trace
}

/// `` `a` → `b` → `a` `` for a round of states.
pub fn names(fsm: &Fsm, states: &[u8]) -> String {
    let mut v: Vec<String> = states
        .iter()
        .map(|&s| format!("`{}`", fsm.states[usize::from(s)].name))
        .collect();
    if let Some(first) = v.first().cloned() {
        v.push(first);
    }
    v.join(" → ")
}

impl Engine<'_> {
    /// Replays `path` from the initial state: every state, initial first.
    pub fn states_along(&self, path: &[G3Action]) -> Vec<G3State> {
        let mut s = self.initial();
        let mut out = vec![s.clone()];
        for &a in path {
            if let Some(n) = self.next_state(&s, a) {
                s = n;
            }
            out.push(s.clone());
        }
        out
    }
}
