//! Partial-order reduction of the untimed semantics: each state is
//! expanded with a *stubborn set* (Valmari) of its steps, computed from
//! static interference tables ([`tables`]), instead of every step.
//!
//! The steps are grouped per member into two *entities*: its request, and
//! its codel steps (beginning the next codel, or every way of finishing
//! the running one). A set `T` of entities is stubborn in a state when
//!
//! - for every enabled entity in `T`, every entity that may interfere with
//!   it (fail to commute with it, or disable it) is in `T`: a request
//!   interferes through its footprint (the instances it may change: its
//!   own, its `stops` targets, and what ending them may start; and those
//!   its outcome reads), a codel step that may end the instance likewise,
//!   and a codel step that cannot only with the requests that interrupt it
//!   at its position and, for a begin, with the codels it locks out
//!   (same thread or conflicting data) and the requests whose control
//!   codel it delays;
//! - for every disabled entity in `T`, a *necessary enabling set* is in
//!   `T`: the steps one of which must occur before it can be enabled (the
//!   request of an idle member; the steps that may end a blocking
//!   instance; the finishing of a codel holding a lock).
//!
//! Then no sequence of steps outside `T` can disable or change a step of
//! `T`, and every enabled step of `T` stays enabled: the enabled steps of
//! `T` form a persistent set. Each verdict reads a state property that is
//! only ever *found* (made true in some visited state); the reduction keeps
//! the set of properties not found yet (its *open* facts) and refuses a
//! set whose steps could make an open fact false: a fact local to one
//! member (a codel running, a service started or pending, an interrupted
//! loop) cannot be, since the member's instance is the same where the step
//! is taken and after any steps outside `T` (every step writing it is in
//! `T`); the facts read across members (a request enabled for a control
//! codel, a starvation pair, a deadlock cycle) are checked against each
//! step's footprint. The explorer adds the *cycle proviso*: a state whose
//! reduced successors include an already stored state is expanded fully.
//!
//! Once no fact is open, exploring further changes no verdict:
//! [`Reduce::finished`] tells the explorer to stop (complete). To get
//! there early, [`probe`]s (explorations where clients request only one
//! service and its stoppers) find codels run and services started before
//! the search. With inputs or watchdogs (compositional parts, timed
//! services) only the facts are followed, without stubborn sets.
//! `docs/semantics.md` ("Partial-order reduction") gives the argument that
//! every verdict is preserved; tests/verdicts/compose.rs compares the stubborn sets
//! alone, the whole reduction and the default method with exhaustive
//! exploration on generated components.

pub mod probe;
mod tables;

use std::cell::RefCell;

use genom_model::behaviour::{Effect, IDLE};

use super::pending::pending_cycle;
use super::system::{Action, Config, Reduce, System, conflict};
use crate::kernel::explore::Limits;
use tables::{Set, Tables, bit, members};

/// The partial-order reduction of one system: its static tables and the
/// facts not found yet.
#[derive(Debug)]
pub struct Reduction {
    /// `None`: neither reduction nor facts (more than 64 members).
    tables: Option<Tables>,
    /// Stubborn sets are computed (else only the facts are followed: with
    /// inputs, or watchdogs).
    stubborn: bool,
    open: RefCell<Open>,
    /// Every fact has been found.
    done: std::cell::Cell<bool>,
    /// Probes run and the exploration stops once every fact is found
    /// (off only to test the stubborn sets alone).
    stop_early: bool,
}

/// The facts no expanded state has shown yet (each verdict reads whether
/// some state shows one).
#[derive(Debug, Clone, Default)]
struct Open {
    /// Members whose request was never enabled (and it is a fact: their
    /// control codel is reached, or, without start codel, they start).
    requests: Set,
    /// Per waiter: the blockers it was never seen starving by.
    starving: Vec<Set>,
    /// Members with an open starvation pair as waiter, as blocker.
    waiters: Set,
    blockers: Set,
    /// Per codel (by id): it may run and was never seen running.
    codels: Vec<bool>,
    /// How many of `codels` are open.
    open_codels: usize,
    /// Members never seen with an active instance.
    unstarted: Set,
    /// Members never seen started or pending (a dead service's reason
    /// reads whether it was pending).
    unpended: Set,
    /// Members with an interrupted loop never seen in it.
    unbounded: Set,
    /// The deadlock cycles (member sets) that may exist and were never
    /// seen; `None` when too many to list (never all found).
    cycles: Option<Vec<Set>>,
}

