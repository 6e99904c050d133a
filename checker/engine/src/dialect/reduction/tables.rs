//! The static tables of the partial-order reduction: per member, what its
//! steps write and read (*footprints*, as sets of members), and from them
//! which steps may interfere with which (see the header of
//! [`super`] for how they are used).
//!
//! Sets of members are bit masks (`u64`): the reduction is off for systems
//! of more than 64 members.

use genom_model::behaviour::{Effect, Position};
use genom_model::component::CodelId;

use crate::dialect::system::{System, conflict};

/// A set of member indices.
pub(super) type Set = u64;

/// The set holding member `i` alone.
pub(super) fn bit(i: usize) -> Set {
    1u64 << i
}

/// The members of a set, in increasing order.
pub(super) fn members(mut s: Set) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        if s == 0 {
            return None;
        }
        let i = s.trailing_zeros() as usize;
        s &= s - 1;
        Some(i)
    })
}

/// What a step may write and read: the members whose instance (position,
/// pending instance, wait mask) it may change, and those whose instance
/// it reads.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Footprint {
    pub(super) writes: Set,
    pub(super) reads: Set,
}

impl Footprint {
    /// Whether two steps with these footprints may not commute: one writes
    /// what the other reads or writes.
    fn interferes(self, other: Footprint) -> bool {
        self.writes & (other.writes | other.reads) != 0 || other.writes & self.reads != 0
    }
}

/// The static facts about the members of one system.
#[derive(Debug, Clone, Default)]
pub(super) struct Tables {
    /// Per member: the members that list it in `stops`.
    pub(super) stoppers: Vec<Set>,
    /// Per member: the members its instances forbid (their requests are
    /// rejected while it has one).
    pub(super) forbidees: Vec<Set>,
    /// Per member: the other members on its thread.
    pub(super) mates: Vec<Set>,
    /// Per member: it has no start codel (it ends as soon as it starts).
    pub(super) no_start: Vec<bool>,
    /// Per codel (by id): the other members with a codel that conflicts
    /// with it (beginning either locks the other out).
    pub(super) lockers: Vec<Set>,
    /// Per codel (by id): the members whose control codel conflicts with
    /// it (running it rejects nothing but delays their requests).
    pub(super) lockees: Vec<Set>,
    /// Per member: the footprint of its request (interrupts, start, and
    /// what ending the interrupted instances may start).
    pub(super) request: Vec<Footprint>,
    /// Per member: the footprint of its codel steps at any position (its
    /// own instance and, when it may end, what ending may start).
    pub(super) steps: Vec<Footprint>,
    /// Per member: the requests (first) and codel steps (second) that may
    /// interfere with its enabled request.
    pub(super) request_deps: Vec<(Set, Set)>,
    /// Per member: the requests and codel steps that may interfere with its
    /// enabled codel step that may end the instance.
    pub(super) ending_deps: Vec<(Set, Set)>,
    /// The member sets a deadlock may consist of (strongly connected by
    /// `delays` among themselves); `None` when too many to list.
    pub(super) cycles: Option<Vec<Set>>,
    /// Per member: the members it may starve (open pairs at the start).
    pub(super) starvable_by: Vec<Set>,
    /// The members whose request being enabled is a fact (their control
    /// codel is reached, or, without start codel, they start).
    pub(super) request_facts: Set,
}

