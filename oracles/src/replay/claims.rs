//! What a replay ends with: the final state and what the trace showed, or
//! why a step is not allowed; and the check that the final state shows a
//! verdict's claimed violation.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt;

use genom_model::component::{Component, ServiceId};
use genom_model::trace::Event;

use super::state::{Instance, InstanceId, Phase, State};

/// Why a step (or the trace as a whole) is not allowed by the semantics.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReplayError {
    /// The 1-based number of the failing step (as the trace is displayed);
    /// 0 when the problem is the trace as a whole.
    pub step: usize,
    /// The failing step, described.
    pub what: String,
    /// Why it is wrong.
    pub why: String,
}

impl fmt::Display for ReplayError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.step == 0 {
            write!(f, "trace: {}", self.why)
        } else {
            write!(f, "step {} ({}): {}", self.step, self.what, self.why)
        }
    }
}

impl std::error::Error for ReplayError {}

/// What a request led to, as the trace says.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Fate {
    /// Rejected with this reason.
    Rejected(String),
    /// Acknowledged (the instance became pending).
    Acknowledged,
}

/// A violation the end of a trace should show.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Claim<'a> {
    /// These services are pending and wait on each other through `delays`.
    Deadlock(&'a [&'a str]),
    /// `waiter` is pending, blocked by `blocker`'s instance, which the loop
    /// keeps running forever.
    Starvation {
        /// The pending service.
        waiter: &'a str,
        /// The service whose instance never ends.
        blocker: &'a str,
    },
    /// The service is stopping and the loop keeps it stopping forever.
    UnboundedInterrupt(&'a str),
    /// The service never started in the trace, and its last request was
    /// rejected or is still pending and cannot start.
    DeadService(&'a str),
}

/// The outcome of a successful replay: the final state and what the trace
/// showed on the way.
#[derive(Debug, Clone)]
pub struct ReplayEnd {
    /// The state when the violation is reported.
    pub state: State,
    /// With `loop_start`, the state before each step of the loop and the
    /// state after its last step (equal to the first).
    pub loop_states: Vec<State>,
    /// The steps of the loop (index into the trace, service involved).
    pub loop_steps: Vec<(usize, Event, Option<ServiceId>)>,
    /// Services that started (or, without start codel, completed) at some
    /// step.
    pub started: BTreeSet<ServiceId>,
    /// What the last request of each requested service led to (for an
    /// auto service, its acknowledgment when initialisation completes).
    pub fates: BTreeMap<ServiceId, Fate>,
    /// The 1-based number of the violation step.
    pub violation_step: usize,
}

impl ReplayEnd {
    /// Checks that the end of the trace shows `claim`.
    pub fn exhibits(&self, c: &Component, claim: Claim<'_>) -> Result<(), ReplayError> {
        let fail = |why: String| ReplayError {
            step: self.violation_step,
            what: "violation".to_owned(),
            why,
        };
        let service = |name: &str| {
            c.service_named(name)
                .ok_or_else(|| fail(format!("the component has no service `{name}`")))
        };
        match claim {
            Claim::Deadlock(names) => {
                let set = names
                    .iter()
                    .map(|n| service(n))
                    .collect::<Result<Vec<_>, _>>()?;
                self.deadlock(c, &set).map_err(fail)
            }
            Claim::Starvation { waiter, blocker } => {
                let (w, b) = (service(waiter)?, service(blocker)?);
                self.starvation(c, w, b).map_err(fail)
            }
            Claim::UnboundedInterrupt(name) => {
                let s = service(name)?;
                self.unbounded(c, s).map_err(fail)
            }
            Claim::DeadService(name) => {
                let s = service(name)?;
                self.dead(c, s).map_err(fail)
            }
        }
    }

    fn deadlock(&self, c: &Component, set: &[ServiceId]) -> Result<(), String> {
        if set.len() < 2 {
            return Err("a circular wait needs at least two services".to_owned());
        }
        let name = |s: ServiceId| c.services[s].name.name.as_str();
        for &s in set {
            if self.state.pending(s).is_none() {
                return Err(format!(
                    "`{}` has no pending instance: {}",
                    name(s),
                    self.state.describe(c)
                ));
            }
            if c.services[s].max_time.is_some() {
                return Err(format!(
                    "`{}` has a max-time: its watchdog ends the pending instance, no deadlock",
                    name(s)
                ));
            }
        }
        // `s` waits for `t`: `t` is in the set, pending, and delays `s`.
        let waits = |s: ServiceId, t: ServiceId| {
            s != t
                && self.state.pending(t).is_some()
                && c.services[t].delays.iter().any(|r| r.id == s)
        };
        for &s in set {
            let mut seen = BTreeSet::from([s]);
            let mut stack = vec![s];
            while let Some(x) = stack.pop() {
                for &t in set {
                    if waits(x, t) && seen.insert(t) {
                        stack.push(t);
                    }
                }
            }
            if let Some(&t) = set.iter().find(|t| !seen.contains(t)) {
                return Err(format!(
                    "the pending instances do not wait on each other: `{}` does not wait, through `delays` of pending instances, for `{}`",
                    name(s),
                    name(t)
                ));
            }
        }
        Ok(())
    }

    fn blocked_by(
        c: &Component,
        state: &State,
        w: ServiceId,
        b: ServiceId,
    ) -> Result<InstanceId, String> {
        let name = |s: ServiceId| c.services[s].name.name.as_str();
        let Some(Instance {
            phase: Phase::Pending { waits_for },
            ..
        }) = state.pending(w)
        else {
            return Err(format!(
                "`{}` is not pending: {}",
                name(w),
                state.describe(c)
            ));
        };
        let Some(blocker) = state.started(b) else {
            return Err(format!(
                "`{}` has no started instance: {}",
                name(b),
                state.describe(c)
            ));
        };
        let delays = b != w && c.services[b].delays.iter().any(|r| r.id == w);
        if !delays && !waits_for.contains(&blocker.id) {
            return Err(format!(
                "`{}`'s pending instance is not blocked by `{}`: it neither delays it nor is an interrupted instance it waits for",
                name(w),
                name(b)
            ));
        }
        Ok(blocker.id)
    }

    fn starvation(&self, c: &Component, w: ServiceId, b: ServiceId) -> Result<(), String> {
        let name = |s: ServiceId| c.services[s].name.name.as_str();
        if c.services[w].max_time.is_some() {
            return Err(format!(
                "`{}` has a max-time: its watchdog ends the wait, it does not starve",
                name(w)
            ));
        }
        if self.loop_states.is_empty() {
            return Err(
                "a starvation trace must end with a loop that repeats forever (no loop_start)"
                    .to_owned(),
            );
        }
        let mut ids = BTreeSet::new();
        let mut waiter_ids = BTreeSet::new();
        for st in self.loop_states.iter().chain([&self.state]) {
            ids.insert(Self::blocked_by(c, st, w, b)?);
            waiter_ids.extend(st.pending(w).map(|i| i.id));
        }
        if ids.len() != 1 || waiter_ids.len() != 1 {
            return Err(
                "the loop does not keep the same instances: the blocker or the waiter changes"
                    .to_owned(),
            );
        }
        let blocker_stopping = self.loop_states[0]
            .started(b)
            .is_some_and(Instance::is_interrupted);
        if c.services[b].max_time.is_some() && !blocker_stopping {
            return Err(format!(
                "`{}` has a max-time: its watchdog would end it",
                name(b)
            ));
        }
        if !self
            .loop_steps
            .iter()
            .any(|&(_, e, s)| e == Event::CodelEnd && s == Some(b))
        {
            return Err(format!("the loop runs no codel of `{}`", name(b)));
        }
        Ok(())
    }

    fn unbounded(&self, c: &Component, s: ServiceId) -> Result<(), String> {
        let name = c.services[s].name.name.as_str();
        if self.loop_states.is_empty() {
            return Err("an unbounded-interrupt trace must end with a loop that repeats forever (no loop_start)".to_owned());
        }
        let mut ids = BTreeSet::new();
        for st in self.loop_states.iter().chain([&self.state]) {
            match st.started(s) {
                Some(
                    i @ Instance {
                        phase: Phase::Stopping { .. },
                        ..
                    },
                ) => {
                    ids.insert(i.id);
                }
                _ => {
                    return Err(format!(
                        "`{name}` is not stopping at every step of the loop: {}",
                        st.describe(c)
                    ));
                }
            }
        }
        if ids.len() != 1 {
            return Err(format!(
                "the loop does not keep the same instance of `{name}`"
            ));
        }
        if !self
            .loop_steps
            .iter()
            .any(|&(_, e, x)| e == Event::CodelEnd && x == Some(s))
        {
            return Err(format!("the loop runs no codel of `{name}`"));
        }
        Ok(())
    }

    fn dead(&self, c: &Component, s: ServiceId) -> Result<(), String> {
        let name = c.services[s].name.name.as_str();
        if self.started.contains(&s) {
            return Err(format!("`{name}` starts in this trace"));
        }
        match self.fates.get(&s) {
            None => Err(format!("the trace never requests `{name}`")),
            Some(Fate::Rejected(_)) => Ok(()),
            Some(Fate::Acknowledged) => {
                if self.state.pending(s).is_none() {
                    return Err(format!(
                        "`{name}` was acknowledged but is no longer pending: {}",
                        self.state.describe(c)
                    ));
                }
                Ok(())
            }
        }
    }
}
