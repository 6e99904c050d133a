//! The exact worst-case data age and reaction time of a cause-effect chain
//! through periodic GenoM3 tasks, by exhaustive discrete-time simulation
//! of the composed system (docs/functional-layer.md, "How the bounds are
//! checked").
//!
//! The chain: an external source publishing every `source_period` units,
//! then stages, each one periodic task (its own component, its own core,
//! an arbitrary phase) that runs its permanent codels one after the other
//! in every wake-up, each taking any whole number of units from 0 to its
//! WCET; the stage's chain codel reads the previous stage's port when it
//! begins and writes its own port when it ends. Every phase, every
//! duration and every order of the events of one instant are explored
//! (with integer constants, integer-time behaviours suffice for these
//! max-delay questions: digitization, Henzinger, Manna and Pnueli 1992).
//!
//! - data age: the largest time from a source sample to the end of the
//!   last stage's chain codel that read data derived from it;
//! - reaction time: the largest time from a source sample to the end of
//!   the first last-stage chain codel that read data derived from it or
//!   from a newer sample.
//!
//! Written from the specification, not from genom-system's analysis; it
//! reads the model only ([`stage_of`]).

use std::collections::{HashSet, VecDeque};

use genom_model::component::Component;
use genom_model::component::genom3::ParamSource;

/// One stage: a periodic task and its codels in wake-up order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Stage {
    /// The period, in units.
    pub period: u64,
    /// Each codel's WCET, in units, in the order a wake-up runs them.
    pub wcets: Vec<u64>,
    /// The codel that reads the previous port and writes the next.
    pub chain: usize,
}

/// A chain from an external periodic source through `stages`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Chain {
    /// The source's period, in units.
    pub source_period: u64,
    /// The stages, source side first.
    pub stages: Vec<Stage>,
}

/// The exact figures, in units.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Exact {
    /// Worst-case data age.
    pub data_age: u64,
    /// Worst-case reaction time.
    pub reaction: u64,
    /// States explored.
    pub states: usize,
}

/// Reads stage `Stage` off a component with one periodic task whose
/// permanent codels run in a cycle (`start` then a chain of unpaused
/// yields ending with one `pause::` back): the codel that reads port
/// `input` is the chain codel. `unit_ns` converts WCETs and the period.
pub fn stage_of(c: &Component, input: &str, unit_ns: u64) -> Option<Stage> {
    let g = c.genom3.as_deref()?;
    let task = g
        .tasks
        .iter()
        .find(|t| c.threads[t.thread].period.is_some())?;
    let period = c.threads[task.thread].period?.ns / unit_ns;
    let named = |s: &str| {
        task.codels
            .iter()
            .find(|k| k.states.iter().any(|x| x.name == s))
    };
    let start = named("start")?;
    let mut state = start.yields.first()?.state.name.clone();
    let mut wcets = Vec::new();
    let mut chain = None;
    for _ in 0..task.codels.len() {
        let k = named(&state)?;
        if k.params
            .iter()
            .any(|p| p.source == ParamSource::Port && p.name == input && p.dir.contains("in"))
        {
            chain = Some(wcets.len());
        }
        wcets.push(k.wcet.map_or(0, |w| w.ns / unit_ns));
        let y = k.yields.first()?;
        if y.pause {
            break;
        }
        state = y.state.name.clone();
    }
    Some(Stage {
        period,
        wcets,
        chain: chain?,
    })
}

/// One stage's state at an instant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct StageState {
    /// Units since the last tick.
    pos: u64,
    /// The codel running (`wcets.len()`: the wake-up's work is done).
    codel: usize,
    /// Units it has run.
    elapsed: u64,
    /// The age of the data the chain codel read, while it runs.
    held: Option<u64>,
    /// Whether the task has had its first tick.
    started: bool,
}

#[derive(Debug, Clone, PartialEq, Eq, Hash)]
struct State {
    /// Units since the source's last publication (`None`: none yet).
    source: Option<u64>,
    stages: Vec<StageState>,
    /// Per stage, the age of the data in its out port.
    ports: Vec<Option<u64>>,
    /// Units since the marked sample (reaction time), when one is marked.
    mark: Option<u64>,
}

/// The exact worst-case data age and reaction time of `chain`, exploring
/// at most `max_states` states; `None` when that is not enough or a
/// figure exceeds `cap` units.
pub fn exact(chain: &Chain, max_states: usize, cap: u64) -> Option<Exact> {
    let n = chain.stages.len();
    if n == 0 || chain.source_period == 0 || chain.stages.iter().any(|s| s.period == 0) {
        return None;
    }
    // Every phase: each task (and the source) starts at any instant of its
    // first period.
    let mut initial = vec![State {
        source: None,
        stages: Vec::new(),
        ports: vec![None; n],
        mark: None,
    }];
    for s in &chain.stages {
        let mut next = Vec::new();
        for st in &initial {
            for phase in 0..s.period {
                let mut x = st.clone();
                x.stages.push(StageState {
                    pos: s.period - phase,
                    codel: s.wcets.len(),
                    elapsed: 0,
                    held: None,
                    started: phase == 0,
                });
                next.push(x);
            }
        }
        initial = next;
    }
    let mut seen: HashSet<State> = HashSet::new();
    let mut queue: VecDeque<State> = VecDeque::new();
    for s in initial {
        for delay in 0..chain.source_period {
            let mut x = s.clone();
            x.source = (delay > 0).then_some(chain.source_period - delay);
            // Source not started yet: its first sample comes at `delay`.
            if seen.insert(x.clone()) {
                queue.push_back(x);
            }
        }
    }
    let mut best = Exact {
        data_age: 0,
        reaction: 0,
        states: 0,
    };
    let orders = permutations(n + 1);
    while let Some(st) = queue.pop_front() {
        if seen.len() > max_states {
            return None;
        }
        // One instant: the source (participant 0) and the stages act, in
        // every order.
        for order in &orders {
            let mut outs = vec![st.clone()];
            for &who in order {
                let mut next = Vec::new();
                for o in outs {
                    if who == 0 {
                        publish(chain, o, &mut next);
                    } else {
                        act(chain, who - 1, o, &mut next, &mut best);
                    }
                }
                outs = next;
            }
            for mut o in outs {
                // Time passes one unit.
                o.source = o.source.map(|a| a + 1);
                for (k, s) in o.stages.iter_mut().enumerate() {
                    s.pos += 1;
                    if s.codel < chain.stages[k].wcets.len() {
                        s.elapsed += 1;
                    }
                    s.held = s.held.map(|a| a + 1);
                }
                for p in &mut o.ports {
                    *p = p.map(|a| a + 1);
                }
                o.mark = o.mark.map(|m| m + 1);
                let over =
                    o.mark.is_some_and(|m| m > cap) || o.ports.iter().flatten().any(|&a| a > cap);
                if over {
                    return None;
                }
                if seen.insert(o.clone()) {
                    queue.push_back(o);
                }
            }
        }
    }
    best.states = seen.len();
    Some(best)
}