impl Open {
    /// The facts of `t` at the start, all open.
    fn new(sys: &System<'_>, t: &Tables) -> Self {
        let n = sys.len();
        let mut codels = vec![false; sys.component().codels.len()];
        let mut unbounded = 0;
        for i in (0..n).filter(|&i| !sys.is_input(i)) {
            let m = sys.machine_of(i);
            for p in m.positions.iter().filter(|p| p.is_running()) {
                if let Some(k) = p.codel() {
                    codels[k.0 as usize] = true;
                }
            }
            if m.stop_loops.iter().any(|&b| b) {
                unbounded |= bit(i);
            }
        }
        let all = (0..n)
            .filter(|&i| !sys.is_input(i))
            .fold(0, |s, i| s | bit(i));
        let mut open = Open {
            requests: t.request_facts,
            starving: t.starvable_by.clone(),
            open_codels: codels.iter().filter(|&&b| b).count(),
            codels,
            unstarted: (0..n)
                .filter(|&i| !t.no_start[i])
                .fold(0, |s, i| s | bit(i))
                & all,
            unpended: all,
            unbounded,
            cycles: t.cycles.clone(),
            ..Open::default()
        };
        open.recount();
        open
    }

    fn recount(&mut self) {
        self.waiters = 0;
        self.blockers = 0;
        for (w, &ts) in self.starving.iter().enumerate() {
            if ts != 0 {
                self.waiters |= bit(w);
                self.blockers |= ts;
            }
        }
    }

    /// Whether some deadlock cycle may still be found.
    fn deadlock_open(&self) -> bool {
        self.cycles.as_ref().is_none_or(|c| !c.is_empty())
    }

    /// Whether every fact has been found.
    fn none(&self) -> bool {
        !self.deadlock_open()
            && self.requests == 0
            && self.waiters == 0
            && self.open_codels == 0
            && self.unstarted == 0
            && self.unpended == 0
            && self.unbounded == 0
    }
}

impl System<'_> {
    /// The same system, explored with partial-order reduction.
    #[must_use]
    pub fn with_reduction(self) -> Self {
        let r = Reduction::new(&self, true);
        self.reduced_by(r)
    }

    /// [`Self::with_reduction`] without probes and without stopping once
    /// every fact is found: the stubborn sets alone (for tests).
    #[must_use]
    pub fn with_stubborn_sets_only(self) -> Self {
        let mut r = Reduction::new(&self, true);
        r.stop_early = false;
        self.reduced_by(r)
    }

    /// The same system, exploring every interleaving but following the
    /// facts its states show, so that [`Model::finished`] ends the
    /// exploration once all are found (see [`super::compose`]).
    ///
    /// [`Model::finished`]: crate::kernel::explore::Model::finished
    #[must_use]
    pub fn with_fact_tracking(self) -> Self {
        let r = Reduction::new(&self, false);
        self.reduced_by(r)
    }
}

impl Reduce for Reduction {
    fn stubborn(&self, sys: &System<'_>, cfg: &Config, actions: &mut [Action]) -> usize {
        Reduction::stubborn(self, sys, cfg, actions)
    }

    fn finished(&self) -> bool {
        self.stop_early && self.done.get()
    }

