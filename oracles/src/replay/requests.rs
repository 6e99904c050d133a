//! The control thread's steps: requests, their rejection or acceptance,
//! the interrupts they cause, watchdogs, and acknowledgment.

use std::collections::BTreeSet;

use genom_model::component::{CodelId, ServiceId};
use genom_model::trace::TraceStep;

use super::claims::Fate;
use super::state::{Instance, InstanceId, Phase, interrupt_target};
use super::steps::{OpenRequest, Replayer, StepResult};

impl<'c> Replayer<'c> {
    /// Why the pending instance of `s` cannot start, or `None` if it can.
    pub(super) fn start_blocker(&self, s: ServiceId) -> Option<String> {
        let Some(Instance {
            phase: Phase::Pending { waits_for },
            ..
        }) = self.state.pending(s)
        else {
            return Some(format!("`{}` has no pending instance", self.name(s)));
        };
        for (t, ts) in self.c.services.iter() {
            if t != s && self.state.has_instance(t) && ts.delays.iter().any(|r| r.id == s) {
                return Some(format!(
                    "`{}` has an instance and delays `{}` (step 7a)",
                    ts.name.name,
                    self.name(s)
                ));
            }
        }
        for &id in waits_for {
            if let Some((t, i)) = self.state.find(id) {
                let at = i
                    .codel()
                    .map(|k| format!(" at `{}`", self.codel_name(k)))
                    .unwrap_or_default();
                return Some(format!(
                    "it still waits for the interrupted instance of `{}`{at} to end (step 7b)",
                    self.name(t)
                ));
            }
        }
        if let Some(i) = self.state.started(s) {
            let at = i
                .codel()
                .map(|k| format!(" at `{}`", self.codel_name(k)))
                .unwrap_or_default();
            return Some(format!("`{}` still has an instance{at}", self.name(s)));
        }
        None
    }

