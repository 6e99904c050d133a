//! Concrete timed traces. A symbolic path of the timed model is replayed
//! without extrapolation, with two kinds of extra clocks: `T`, never reset
//! (absolute time), and one snapshot clock `sᵢ` reset at step `i` and never
//! again. The final zone then holds every feasible timing of the whole
//! path at once, so any point of it gives consistent instants: step `i`
//! happens at `T − sᵢ`. No backward pass is needed.

use genom_model::trace::{Trace, TraceStep};

use super::model::{TAction, TState, TimedSystem};
use crate::dialect::system::Action;
use crate::dialect::witness::local_loop;
use crate::zones::dbm::{Dbm, lt};

/// How many extra steps the lasso of a looping trace may take per codel
/// step of the loop (wake-ups and other threads' work in between).
const LASSO_PATIENCE: usize = 64;

/// What the last state of the trace must show.
#[derive(Debug, Clone, Copy)]
pub enum Target {
    /// Any point of the state.
    Any,
    /// The watchdog clock `clock` of member `member`'s instance exceeds
    /// `max` units (time passes after the last step, ignoring that
    /// member's watchdog invariant).
    Exceeded {
        /// The member.
        member: usize,
        /// Its watchdog clock.
        clock: usize,
        /// Its max-time in units.
        max: i64,
    },
    /// Clock `clock` is above `after` units (a response clock past a
    /// deadline), time passing after the last step as the invariants allow.
    Late {
        /// The clock.
        clock: usize,
        /// The bound it must exceed, in units.
        after: i64,
    },
}

/// A concrete timed trace of `path` (from the component start), with `last`
/// appended at the final instant.
pub fn timed_trace(
    ts: &TimedSystem<'_>,
    path: &[TAction],
    target: Target,
    last: TraceStep,
) -> Trace {
    instants(ts, path, target, None, last)
}

/// A concrete timed trace of `path` followed by member `looping`'s codel
/// loop, marked as the cycle that may repeat forever. Without a loop that
/// time allows, the trace is the path alone.
pub fn timed_lasso(
    ts: &TimedSystem<'_>,
    path: &[TAction],
    looping: usize,
    last: TraceStep,
) -> Trace {
    match extend_with_loop(ts, path, looping) {
        Some((full, at)) => instants(ts, &full, Target::Any, Some(at), last),
        None => instants(ts, path, Target::Any, None, last),
    }
}

/// `path` extended with member `i`'s codel loop, and the index in the
/// result where the loop starts; the timed actions between the loop's
/// codel steps are wake-ups and other work, chosen greedily.
fn extend_with_loop(
    ts: &TimedSystem<'_>,
    path: &[TAction],
    i: usize,
) -> Option<(Vec<TAction>, usize)> {
    let mut st = ts.start(0, false, &mut None);
    for &a in path {
        st = ts.settle_with(ts.fire(&st, a, &mut None)?, false);
    }
    let (before, cycle) = local_loop(&ts.sys, &st.cfg, i);
    if cycle.is_empty() {
        return None;
    }
    let mut full = path.to_vec();
    for &a in &before {
        st = reach(ts, st, a, &mut full)?;
    }
    let at = full.len();
    for &a in &cycle {
        st = reach(ts, st, a, &mut full)?;
    }
    Some((full, at))
}

/// Fires untimed step `a` from `st`, after as few other timed actions as
/// the greedy choice finds (wake-ups first); records them all in `out`.
fn reach(
    ts: &TimedSystem<'_>,
    mut st: TState,
    a: Action,
    out: &mut Vec<TAction>,
) -> Option<TState> {
    for _ in 0..LASSO_PATIENCE {
        let mut enabled = Vec::new();
        ts.enabled(&st, &mut enabled);
        let step = |x: TAction| {
            let next = ts.settle_with(ts.fire(&st, x, &mut None)?, false);
            (!next.zone.is_empty()).then_some(next)
        };
        if let Some(next) = step(TAction::Step(a)) {
            out.push(TAction::Step(a));
            return Some(next);
        }
        let filler = enabled
            .iter()
            .filter(|x| matches!(x, TAction::WakeUp(_) | TAction::Round(_)))
            .chain(
                enabled
                    .iter()
                    .filter(|x| matches!(x, TAction::Step(Action::Begin(_) | Action::Finish(..)))),
            )
            .find_map(|&x| step(x).map(|n| (x, n)));
        let (x, next) = filler?;
        out.push(x);
        st = next;
    }
    None
}

/// The concrete instants of `path`; `loop_from` is the index in `path` of
/// the first action of the repeating cycle.
fn instants(
    ts: &TimedSystem<'_>,
    path: &[TAction],
    target: Target,
    loop_from: Option<usize>,
    mut last: TraceStep,
) -> Trace {
    let base = ts.clock_count();
    let extra = 1 + path.len();
    let mut steps = vec![TraceStep::new(
        genom_model::Event::ComponentStart,
        "the component starts",
    )];
    let mut st = ts.start(extra, false, &mut Some(&mut steps));
    // (mark, first event of that step): mark 0 is the start, mark m is
    // path step m - 1, whose snapshot clock is `base + 1 + m`.
    let mut marks = vec![(0usize, 0usize)];
    for (i, &a) in path.iter().enumerate() {
        let before = steps.len();
        let Some(mut next) = ts.fire(&st, a, &mut Some(&mut steps)) else {
            break;
        };
        next.zone.reset(base + 2 + i);
        st = ts.settle_with(next, false);
        marks.push((i + 1, before));
    }
    let mut zone = st.zone.clone();
    if let Target::Exceeded { member, clock, max } = target {
        zone = exceeded_zone(ts, &st, member, clock, max);
    }
    if let Target::Late { clock, after } = target {
        zone.constrain(0, clock, lt(-after));
    }
    let loop_start = loop_from
        .and_then(|k| marks.get(k + 1))
        .map(|&(_, first)| first);
    let Some((values, scale)) = zone.pick() else {
        steps.push(last);
        return Trace { steps, loop_start };
    };
    let now = values[base];
    let to_ns = |units_scaled: i64| {
        let ns = i128::from(units_scaled) * i128::from(ts.unit) / i128::from(scale);
        u64::try_from(ns.max(0)).unwrap_or(u64::MAX)
    };
    for (n, step) in steps.iter_mut().enumerate() {
        let m = marks
            .iter()
            .rev()
            .find(|&&(_, start)| start <= n)
            .map_or(0, |&(m, _)| m);
        let at = if m == 0 { 0 } else { now - values[base + m] };
        step.time_ns = Some(to_ns(at));
    }
    last.time_ns = Some(to_ns(now));
    steps.push(last);
    Trace { steps, loop_start }
}

/// The valuations reached by letting time pass after `st` while ignoring
/// the member's watchdog invariant, where its clock exceeds `max`.
pub fn exceeded_zone(
    ts: &TimedSystem<'_>,
    st: &TState,
    member: usize,
    clock: usize,
    max: i64,
) -> Dbm {
    let mut z = st.zone.clone();
    z.up();
    for (x, c) in ts.invariants(st, Some(member)) {
        z.upper(x, c);
    }
    z.constrain(0, clock, lt(-max));
    z
}
