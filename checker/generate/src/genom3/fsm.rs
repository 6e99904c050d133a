//! Codel state machines (an activity's, a task's permanent one) and the
//! parameters of codels.
//!
//! A machine's states are `start` and `states - 1` others, linked by a
//! random tree of yields rooted at `start` (so every state is reachable,
//! as genom3 requires) plus random extra yields. A yield to a later state
//! is `pause::` with probability `pauses`; a yield to the same or an
//! earlier state is always `pause::` unless `unpaused_cycles`, so by
//! default the unpaused yields form no cycle (no `livelock`, no
//! `unpaused-loop`). Unless the machine is drawn *endless*, every leaf of
//! the tree yields `ether` (and other states sometimes do); an endless
//! machine never reaches `ether` by itself, only by a `stop` codel after
//! an interruption, an exception or `kill`. A `stop` state, when drawn,
//! yields `ether` (and sometimes `pause::stop`), as genom3 requires.

use std::collections::BTreeSet;

use super::plan::{DataPath, Dir, Fsm, FsmCodel, Param, PortPlan, ServiceParam, Source, Yield};
use crate::rng::SplitMix;

/// State names after `start` (then `s7`, `s8`, ...).
const NAMES: [&str; 6] = ["main", "wait", "run", "check", "poll", "done"];

/// The shape of a machine.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Shape {
    pub(crate) states: usize,
    pub(crate) pauses: f64,
    pub(crate) unpaused_cycles: bool,
    pub(crate) asyncs: bool,
    /// Probability that the machine never yields `ether`.
    pub(crate) endless: f64,
    /// Probability of a `stop` state.
    pub(crate) stop: f64,
}

/// What a codel's parameters may name: ids paths, the service's own
/// parameters, ports.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Pool<'a> {
    pub(crate) paths: &'a [DataPath],
    pub(crate) locals: &'a [ServiceParam],
    pub(crate) ports: &'a [PortPlan],
}

impl Pool<'_> {
    /// Up to `count` parameters with distinct names and non-overlapping
    /// paths (genom3 names a parameter after its path's last component).
    pub(crate) fn pick(&self, r: &mut SplitMix, count: usize) -> Vec<Param> {
        if count > 0 && r.chance(0.03) {
            let dir = if r.chance(0.5) { Dir::In } else { Dir::InOut };
            return vec![Param {
                source: Source::Implicit,
                dir,
                path: "::ids".into(),
            }];
        }
        let mut out: Vec<Param> = Vec::new();
        let mut names = BTreeSet::new();
        let mut taken: Vec<String> = Vec::new();
        for _ in 0..count * 3 {
            if out.len() == count {
                break;
            }
            let roll = r.below(10);
            let param = if roll < 2 && !self.locals.is_empty() {
                self.local(r)
            } else if roll < 3 && !self.ports.is_empty() {
                self.port(r)
            } else {
                self.ids(r, &taken)
            };
            let Some((param, name)) = param else { continue };
            if names.insert(name) {
                if param.source != Source::Local && param.source != Source::Port {
                    taken.push(param.path.clone());
                }
                out.push(param);
            }
        }
        out
    }

    fn local(&self, r: &mut SplitMix) -> Option<(Param, String)> {
        let p = r.pick(self.locals)?;
        let source = if r.chance(0.5) {
            Source::Local
        } else {
            Source::Implicit
        };
        let param = Param {
            source,
            dir: p.dir,
            path: p.name.clone(),
        };
        Some((param, p.name.clone()))
    }

    fn port(&self, r: &mut SplitMix) -> Option<(Param, String)> {
        let p = r.pick(self.ports)?;
        let dir = if p.out { Dir::Out } else { Dir::In };
        let param = Param {
            source: Source::Port,
            dir,
            path: p.name.clone(),
        };
        Some((param, p.name.clone()))
    }

    fn ids(&self, r: &mut SplitMix, taken: &[String]) -> Option<(Param, String)> {
        let p = r.pick(self.paths)?;
        if taken.iter().any(|t| p.overlaps(t)) {
            return None;
        }
        let dir = match r.below(4) {
            0 | 1 => Dir::In,
            2 => Dir::Out,
            _ => Dir::InOut,
        };
        let source = if r.chance(0.3) {
            Source::Ids
        } else {
            Source::Implicit
        };
        let param = Param {
            source,
            dir,
            path: p.path.clone(),
        };
        Some((param, p.last().to_owned()))
    }
}

