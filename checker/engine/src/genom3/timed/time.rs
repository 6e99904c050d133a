//! Time passing in the timed GenoM3 model: urgency (a codel may begin or
//! a ticket be taken), the invariants of a state (each tick, each running
//! codel's WCET), and the zone's delay, frees and extrapolation with bounds
//! read off the state (docs/genom3-semantics.md 15.10).

use super::{TG3State, TimedEngine};

impl TimedEngine<'_> {
    /// Whether time may not pass: some codel may begin or some ticket be
    /// taken.
    pub fn urgent(&self, st: &TG3State) -> bool {
        let mut any = false;
        self.each_begin(st, &mut |_| any = true);
        any
    }

    /// The invariants of a state, as `x ≤ c`.
    pub fn invariants(&self, st: &TG3State) -> Vec<(usize, i64)> {
        let mut out = Vec::new();
        for t in (0..self.e.m.tasks.len()).filter(|&t| self.in_group[t]) {
            if let (Some(x), Some(p)) = (self.period_clock[t], self.period[t]) {
                let first = st.ticked >> t & 1 == 0;
                out.push((x, if first { self.delay[t] } else { p }));
            }
            if let Some((who, i)) = self.running(&st.g, t) {
                if let Some(w) = self.locks.wcet(who.owner(), i.state) {
                    out.push((self.exec_clock[t], w));
                }
            }
        }
        if st.ctl.is_some_and(|c| c.running) {
            if let Some(w) = self.ctl_codel(st).and_then(|k| self.locks.wcet_of(k)) {
                out.push((self.ctl_clock, w));
            }
        }
        out
    }

    /// Lets time pass (unless urgent or violated) under the invariants,
    /// frees the clocks of idle tasks, extrapolates.
    pub fn let_time_pass(&self, mut st: TG3State) -> TG3State {
        if st.violation.is_none() && !self.urgent(&st) {
            st.zone.up();
        }
        for (x, c) in self.invariants(&st) {
            st.zone.upper(x, c);
        }
        for t in 0..self.e.m.tasks.len() {
            if self.running(&st.g, t).is_none() {
                st.zone.free(self.exec_clock[t]);
            }
            if let (false, Some(x)) = (self.in_group[t], self.period_clock[t]) {
                st.zone.free(x);
            }
        }
        if !st.ctl.is_some_and(|c| c.running) {
            st.zone.free(self.ctl_clock);
        }
        self.free_responses(&mut st);
        // Only zones of the model's own clocks: a trace's zone has more
        // (snapshot clocks, whose exact values it needs).
        let own = st.zone.clocks() == self.clock_count();
        if own && !st.zone.is_empty() {
            let (lower, upper) = self.local_bounds(&st);
            st.zone.extrapolate(&lower, &upper);
        }
        st
    }

    /// The extrapolation bounds of `st`'s clocks (`docs/genom3-semantics.md`
    /// 15.10): per clock, the largest constant it is compared with from
    /// below and from above *before it is next reset*, read off the state.
    /// A period clock keeps the model's bounds (its tick). A task's or the
    /// control thread's execution clock is compared only with the codel it
    /// runs: from below with that codel's least duration (an `async`
    /// codel's WCET, else 0: no guard), from above with its WCET (the
    /// invariant, and the overrun test at a tick); once the codel ends, the
    /// clock is free until the next codel begins and resets it. So a long
    /// codel elsewhere in the task does not keep every short codel's clock
    /// exact up to its own length, and an execution clock's lower bounds
    /// are forgotten past its least duration (Behrmann, Bouyer, Larsen and
    /// Pelánek's LU extrapolation, with bounds per discrete state: exact
    /// for reachability, and every path of the abstract graph runs
    /// concretely).
    fn local_bounds(&self, st: &TG3State) -> (Vec<Option<i64>>, Vec<Option<i64>>) {
        let mut lower = self.bounds.clone();
        let mut upper = self.upper.clone();
        let mut set = |clock: usize, l: i64, u: Option<i64>| {
            lower[clock - 1] = Some(l);
            upper[clock - 1] = u;
        };
        for t in 0..self.e.m.tasks.len() {
            match self.running(&st.g, t) {
                Some((who, i)) => set(
                    self.exec_clock[t],
                    self.locks.lower(who.owner(), i.state),
                    self.locks.wcet(who.owner(), i.state),
                ),
                None => set(self.exec_clock[t], 0, Some(0)),
            }
        }
        let running = st.ctl.filter(|c| c.running).and(self.ctl_codel(st));
        set(
            self.ctl_clock,
            0,
            Some(running.and_then(|k| self.locks.wcet_of(k)).unwrap_or(0)),
        );
        (lower, upper)
    }
}
