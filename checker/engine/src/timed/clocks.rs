//! The clocks of the timed model and their integer scale: every duration of
//! the component (periods, codel WCETs, service and control max-times) is
//! divided by their greatest common divisor, so zone constants are small
//! integers; and the maximal constants each clock is compared with (the LU
//! bounds used by extrapolation).

use genom_model::component::{Component, ServiceId, ThreadId};

/// Greatest common divisor.
pub fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// The time unit of the timed model, in nanoseconds: the GCD of every
/// duration that matters for `services`, or 1 ns when there is none.
pub fn unit_ns(c: &Component, services: &[ServiceId]) -> u64 {
    let mut g = 0;
    for &s in services {
        let svc = &c.services[s];
        if let Some(t) = svc.thread.and_then(|t| c.threads[t.id].period) {
            g = gcd(g, t.ns);
        }
        if let Some(m) = svc.max_time.filter(|_| c.services[s].start.is_some()) {
            g = gcd(g, m.ns);
        }
        for &k in &svc.codels {
            if let Some(w) = c.codels[k].wcet {
                g = gcd(g, w.ns);
            }
        }
    }
    g.max(1)
}

/// Converts a duration to model units (exact: the unit divides it).
pub fn units(ns: u64, unit: u64) -> i64 {
    i64::try_from(ns / unit.max(1)).unwrap_or(i64::MAX / 4)
}

/// What a clock measures.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ClockRole {
    /// Time since the last wake-up of a periodic thread.
    Period(ThreadId),
    /// Time since the running codel of a thread started.
    Exec(Option<ThreadId>),
    /// Time since the acknowledgment of a service's (main) instance.
    Watch(ServiceId),
    /// Time since the acknowledgment of a self-stopping service's pending
    /// instance (while the old instance stops).
    WatchPending(ServiceId),
    /// Time since the acknowledgment of a service's tracked instance (its
    /// response time, while it has not replied: see `timed::response`).
    Response(ServiceId),
    /// Time since the acknowledgment of a self-stopping service's pending
    /// instance, for its response time.
    ResponsePending(ServiceId),
}

/// The clocks, numbered from 1 (0 is the reference clock of zones).
#[derive(Debug, Clone, Default)]
pub struct Clocks {
    /// Role of clock `i + 1`.
    pub roles: Vec<ClockRole>,
    /// Largest constant each clock is compared with from below (L).
    pub lower: Vec<Option<i64>>,
    /// Largest constant each clock is compared with from above (U).
    pub upper: Vec<Option<i64>>,
}

impl Clocks {
    /// Adds a clock compared with `l` from below and `u` from above;
    /// returns its index (from 1).
    pub fn add(&mut self, role: ClockRole, l: Option<i64>, u: Option<i64>) -> usize {
        self.roles.push(role);
        self.lower.push(l);
        self.upper.push(u);
        self.roles.len()
    }

    /// Number of clocks.
    pub fn len(&self) -> usize {
        self.roles.len()
    }

    /// True without clocks.
    pub fn is_empty(&self) -> bool {
        self.roles.is_empty()
    }

    /// Raises the upper bound of clock `x` to at least `u`.
    pub fn raise_upper(&mut self, x: usize, u: i64) {
        if let Some(slot) = self.upper.get_mut(x - 1) {
            *slot = Some(slot.map_or(u, |v| v.max(u)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_unit_is_the_gcd_of_durations() {
        assert_eq!(gcd(10_000_000, 4_000_000), 2_000_000);
        assert_eq!(gcd(0, 7), 7);
        assert_eq!(units(10_000_000, 2_000_000), 5);
    }
}