    /// The first of request rules 1–3 that rejects a request for `s`.
    pub(super) fn rule(&self, s: ServiceId) -> Option<&'static str> {
        if let Some(init) = self.c.init_service() {
            if !self.state.init_done && init != s {
                return Some("NOT_INITIALIZED");
            }
        }
        let forbidden = self.c.services.iter().any(|(t, ts)| {
            t != s && self.state.has_instance(t) && ts.forbids.iter().any(|r| r.id == s)
        });
        if forbidden {
            return Some("FORBIDDEN");
        }
        let svc = &self.c.services[s];
        if self.state.has_instance(s) && !svc.stops.iter().any(|r| r.id == s) {
            return Some("BUSY");
        }
        None
    }

    pub(super) fn request(&mut self, step: &TraceStep) -> StepResult {
        if let Some(r) = &self.request {
            return Err(format!(
                "the control thread still handles the request for `{}`: one request at a time",
                self.name(r.service)
            ));
        }
        self.settled()?;
        self.check_thread(step, "control")?;
        let s = self.service_of(step)?;
        let rule = self.rule(s);
        if rule.is_none() {
            self.control_locks(s)?;
        }
        let accepted = rule.is_none() && self.c.services[s].control.is_none();
        self.request = Some(OpenRequest {
            service: s,
            rule,
            accepted,
        });
        Ok(())
    }

    pub(super) fn open_request(
        &self,
        step: &TraceStep,
        s: ServiceId,
    ) -> Result<OpenRequest, String> {
        match &self.request {
            Some(r) if r.service == s => Ok(r.clone()),
            Some(r) => Err(format!(
                "the open request is for `{}`, not `{}`",
                self.name(r.service),
                self.name(s)
            )),
            None => Err(format!(
                "no request for `{}` is being handled",
                step.service.as_deref().unwrap_or("?")
            )),
        }
    }

    /// The control codel of `s` can take its locks now.
    pub(super) fn control_locks(&self, s: ServiceId) -> StepResult {
        let Some(control) = self.c.services[s].control else {
            return Ok(());
        };
        for (t, v) in self.c.services.iter().map(|(t, _)| (t, self.state.of(t))) {
            for k in v.iter().filter_map(Instance::running) {
                if self.c.conflicts(control, k) {
                    return Err(format!(
                        "the control codel of `{}` conflicts with `{}::{}`, which is running: it cannot run now",
                        self.name(s),
                        self.name(t),
                        self.codel_name(k)
                    ));
                }
            }
        }
        Ok(())
    }

    pub(super) fn accept(&mut self, step: &TraceStep) -> StepResult {
        let s = self.service_of(step)?;
        let r = self.open_request(step, s)?;
        self.check_thread(step, "control")?;
        if let Some(reason) = r.rule {
            return Err(format!(
                "the request must be rejected with `{reason}` before any control codel runs"
            ));
        }
        let Some(control) = self.c.services[s].control else {
            return Err(format!(
                "`{}` has no control codel to accept the request",
                self.name(s)
            ));
        };
        if r.accepted {
            return Err("the request was already accepted".to_owned());
        }
        if self.codel_of(s, step)?.is_some_and(|k| k != control) {
            return Err("only the control codel accepts a request".to_owned());
        }
        self.control_locks(s)?;
        if let Some(r) = &mut self.request {
            r.accepted = true;
        }
        Ok(())
    }

    pub(super) fn reject(&mut self, step: &TraceStep) -> StepResult {
        let s = self.service_of(step)?;
        let r = self.open_request(step, s)?;
        let Some(reason) = step.outcome.as_deref() else {
            return Err("a rejection must give its reason (NOT_INITIALIZED, FORBIDDEN, BUSY or a report) in `outcome`; none is given".to_owned());
        };
        match r.rule {
            Some(expected) if expected != reason => {
                return Err(format!(
                    "the request must be rejected with `{expected}` (the first rule of section 3 that applies), not `{reason}`"
                ));
            }
            Some(_) => {}
            None => {
                if r.accepted {
                    return Err(
                        "the request was already accepted: it cannot be rejected now".to_owned(),
                    );
                }
                if self.c.services[s].control.is_none() {
                    return Err(format!(
                        "no rule rejects this request (`{}` is not forbidden, not busy, initialisation is done) and it has no control codel: `{reason}` is not possible",
                        self.name(s)
                    ));
                }
                if self.c.services[s].report(reason).is_none() {
                    return Err(format!(
                        "no rule rejects this request, so only its control codel can, with one of `{}`'s reports; `{reason}` is not one",
                        self.name(s)
                    ));
                }
                self.control_locks(s)?;
            }
        }
        self.request = None;
        self.fates.insert(s, Fate::Rejected(reason.to_owned()));
        Ok(())
    }

    pub(super) fn interrupt(&mut self, step: &TraceStep) -> StepResult {
        let t = self.service_of(step)?;
        let Some(r) = self.request.clone() else {
            return Err(format!(
                "`{}` is interrupted but no request is being handled: only a request (step 5) or the watchdog interrupts",
                self.name(t)
            ));
        };
        let requester = &self.c.services[r.service];
        if !r.accepted {
            return Err(format!(
                "the request for `{}` is not accepted yet: interrupts come after the control codel (step 5)",
                requester.name.name
            ));
        }
        if !requester.stops.iter().any(|x| x.id == t) {
            return Err(format!(
                "`{}` does not list `{}` in `stops`: it cannot interrupt it",
                requester.name.name,
                self.name(t)
            ));
        }
        let codel = self.codel_of(t, step)?;
        self.interrupt_instance(t, codel, false)
    }

    pub(super) fn watchdog(&mut self, step: &TraceStep) -> StepResult {
        self.settled()?;
        let s = self.service_of(step)?;
        if self.c.services[s].max_time.is_none() {
            return Err(format!(
                "`{}` has no `max-time`: no watchdog can interrupt it",
                self.name(s)
            ));
        }
        let codel = self.codel_of(s, step)?;
        self.interrupt_instance(s, codel, true)
    }

    /// Interrupts the pending instance of `s` (`codel` is `None`) or its
    /// started one at `codel`.
    pub(super) fn interrupt_instance(
        &mut self,
        s: ServiceId,
        codel: Option<CodelId>,
        watchdog: bool,
    ) -> StepResult {
        let reply = if watchdog { "TIMEOUT" } else { "INTERRUPTED" };
        let v = &self.state.instances[s.0 as usize];
        let pos = match codel {
            None => v.iter().position(Instance::is_pending).ok_or_else(|| {
                format!("`{}` has no pending instance (the step names no codel, so it is about a pending one)", self.name(s))
            })?,
            Some(k) => v.iter().position(|i| i.codel() == Some(k)).ok_or_else(|| {
                format!("`{}` has no instance at `{}`: {}", self.name(s), self.codel_name(k), self.state.describe(self.c))
            })?,
        };
        let inst = &v[pos];
        if inst.is_interrupted() {
            return Err(format!(
                "`{}` is already interrupted: a stopping service is not interrupted again",
                self.name(s)
            ));
        }
        let c = self.c;
        let ends = match inst.phase.clone() {
            Phase::Pending { .. } => true,
            Phase::Active { running: true, .. } => {
                let inst = &mut self.state.instances[s.0 as usize][pos];
                if let Phase::Active { interrupted, .. } = &mut inst.phase {
                    *interrupted = true;
                }
                inst.by_watchdog = watchdog;
                false
            }
            Phase::Active {
                running: false,
                last_ran,
                ..
            } => match interrupt_target(c, last_ran) {
                Some(x) => {
                    let inst = &mut self.state.instances[s.0 as usize][pos];
                    inst.phase = Phase::Stopping {
                        codel: x,
                        running: false,
                    };
                    inst.by_watchdog = watchdog;
                    false
                }
                None => true,
            },
            Phase::Stopping { .. } => {
                return Err(format!(
                    "`{}` is stopping: it is not interrupted again",
                    self.name(s)
                ));
            }
        };
        if ends {
            self.end(s, pos, reply.to_owned(), false);
        }
        Ok(())
    }

    pub(super) fn acknowledge(&mut self, step: &TraceStep) -> StepResult {
        self.check_thread(step, "control")?;
        let s = self.service_of(step)?;
        if let Some(r) = self.request.clone() {
            if r.service != s {
                return Err(format!(
                    "the open request is for `{}`, not `{}`",
                    self.name(r.service),
                    self.name(s)
                ));
            }
            if let Some(reason) = r.rule {
                return Err(format!("the request must be rejected with `{reason}`"));
            }
            if !r.accepted {
                return Err(format!(
                    "`{}` has a control codel: it must accept the request first (step 4)",
                    self.name(s)
                ));
            }
            let mut waits_for = BTreeSet::new();
            for t in self.c.services[s].stops.iter().map(|x| x.id) {
                for i in self.state.of(t) {
                    if !i.is_interrupted() {
                        let at = i.codel().map_or_else(
                            || " (pending)".to_owned(),
                            |k| format!(" at `{}`", self.codel_name(k)),
                        );
                        return Err(format!(
                            "`{}` stops `{}`, whose instance{at} was not interrupted (step 5 comes before the acknowledgment)",
                            self.name(s),
                            self.name(t)
                        ));
                    }
                    waits_for.insert(i.id);
                }
            }
            if self.state.pending(s).is_some() {
                return Err(format!("`{}` already has a pending instance", self.name(s)));
            }
            self.new_pending(s, waits_for);
            self.request = None;
            self.fates.insert(s, Fate::Acknowledged);
            return Ok(());
        }
        Err(format!(
            "`{}` is acknowledged without a request: auto services are not acknowledged, they start when initialisation completes",
            self.name(s)
        ))
    }

    pub(super) fn new_pending(&mut self, s: ServiceId, waits_for: BTreeSet<InstanceId>) {
        let id = self.state.next_id;
        self.state.next_id += 1;
        self.state.instances[s.0 as usize].push(Instance {
            id,
            phase: Phase::Pending { waits_for },
            by_watchdog: false,
        });
    }
}