/// A random machine whose codel functions are named `prefix_STATE`.
pub(crate) fn machine(r: &mut SplitMix, prefix: &str, shape: &Shape, pool: &Pool<'_>) -> Fsm {
    let n = shape.states.max(1);
    let mut states = vec!["start".to_owned()];
    states.extend((1..n).map(|i| {
        NAMES
            .get(i - 1)
            .map_or_else(|| format!("s{}", i + 1), |s| (*s).to_owned())
    }));
    let mut yields = state_yields(r, n, shape);
    if r.chance(shape.stop) {
        let mut stop = vec![Yield {
            to: None,
            pause: false,
        }];
        if r.chance(0.3) {
            stop.insert(
                0,
                Yield {
                    to: Some(n),
                    pause: true,
                },
            );
        }
        yields.push(stop);
        states.push("stop".into());
    }
    let codels = group(r, yields, n, shape)
        .into_iter()
        .map(|(members, ys, is_async)| {
            let function = format!("{prefix}_{}", states[members[0]]);
            let params = if is_async {
                Vec::new()
            } else {
                let count = r.below(3);
                pool.pick(r, count)
            };
            FsmCodel {
                states: members,
                function,
                params,
                yields: ys,
                is_async,
            }
        })
        .collect();
    Fsm { states, codels }
}

/// The yields of states `0..n`: a tree rooted at `start`, extra edges,
/// `ether` (or, when endless, paused loops) at the leaves.
fn state_yields(r: &mut SplitMix, n: usize, shape: &Shape) -> Vec<Vec<Yield>> {
    let mut yields: Vec<Vec<Yield>> = vec![Vec::new(); n];
    for i in 1..n {
        let parent = r.below(i);
        yields[parent].push(Yield {
            to: Some(i),
            pause: r.chance(shape.pauses),
        });
    }
    for (i, ys) in yields.iter_mut().enumerate() {
        if r.chance(0.4) {
            let j = r.below(n);
            ys.push(edge(r, i, j, shape));
        }
    }
    let endless = r.chance(shape.endless);
    for (i, ys) in yields.iter_mut().enumerate() {
        let leaf = !ys.iter().any(|y| y.to.is_some_and(|j| j > i));
        if endless {
            if leaf {
                let back = Yield {
                    to: Some(r.below(i + 1)),
                    pause: true,
                };
                ys.push(back);
            }
        } else if leaf || r.chance(0.3) {
            ys.push(Yield {
                to: None,
                pause: false,
            });
        }
    }
    for ys in &mut yields {
        let mut seen = BTreeSet::new();
        ys.retain(|y| seen.insert(y.to));
    }
    yields
}

/// A yield from `i` to `j`: paused when it goes back unless unpaused
/// cycles are allowed (then half of them are not).
fn edge(r: &mut SplitMix, i: usize, j: usize, shape: &Shape) -> Yield {
    let pause = if j <= i {
        !(shape.unpaused_cycles && r.chance(0.5))
    } else {
        r.chance(shape.pauses)
    };
    Yield { to: Some(j), pause }
}

/// One codel per state, except that a state whose yields are all paused
/// (or `ether`) sometimes shares the previous state's codel when that
/// one's are too (`codel<main, wait>`): the union of paused yields adds no
/// unpaused cycle. Returns (states, yields, async) per codel.
fn group(
    r: &mut SplitMix,
    yields: Vec<Vec<Yield>>,
    n: usize,
    shape: &Shape,
) -> Vec<(Vec<usize>, Vec<Yield>, bool)> {
    let calm = |ys: &[Yield]| ys.iter().all(|y| y.pause || y.to.is_none());
    let mut out: Vec<(Vec<usize>, Vec<Yield>, bool)> = Vec::new();
    for (i, ys) in yields.into_iter().enumerate() {
        let is_async = shape.asyncs && i > 0 && i < n && r.chance(0.25);
        let merge = i > 0 && i < n && !is_async && calm(&ys) && r.chance(0.15);
        match out.last_mut() {
            Some((members, prev, false)) if merge && calm(prev) => {
                members.push(i);
                for y in ys {
                    if !prev.iter().any(|p| p.to == y.to) {
                        prev.push(y);
                    }
                }
            }
            _ => out.push((vec![i], ys, is_async)),
        }
    }
    out
}
