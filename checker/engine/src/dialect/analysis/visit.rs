//! The facts of one exploration read off each new state ([`visit`]):
//! codels reached, services started, unbounded interrupts, pending
//! instances, starvations and deadlocks, each kept with the first state
//! that shows it. Most states add nothing: [`Found`] remembers what is
//! known so that a state is read in a few loads per member.

use std::collections::{BTreeMap, BTreeSet};

use genom_model::behaviour::IDLE;
use genom_model::component::{CodelId, ServiceId};

use super::super::pending::{cycle_services, pending_cycle, pending_cycle_bits};
use super::super::system::{Config, System};
use crate::kernel::store::StateId;

/// Witnesses found in one exploration, by state id.
#[derive(Default)]
pub(crate) struct Found {
    pub(crate) reached: BTreeSet<CodelId>,
    pub(crate) started: BTreeSet<ServiceId>,
    pub(crate) deadlocks: BTreeMap<Vec<ServiceId>, StateId>,
    pub(crate) starvations: BTreeMap<(ServiceId, ServiceId), (StateId, bool)>,
    pub(crate) unbounded: BTreeMap<ServiceId, StateId>,
    pub(crate) pending: BTreeMap<ServiceId, StateId>,
    pub(crate) init_success: Option<StateId>,
    pub(crate) root: Option<StateId>,
    /// Codels (by id) and members already in `reached` and `started`: most
    /// states add nothing, and these are cheaper to ask.
    seen_codels: Vec<bool>,
    seen_members: Vec<bool>,
    /// Members already in `unbounded` and in `pending`, member pairs
    /// (`waiter * members + blocker`, below [`MAX_PAIRS`]) already in
    /// `starvations`, and the cycles (as member bits) already in
    /// `deadlocks`: a fact noted once is not looked up in its map again.
    seen_unbounded: Vec<bool>,
    seen_pending: Vec<bool>,
    seen_pairs: Vec<bool>,
    seen_cycles: Vec<u64>,
    /// Per member, where its positions start in `quiet` (`None` for an
    /// input); empty until the first state is visited.
    quiet_at: Vec<Option<usize>>,
    /// Per member and position: every fact the position shows by itself
    /// (its running codel, the start, an unbounded interrupt) is noted, so
    /// a state with the member there adds nothing unless it is pending.
    quiet: Vec<bool>,
    /// Members whose requests may still add a fact (see
    /// [`Found::request_adds`]); members leave it for good.
    requests_open: Vec<usize>,
}

/// Most member pairs whose starvation [`Found`] notes by index.
const MAX_PAIRS: usize = 1 << 22;

impl Found {
    /// Notes that `codel` runs or is reached.
    pub(super) fn reach(&mut self, codel: CodelId) {
        if first_time(&mut self.seen_codels, codel.0 as usize) {
            self.reached.insert(codel);
        }
    }

    fn has_reached(&self, codel: CodelId) -> bool {
        self.seen_codels.get(codel.0 as usize) == Some(&true)
    }

    fn has_started(&self, i: usize) -> bool {
        self.seen_members.get(i) == Some(&true)
    }

    /// Notes that member `i`, service `s`, starts.
    pub(super) fn start(&mut self, i: usize, s: ServiceId) {
        if first_time(&mut self.seen_members, i) {
            self.started.insert(s);
        }
    }

    /// Whether a request of member `i` (service `s`) may still add a fact:
    /// its control codel not reached yet, or, without start codel, the
    /// service not started yet.
    fn request_adds(&self, sys: &System<'_>, i: usize, s: ServiceId) -> (Option<CodelId>, bool) {
        let control = sys.component().services[s]
            .control
            .filter(|&k| !self.has_reached(k));
        let start = sys.machine_of(i).start.is_none() && !self.has_started(i);
        (control, start)
    }

    /// Sizes the per-member tables for `sys`, at the first state visited.
    fn prepare(&mut self, sys: &System<'_>) {
        if !self.quiet_at.is_empty() || sys.is_empty() {
            return;
        }
        let mut next = 0;
        for i in 0..sys.len() {
            if sys.is_input(i) {
                self.quiet_at.push(None);
                continue;
            }
            self.quiet_at.push(Some(next));
            next += sys.machine_of(i).positions.len();
            self.requests_open.push(i);
        }
        self.quiet = vec![false; next];
    }
}