impl Tables {
    /// The tables of `sys` (at most 64 members).
    pub(super) fn new(sys: &System<'_>) -> Self {
        let c = sys.component();
        let n = sys.len();
        let set = |list: &[usize]| list.iter().fold(0, |s, &j| s | bit(j));
        let stops: Vec<Set> = (0..n).map(|i| set(sys.stops_of(i))).collect();
        let inputs = (0..n)
            .filter(|&i| sys.is_input(i))
            .fold(0, |s, i| s | bit(i));
        // The relation between members only (inputs are no pending nodes).
        let own = |rel: &[Set]| -> Vec<Set> {
            (0..n)
                .map(|i| {
                    if inputs & bit(i) != 0 {
                        0
                    } else {
                        rel[i] & !inputs
                    }
                })
                .collect()
        };
        let delayers: Vec<Set> = (0..n).map(|i| set(sys.delayers_of(i))).collect();
        let forbidders: Vec<Set> = (0..n).map(|i| set(sys.forbidders_of(i))).collect();
        let transpose = |rel: &[Set]| -> Vec<Set> {
            (0..n)
                .map(|t| {
                    (0..n)
                        .filter(|&k| rel[k] & bit(t) != 0)
                        .fold(0, |s, k| s | bit(k))
                })
                .collect()
        };
        let stoppers = transpose(&stops);
        let forbidees = transpose(&forbidders);
        let thread = |i: usize| sys.machine_of(i).thread;
        let mates: Vec<Set> = (0..n)
            .map(|i| {
                (0..n)
                    .filter(|&j| j != i && thread(i).is_some() && thread(j) == thread(i))
                    .fold(0, |s, j| s | bit(j))
            })
            .collect();
        let no_start: Vec<bool> = (0..n).map(|i| sys.machine_of(i).start.is_none()).collect();
        let can_end: Vec<bool> = (0..n)
            .map(|i| {
                let m = sys.machine_of(i);
                m.finish
                    .iter()
                    .flatten()
                    .any(|f| matches!(f.effect, Effect::End(_)))
            })
            .collect();
        let vanish = vanish_cascades(n, &stops, &delayers, &no_start);
        // Closure reads: starting a member reads the instances of its
        // delayers and the wait mask of its stops targets.
        let closure_reads = |s: Set| members(s).fold(s, |r, k| r | delayers[k] | stops[k]);
        let request: Vec<Footprint> = (0..n)
            .map(|x| {
                let mut writes = bit(x) | stops[x];
                for t in members(stops[x]) {
                    writes |= vanish[t];
                }
                if no_start[x] {
                    writes |= vanish[x];
                }
                let reads = bit(x) | forbidders[x] | delayers[x] | closure_reads(writes);
                Footprint { writes, reads }
            })
            .collect();
        let steps: Vec<Footprint> = (0..n)
            .map(|j| {
                let writes = bit(j) | if can_end[j] { vanish[j] } else { 0 };
                let reads = if can_end[j] {
                    closure_reads(writes)
                } else {
                    bit(j)
                };
                Footprint { writes, reads }
            })
            .collect();
        let deps = |f: Footprint| -> (Set, Set) {
            let r = (0..n)
                .filter(|&y| f.interferes(request[y]))
                .fold(0, |s, y| s | bit(y));
            let m = (0..n)
                .filter(|&j| f.interferes(steps[j]))
                .fold(0, |s, j| s | bit(j));
            (r, m)
        };
        let codels = member_codels(sys);
        let mut lockers = vec![0; c.codels.len()];
        let mut lockees = vec![0; c.codels.len()];
        let mut control_lockers = vec![0; n];
        for &(j, k) in &codels {
            let uses = sys.codel_uses(k);
            for &(i, other) in &codels {
                if i != j && conflict(uses, sys.codel_uses(other)) {
                    lockers[k.0 as usize] |= bit(i);
                }
            }
            for (x, locked_by) in control_lockers.iter_mut().enumerate() {
                if conflict(uses, sys.control_uses(x)) {
                    lockees[k.0 as usize] |= bit(x);
                    *locked_by |= bit(j);
                }
            }
        }
        let request_deps: Vec<(Set, Set)> = (0..n)
            .map(|x| {
                let (r, m) = deps(request[x]);
                (r & !bit(x), m | control_lockers[x])
            })
            .collect();
        let ending_deps: Vec<(Set, Set)> = (0..n)
            .map(|i| {
                let (r, m) = deps(steps[i]);
                (r, m & !bit(i))
            })
            .collect();
        let starvable_by = (0..n)
            .map(|w| {
                if sys.machine_of(w).watchdog || sys.is_input(w) {
                    return 0;
                }
                // Waiting for an interrupted instance never starves: it
                // may never end only while active (not interrupted).
                members(delayers[w])
                    .filter(|&t| {
                        sys.is_input(t) || sys.machine_of(t).may_never_end.iter().any(|&b| b)
                    })
                    .fold(0, |s, t| s | bit(t))
            })
            .collect();
        let request_facts = (0..n)
            .filter(|&i| !sys.is_input(i))
            .filter(|&i| no_start[i] || c.services[sys.service(i)].control.is_some())
            .fold(0, |s, i| s | bit(i));
        Tables {
            stoppers,
            forbidees,
            mates,
            no_start,
            lockers,
            lockees,
            request,
            steps,
            request_deps,
            ending_deps,
            cycles: deadlock_cycles(&own(&delayers), |i| !sys.machine_of(i).watchdog),
            starvable_by,
            request_facts,
        }
    }
}

