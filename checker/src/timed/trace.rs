//! Concrete timed traces. A symbolic path of the timed model is replayed
//! without extrapolation, with two kinds of extra clocks: `T`, never reset
//! (absolute time), and one snapshot clock `sᵢ` reset at step `i` and never
//! again. The final zone then holds every feasible timing of the whole
//! path at once, so any point of it gives consistent instants: step `i`
//! happens at `T − sᵢ`. No backward pass is needed.

use genom_model::trace::{Trace, TraceStep};

use super::model::{TAction, TState, TimedSystem};
use crate::zones::dbm::{Dbm, lt};

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
}

/// A concrete timed trace of `path` (from the component start), with `last`
/// appended at the final instant.
pub fn timed_trace(
    ts: &TimedSystem<'_>,
    path: &[TAction],
    target: Target,
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
    let Some((values, scale)) = zone.pick() else {
        steps.push(last);
        return Trace {
            steps,
            loop_start: None,
        };
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
    Trace {
        steps,
        loop_start: None,
    }
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