    fn probe(&self, sys: &System<'_>, limits: Limits) -> Option<probe::Probed> {
        let t = self
            .tables
            .as_ref()
            .filter(|_| self.stubborn && self.stop_early)?;
        let mut open = self.open.try_borrow_mut().ok()?;
        let wanted = (0..sys.len()).fold(0, |s, i| s | bit(i));
        let found = probe::probe(sys, &t.stoppers, wanted, limits);
        for &k in &found.reached {
            if let Some(o) = open.codels.get_mut(k.0 as usize) {
                if std::mem::replace(o, false) {
                    open.open_codels -= 1;
                }
            }
        }
        let started = found.started.iter().fold(0, |s, &(i, _)| s | bit(i));
        open.unstarted &= !started;
        open.unpended &= !started;
        let c = sys.component();
        for y in members(open.requests) {
            let control = c.services[sys.service(y)].control;
            let start = sys.machine_of(y).start.is_some() || started & bit(y) != 0;
            if control.is_none_or(|k| found.reached.contains(&k)) && start {
                open.requests &= !bit(y);
            }
        }
        if open.none() {
            self.done.set(true);
        }
        Some(found)
    }

    fn note(&self, sys: &System<'_>, cfg: &Config) {
        if let (Some(_), Ok(mut open)) = (&self.tables, self.open.try_borrow_mut()) {
            sys.with_running(cfg, |running| self.note_facts(sys, cfg, running, &mut open));
        }
    }
}

/// An entity: a member's request, or its codel steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Entity {
    Request(usize),
    Steps(usize),
}

/// Requests (first) and codel steps (second), as member sets; `None` when
/// no small set exists.
type Pair = (Set, Set);

/// What one state offers: its enabled entities and running codels.
struct Here<'s, 'a> {
    sys: &'s System<'a>,
    cfg: &'s Config,
    t: &'s Tables,
    open: &'s Open,
    enabled: Pair,
    running: &'s [(usize, genom_model::component::CodelId)],
}

impl Reduction {
    /// The tables of `sys`; with `stubborn`, reducing its steps (when it
    /// has no inputs and no watchdog), else only following its facts.
    pub fn new(sys: &System<'_>, stubborn: bool) -> Self {
        let n = sys.len();
        let tables = (n <= 64 && !sys.too_many_stops()).then(|| Tables::new(sys));
        let stubborn = stubborn && (0..n).all(|i| !sys.is_input(i) && !sys.machine_of(i).watchdog);
        let open = tables
            .as_ref()
            .map(|t| Open::new(sys, t))
            .unwrap_or_default();
        Reduction {
            tables,
            stubborn,
            open: RefCell::new(open),
            done: std::cell::Cell::new(false),
            stop_early: true,
        }
    }

    /// Moves a stubborn subset of `actions` (the actions enabled in `cfg`)
    /// to the front and returns its length; `actions.len()` when there is
    /// none smaller.
    pub fn stubborn(&self, sys: &System<'_>, cfg: &Config, actions: &mut [Action]) -> usize {
        let Some(t) = &self.tables else {
            return actions.len();
        };
        let Ok(mut open) = self.open.try_borrow_mut() else {
            return actions.len();
        };
        sys.with_running(cfg, |running| {
            self.note_facts(sys, cfg, running, &mut open);
            if !self.stubborn || !cfg.init_done || actions.len() < 2 {
                return actions.len();
            }
            let mut enabled = (0, 0);
            for &a in actions.iter() {
                let Some(i) = sys.member_index(a.service()) else {
                    return actions.len();
                };
                match a {
                    Action::Request(_) => enabled.0 |= bit(i),
                    Action::Begin(_) | Action::Finish(..) => enabled.1 |= bit(i),
                    Action::Watchdog(..) => return actions.len(),
                }
            }
            let here = Here {
                sys,
                cfg,
                t,
                open: &open,
                enabled,
                running,
            };
            match here.best() {
                Some(chosen) => keep(sys, actions, chosen),
                None => actions.len(),
            }
        })
    }
}

impl Reduction {
    /// Marks the facts `cfg` shows as found, and notes when none is left.
    fn note_facts(
        &self,
        sys: &System<'_>,
        cfg: &Config,
        running: &[(usize, genom_model::component::CodelId)],
        open: &mut Open,
    ) {
        note_facts(sys, cfg, running, open);
        if open.none() {
            self.done.set(true);
        }
    }
}