/// Per member `t`: the members whose instance may change when `t`'s
/// instance disappears: those waiting for it or delayed by it may start,
/// and one without start codel then ends at once, and so on.
fn vanish_cascades(n: usize, stops: &[Set], delayers: &[Set], no_start: &[bool]) -> Vec<Set> {
    let direct: Vec<Set> = (0..n)
        .map(|t| {
            (0..n)
                .filter(|&k| (stops[k] | delayers[k]) & bit(t) != 0)
                .fold(0, |s, k| s | bit(k))
        })
        .collect();
    (0..n)
        .map(|t| {
            let mut out = direct[t];
            let mut todo = direct[t];
            while todo != 0 {
                let k = todo.trailing_zeros() as usize;
                todo &= todo - 1;
                if no_start[k] {
                    let more = direct[k] & !out;
                    out |= more;
                    todo |= more;
                }
            }
            out
        })
        .collect()
}

/// Largest strongly connected set of `delays` whose subsets are listed.
const MAX_CYCLE_SCC: usize = 14;

/// Most deadlock cycles listed.
const MAX_CYCLES: usize = 512;

/// Every set of at least two `node` members strongly connected by `rel`
/// (member → its delayers) among themselves: the values a deadlock's
/// cycle can take (see `engine::pending`); `None` when a strongly
/// connected component is too large to list its subsets, or they are too
/// many.
fn deadlock_cycles(rel: &[Set], node: impl Fn(usize) -> bool) -> Option<Vec<Set>> {
    let n = rel.len();
    let nodes = (0..n).filter(|&i| node(i)).fold(0, |s, i| s | bit(i));
    let rel: Vec<Set> = (0..n)
        .map(|i| {
            if nodes & bit(i) != 0 {
                rel[i] & nodes
            } else {
                0
            }
        })
        .collect();
    let mut out = Vec::new();
    let mut seen = 0;
    for i in 0..n {
        if seen & bit(i) != 0 {
            continue;
        }
        let scc = strongly_connected(&rel, bit(i) | reach(&rel, bit(i)), i);
        seen |= scc | bit(i);
        if scc.count_ones() < 2 {
            continue;
        }
        let list: Vec<usize> = members(scc).collect();
        if list.len() > MAX_CYCLE_SCC {
            return None;
        }
        for mask in 1u32..(1 << list.len()) {
            let s = list
                .iter()
                .enumerate()
                .filter(|&(k, _)| mask & (1 << k) != 0)
                .fold(0, |s, (_, &j)| s | bit(j));
            if s.count_ones() >= 2 && is_strongly_connected(&rel, s) {
                out.push(s);
                if out.len() > MAX_CYCLES {
                    return None;
                }
            }
        }
    }
    Some(out)
}

/// The members reachable from `from` in one step or more, within the
/// relation.
fn reach(rel: &[Set], from: Set) -> Set {
    let mut seen = 0;
    let mut todo = from;
    while todo != 0 {
        let k = todo.trailing_zeros() as usize;
        todo &= todo - 1;
        let next = rel[k] & !seen;
        seen |= next;
        todo |= next;
    }
    seen
}

/// The members of `within` on a cycle through `i` (its strongly connected
/// component, when `within` holds every member reachable from `i`).
fn strongly_connected(rel: &[Set], within: Set, i: usize) -> Set {
    members(within)
        .filter(|&j| reach(rel, bit(i)) & bit(j) != 0 && reach(rel, bit(j)) & bit(i) != 0)
        .fold(0, |s, j| s | bit(j))
}

/// Whether `s` is strongly connected by the relation restricted to it.
fn is_strongly_connected(rel: &[Set], s: Set) -> bool {
    let inner: Vec<Set> = (0..rel.len())
        .map(|i| if s & bit(i) != 0 { rel[i] & s } else { 0 })
        .collect();
    let first = s.trailing_zeros() as usize;
    let from_first = reach(&inner, bit(first)) | bit(first);
    from_first & s == s && members(s).all(|j| reach(&inner, bit(j)) & bit(first) != 0)
}

/// Every codel of every member (control codels excluded), with its member.
fn member_codels(sys: &System<'_>) -> Vec<(usize, CodelId)> {
    let mut out = Vec::new();
    for j in 0..sys.len() {
        let m = sys.machine_of(j);
        let mut seen: Vec<CodelId> = Vec::new();
        for p in &m.positions {
            if let Some(k) = p.codel().filter(|_| !matches!(p, Position::Idle)) {
                if !seen.contains(&k) {
                    seen.push(k);
                    out.push((j, k));
                }
            }
        }
    }
    out
}