/// The source at this instant: it publishes when its period has passed
/// (the sample may be the marked one).
fn publish(chain: &Chain, st: State, out: &mut Vec<State>) {
    if st.source.is_none_or(|a| a >= chain.source_period) {
        let mut x = st;
        x.source = Some(0);
        if x.mark.is_none() {
            let mut marked = x.clone();
            marked.mark = Some(0);
            out.push(marked);
        }
        out.push(x);
    } else {
        out.push(st);
    }
}

/// What stage `k` may do at this instant, from `st`: its tick, then its
/// codels ending and beginning (several when they take no time).
fn act(chain: &Chain, k: usize, st: State, out: &mut Vec<State>, best: &mut Exact) {
    let spec = &chain.stages[k];
    let mut st = st;
    let s = &mut st.stages[k];
    if s.pos >= spec.period {
        // The tick: a new wake-up (the previous one's work is done, as no
        // task overruns).
        if s.codel < spec.wcets.len() {
            // Work unfinished at the tick: outside the chains' premise.
            return;
        }
        s.pos = 0;
        s.started = true;
        s.codel = 0;
        s.elapsed = 0;
        begin(chain, k, &mut st);
    }
    // Each running codel may end now (must at its WCET); the next begins
    // at once.
    let mut frontier = vec![st];
    while let Some(x) = frontier.pop() {
        let s = x.stages[k];
        if s.codel >= spec.wcets.len() {
            out.push(x);
            continue;
        }
        if s.elapsed < spec.wcets[s.codel] {
            out.push(x.clone());
        }
        let mut y = x;
        end(chain, k, &mut y, best);
        let s = &mut y.stages[k];
        s.codel += 1;
        s.elapsed = 0;
        if s.codel < spec.wcets.len() {
            begin(chain, k, &mut y);
        }
        frontier.push(y);
    }
}

/// Stage `k`'s current codel begins: the chain codel reads its input.
fn begin(chain: &Chain, k: usize, st: &mut State) {
    if st.stages[k].codel == chain.stages[k].chain {
        let input = if k == 0 { st.source } else { st.ports[k - 1] };
        st.stages[k].held = input;
    }
}

/// Stage `k`'s current codel ends: the chain codel writes its port, or,
/// for the last stage, the data reaches the sink.
fn end(chain: &Chain, k: usize, st: &mut State, best: &mut Exact) {
    if st.stages[k].codel != chain.stages[k].chain {
        return;
    }
    let held = st.stages[k].held.take();
    if k + 1 == chain.stages.len() {
        if let Some(age) = held {
            best.data_age = best.data_age.max(age);
            if let Some(m) = st.mark
                && age <= m
            {
                best.reaction = best.reaction.max(m);
                st.mark = None;
            }
        }
    } else {
        st.ports[k] = held;
    }
}

fn permutations(n: usize) -> Vec<Vec<usize>> {
    if n == 0 {
        return vec![Vec::new()];
    }
    let mut out = Vec::new();
    for p in permutations(n - 1) {
        for i in 0..=p.len() {
            let mut q = p.clone();
            q.insert(i, n - 1);
            out.push(q);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stage that reads and ends at once every unit, a source of period
    /// 2: a read at the instant of a publication may come first and see
    /// the previous sample, 2 units old; a sample is read at once, or one
    /// unit later when the read of its instant came first.
    #[test]
    fn one_instant_stage() {
        let c = Chain {
            source_period: 2,
            stages: vec![Stage {
                period: 1,
                wcets: vec![0],
                chain: 0,
            }],
        };
        let e = exact(&c, 100_000, 100).expect("small");
        assert_eq!(e.data_age, 2);
        assert_eq!(e.reaction, 1);
    }

    /// Source and stage of period 3, the chain codel's WCET 2: read at a
    /// tick that comes just before the next sample (3 units), then 2 units
    /// of codel; the reaction: the tick just missed the sample (3), then
    /// the codel (2).
    #[test]
    fn long_codel_adds_its_wcet() {
        let c = Chain {
            source_period: 3,
            stages: vec![Stage {
                period: 3,
                wcets: vec![2],
                chain: 0,
            }],
        };
        let e = exact(&c, 1_000_000, 100).expect("small");
        assert_eq!(e.data_age, 3 + 2);
        assert_eq!(e.reaction, 3 + 2);
    }
}