/// Marks the facts `cfg` shows as found.
fn note_facts(
    sys: &System<'_>,
    cfg: &Config,
    running: &[(usize, genom_model::component::CodelId)],
    open: &mut Open,
) {
    for &(_, k) in running {
        if std::mem::replace(&mut open.codels[k.0 as usize], false) {
            open.open_codels -= 1;
        }
    }
    if open.unstarted | open.unpended | open.unbounded != 0 {
        for i in 0..cfg.main.len() {
            let active = cfg.main[i] != IDLE;
            if active {
                open.unstarted &= !bit(i);
                open.unpended &= !bit(i);
                if sys.machine_of(i).stop_loops[usize::from(cfg.main[i])] {
                    open.unbounded &= !bit(i);
                }
            }
            if cfg.pending[i].is_some() {
                open.unpended &= !bit(i);
            }
        }
    }
    for y in members(open.requests) {
        if sys.request_enabled_among(cfg, y, running) {
            open.requests &= !bit(y);
            if sys.machine_of(y).start.is_none() {
                open.unpended &= !bit(y);
            }
        }
    }
    if open.cycles.as_ref().is_some_and(|c| !c.is_empty())
        && cfg.pending.iter().filter(|p| p.is_some()).count() >= 2
    {
        if let Some(cycle) = pending_cycle(sys, cfg) {
            let set = cycle
                .iter()
                .filter_map(|&s| sys.member_index(s))
                .fold(0, |s, i| s | bit(i));
            if let Some(list) = open.cycles.as_mut() {
                list.retain(|&c| c != set);
            }
        }
    }
    if open.waiters == 0 {
        return;
    }
    let mut changed = false;
    for w in members(open.waiters) {
        if cfg.pending[w].is_none() {
            continue;
        }
        for (b, _) in sys.blockers_iter(cfg, w) {
            if open.starving[w] & bit(b) != 0 && sys.may_never_end(cfg, b) {
                open.starving[w] &= !bit(b);
                changed = true;
            }
        }
    }
    if changed {
        open.recount();
    }
}

/// Moves the actions of the chosen entities to the front; their number.
fn keep(sys: &System<'_>, actions: &mut [Action], (r, m): Pair) -> usize {
    let mut n = 0;
    for k in 0..actions.len() {
        let a = actions[k];
        let Some(i) = sys.member_index(a.service()) else {
            continue;
        };
        let set = if matches!(a, Action::Request(_)) {
            r
        } else {
            m
        };
        if set & bit(i) != 0 {
            actions.swap(n, k);
            n += 1;
        }
    }
    if n == 0 { actions.len() } else { n }
}

impl Here<'_, '_> {
    /// The stubborn set with fewest enabled entities, over every enabled
    /// seed; `None` when each covers every enabled entity or is visible.
    fn best(&self) -> Option<Pair> {
        let total = (self.enabled.0.count_ones() + self.enabled.1.count_ones()) as usize;
        let mut best: Option<(usize, Pair)> = None;
        let seeds = members(self.enabled.1)
            .map(Entity::Steps)
            .chain(members(self.enabled.0).map(Entity::Request));
        for seed in seeds {
            if best.is_some_and(|b| b.0 == 1) {
                break;
            }
            let Some(set) = self.closure(seed) else {
                continue;
            };
            let on = (set.0 & self.enabled.0, set.1 & self.enabled.1);
            let size = (on.0.count_ones() + on.1.count_ones()) as usize;
            if size >= total || best.is_some_and(|b| b.0 <= size) {
                continue;
            }
            if self.visible(on) {
                continue;
            }
            best = Some((size, on));
        }
        best.map(|b| b.1)
    }