/// Marks `k` in `seen` (grown as needed); whether it was not marked yet.
fn first_time(seen: &mut Vec<bool>, k: usize) -> bool {
    if let Some(flag) = seen.get_mut(k) {
        return !std::mem::replace(flag, true);
    }
    seen.resize(k + 1, false);
    seen[k] = true;
    true
}

/// Reads the properties of one new state.
pub(crate) fn visit(sys: &System<'_>, id: StateId, cfg: &Config, found: &mut Found) {
    found.root.get_or_insert(id);
    if cfg.init_done && found.init_success.is_none() && sys.init().is_some() {
        found.init_success = Some(id);
    }
    visit_members(sys, id, cfg, found);
    if cfg.main.len() <= 64 {
        // The cycle as member bits: a cycle already noted costs no
        // allocation.
        if let Some(set) = pending_cycle_bits(sys, cfg) {
            if !found.seen_cycles.contains(&set) {
                found.seen_cycles.push(set);
                let cycle = cycle_services(sys, set);
                found.deadlocks.entry(cycle).or_insert(id);
            }
        }
    } else if cfg.pending.iter().filter(|p| p.is_some()).count() >= 2 {
        if let Some(cycle) = pending_cycle(sys, cfg) {
            found.deadlocks.entry(cycle).or_insert(id);
        }
    }
}

/// Reads the properties of each member in a new state: first what the
/// state shows by itself (skipping a member at a position seen before
/// without pending instance: it adds nothing), then, only while some
/// request may still add a fact (a control codel not reached, a service
/// without start codel not started), which requests are enabled (the
/// running codels are gathered only then).
fn visit_members(sys: &System<'_>, id: StateId, cfg: &Config, found: &mut Found) {
    found.prepare(sys);
    for i in 0..cfg.main.len() {
        let Some(at) = found.quiet_at.get(i).copied().flatten() else {
            continue;
        };
        let p = cfg.main[i];
        let pending = cfg.pending[i].is_some();
        let quiet = found
            .quiet
            .get(at + usize::from(p))
            .copied()
            .unwrap_or(false);
        if quiet && !pending {
            continue;
        }
        let s = sys.service(i);
        if !quiet {
            if let Some(codel) = sys.running_codel(cfg, i) {
                found.reach(codel);
            }
            if p != IDLE {
                found.start(i, s);
            }
            if sys.machine_of(i).stop_loops[usize::from(p)]
                && first_time(&mut found.seen_unbounded, i)
            {
                found.unbounded.entry(s).or_insert(id);
            }
            if let Some(q) = found.quiet.get_mut(at + usize::from(p)) {
                *q = true;
            }
        }
        if pending {
            if first_time(&mut found.seen_pending, i) {
                found.pending.entry(s).or_insert(id);
            }
            starving(sys, id, cfg, i, found);
        }
    }
    let mut open = std::mem::take(&mut found.requests_open);
    open.retain(|&i| {
        let (control, start) = found.request_adds(sys, i, sys.service(i));
        control.is_some() || start
    });
    if !open.is_empty() {
        // Whether a request is enabled only matters while it adds a fact.
        sys.with_running(cfg, |running| {
            for &i in &open {
                let s = sys.service(i);
                let (control, start) = found.request_adds(sys, i, s);
                if (control.is_some() || start) && sys.request_enabled_among(cfg, i, running) {
                    if let Some(k) = control {
                        found.reach(k);
                    }
                    if start {
                        found.start(i, s);
                    }
                }
            }
        });
    }
    found.requests_open = open;
}

fn starving(sys: &System<'_>, id: StateId, cfg: &Config, i: usize, found: &mut Found) {
    if sys.machine_of(i).watchdog {
        return;
    }
    let n = cfg.main.len();
    for (t, via_delays) in sys.blockers_iter(cfg, i) {
        if !sys.may_never_end(cfg, t) {
            continue;
        }
        let pair = i * n + t;
        if n * n <= MAX_PAIRS && !first_time(&mut found.seen_pairs, pair) {
            continue;
        }
        found
            .starvations
            .entry((sys.service(i), sys.service(t)))
            .or_insert((id, via_delays));
    }
}
