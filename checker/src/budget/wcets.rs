//! WCET edits of a component: the search grid, one codel's WCET changed,
//! every WCET scaled.

use genom_model::component::{CodelId, Component, Duration};
use genom_model::kinds::CodelKind;

use crate::timed::clocks::gcd;

/// Steps of the scale factor per unit: `λ` is a multiple of 1/1000.
pub const SCALE_STEPS: u64 = 1000;

/// The grid of the searches: the GCD of every duration of the component.
pub fn grid_ns(c: &Component) -> u64 {
    let mut g = 0;
    for t in c.threads.values() {
        g = gcd(g, t.period.map_or(0, |p| p.ns));
    }
    for s in c.services.values() {
        g = gcd(g, s.max_time.map_or(0, |m| m.ns));
    }
    for k in c.codels.values() {
        g = gcd(g, k.wcet.map_or(0, |w| w.ns));
    }
    g.max(1)
}

/// `c` with the WCETs of `set` changed (`None`: no WCET).
pub fn with_wcets(c: &Component, set: &[(CodelId, Option<u64>)]) -> Component {
    let mut out = c.clone();
    for &(k, ns) in set {
        let codel = &mut out.codels[k];
        let span = codel.wcet.map_or(codel.name.span, |w| w.span);
        codel.wcet = ns.map(|ns| Duration { ns, span });
    }
    out
}

/// `c` with every WCET multiplied by `steps`/[`SCALE_STEPS`] and rounded
/// down to whole nanoseconds.
pub fn scaled(c: &Component, steps: u64) -> Component {
    let set: Vec<(CodelId, Option<u64>)> = c
        .codels
        .iter()
        .map(|(k, codel)| (k, codel.wcet.map(|w| scale_ns(w.ns, steps))))
        .collect();
    with_wcets(c, &set)
}

fn scale_ns(ns: u64, steps: u64) -> u64 {
    let v = u128::from(ns) * u128::from(steps) / u128::from(SCALE_STEPS);
    u64::try_from(v).unwrap_or(u64::MAX)
}

/// The period of the thread that runs codel `k` (not for control codels).
pub(super) fn period_of(c: &Component, k: CodelId) -> Option<u64> {
    let codel = &c.codels[k];
    if codel.kind == CodelKind::Control {
        return None;
    }
    let t = c.services[codel.service].thread?;
    c.threads[t.id].period.map(|p| p.ns)
}