    /// The least set of entities holding `seed` and closed under the two
    /// rules; `None` when some disabled entity has no small enabling set.
    fn closure(&self, seed: Entity) -> Option<Pair> {
        let mut set: Pair = (0, 0);
        let mut done: Pair = (0, 0);
        match seed {
            Entity::Request(x) => set.0 |= bit(x),
            Entity::Steps(i) => set.1 |= bit(i),
        }
        loop {
            let todo = (set.0 & !done.0, set.1 & !done.1);
            let e = if todo.0 != 0 {
                Entity::Request(todo.0.trailing_zeros() as usize)
            } else if todo.1 != 0 {
                Entity::Steps(todo.1.trailing_zeros() as usize)
            } else {
                return Some(set);
            };
            let add = match e {
                Entity::Request(x) => {
                    done.0 |= bit(x);
                    if self.enabled.0 & bit(x) != 0 {
                        self.t.request_deps[x]
                    } else {
                        self.enable_request(x)?
                    }
                }
                Entity::Steps(i) => {
                    done.1 |= bit(i);
                    if self.enabled.1 & bit(i) != 0 {
                        self.step_deps(i)
                    } else {
                        self.enable_steps(i)?
                    }
                }
            };
            set.0 |= add.0;
            set.1 |= add.1;
        }
    }

    /// The entities that may interfere with member `i`'s enabled codel
    /// step at its position.
    fn step_deps(&self, i: usize) -> Pair {
        let m = self.sys.machine_of(i);
        let p = usize::from(self.cfg.main[i]);
        let ends = m.finish[p]
            .iter()
            .any(|f| matches!(f.effect, Effect::End(_)));
        if ends {
            return self.t.ending_deps[i];
        }
        let interrupters = if m.interrupt[p].is_some() {
            self.t.stoppers[i]
        } else {
            0
        };
        match m.begin[p].and(m.positions[p].codel()) {
            Some(k) => (
                interrupters | self.t.lockees[k.0 as usize],
                self.t.mates[i] | self.t.lockers[k.0 as usize],
            ),
            None => (interrupters, 0),
        }
    }

    /// A necessary enabling set of member `i`'s codel steps, disabled here.
    fn enable_steps(&self, i: usize) -> Option<Pair> {
        let (sys, cfg) = (self.sys, self.cfg);
        let m = sys.machine_of(i);
        let p = usize::from(cfg.main[i]);
        if cfg.main[i] == IDLE {
            if cfg.pending[i].is_none() {
                return Some((bit(i), 0));
            }
            let (b, _) = sys.blockers_iter(cfg, i).next()?;
            return self.enable_vanish(b);
        }
        let k = m.positions[p].codel().filter(|_| m.begin[p].is_some())?;
        let thread = m.thread;
        let uses = sys.codel_uses(k);
        let &(r, _) = self.running.iter().find(|&&(r, other)| {
            r != i
                && ((thread.is_some() && sys.machine_of(r).thread == thread)
                    || conflict(uses, sys.codel_uses(other)))
        })?;
        let interrupters = if m.interrupt[p].is_some() {
            self.t.stoppers[i]
        } else {
            0
        };
        Some((interrupters, bit(r)))
    }

    /// A necessary enabling set of member `x`'s request, disabled here.
    fn enable_request(&self, x: usize) -> Option<Pair> {
        let (sys, cfg) = (self.sys, self.cfg);
        if let Some(&f) = sys
            .forbidders_of(x)
            .iter()
            .find(|&&f| System::has_instance(cfg, f))
        {
            return self.enable_vanish(f);
        }
        if System::has_instance(cfg, x) && !sys.stops_itself(x) {
            return self.enable_vanish(x);
        }
        let uses = sys.control_uses(x);
        let &(r, _) = self
            .running
            .iter()
            .find(|&&(_, k)| conflict(uses, sys.codel_uses(k)))?;
        Some((0, bit(r)))
    }

    /// The steps one of which must occur before member `b`'s instance (main
    /// and pending) disappears: its codel steps and the requests that
    /// interrupt it.
    fn enable_vanish(&self, b: usize) -> Option<Pair> {
        if self.cfg.main[b] == IDLE && self.t.no_start[b] {
            return None;
        }
        Some((self.t.stoppers[b], bit(b)))
    }

    /// Whether some enabled entity of `on` may make an open fact false.
    fn visible(&self, (r, m): Pair) -> bool {
        let (t, open) = (self.t, self.open);
        let starving = open.waiters | open.blockers;
        for x in members(r) {
            let mut rejects = t.forbidees[x];
            if !self.sys.stops_itself(x) {
                rejects |= bit(x);
            }
            if open.deadlock_open()
                || t.request[x].writes & starving != 0
                || rejects & open.requests != 0
            {
                return true;
            }
        }
        for i in members(m) {
            let mach = self.sys.machine_of(i);
            let p = usize::from(self.cfg.main[i]);
            let ways = &mach.finish[p];
            if ways.iter().any(|f| matches!(f.effect, Effect::End(_))) {
                if open.deadlock_open() || t.steps[i].writes & starving != 0 {
                    return true;
                }
                continue;
            }
            if let Some(k) = mach.begin[p].and(mach.positions[p].codel()) {
                if t.lockees[k.0 as usize] & open.requests != 0 {
                    return true;
                }
            }
            let targets =
                mach.begin[p]
                    .into_iter()
                    .chain(ways.iter().filter_map(|f| match f.effect {
                        Effect::Goto(q) => Some(q),
                        Effect::End(_) => None,
                    }));
            let mne = &mach.may_never_end;
            if open.blockers & bit(i) != 0
                && mne[p]
                && targets.into_iter().any(|q| !mne[usize::from(q)])
            {
                return true;
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use genom_model::behaviour::Behaviour;
    use genom_model::component::ServiceId;

    use crate::dialect::system::System;
    use crate::kernel::explore::{Limits, explore};
    use crate::testing::check;

    /// Two looping services on threads of their own, sharing no data, and a
    /// third that stops the first while a codel writes what its control
    /// codel reads.
    const SRC: &str = "component t { lang: C; }\nids d { double x; }\n\
        thread t1 { period: 10ms; }\nthread t2 { period: 10ms; }\nthread t3 { period: 10ms; }\n\
        service a { thread: t1;\n start codel { exec: f(d.x); update: d.x; next: run; }\n\
          exec codel run { exec: f(d.x); update: d.x; next: run, end; } }\n\
        service b { thread: t2;\n start codel { exec: g(); next: run; }\n\
          exec codel run { exec: g(); next: run, end; } }\n\
        service c { thread: t3; stops: a;\n control codel { exec: h(const d.x); }\n\
          start codel { exec: k(); next: end; } }\n";

    #[test]
    fn stubborn_sets_cut_interleavings_and_keep_every_local_state() {
        let c = check(SRC).component.expect("a component");
        let b = Behaviour::new(&c);
        let all: Vec<ServiceId> = c.services.ids().collect();
        let positions = |reduce: bool| {
            let sys = System::new(&c, &b, &all, false);
            let sys = if reduce {
                sys.with_stubborn_sets_only()
            } else {
                sys
            };
            let mut seen = std::collections::BTreeSet::new();
            let e = explore(&sys, Limits::default(), |_, cfg| {
                for i in 0..cfg.main.len() {
                    seen.insert((i, cfg.main[i]));
                }
            });
            assert!(e.stopped.is_none());
            (e.transitions, e.reduced, seen)
        };
        let (full, none, all_full) = positions(false);
        let (reduced, expansions, all_reduced) = positions(true);
        assert_eq!(none, 0);
        assert!(expansions > 0, "some state is expanded with a stubborn set");
        // The tight loops close cycles at once, so the cycle proviso
        // expands most states fully: fewer transitions, not fewer states.
        assert!(
            reduced < full,
            "{reduced} transitions, {full} without reduction"
        );
        assert_eq!(all_reduced, all_full, "every position of every service");
    }
}
