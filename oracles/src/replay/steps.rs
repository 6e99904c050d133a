//! The replayer: reads a trace step by step, checking each against the
//! current state; the codel, start and reply steps (the control thread's
//! steps are in `requests`).

use std::collections::{BTreeMap, BTreeSet, VecDeque};

use genom_model::component::{CodelId, Component, Outcome, ServiceId};
use genom_model::kinds::ServiceKind;
use genom_model::trace::{Event, Trace, TraceStep};

use super::claims::{Fate, ReplayEnd, ReplayError};
use super::state::{Instance, Phase, State};

/// A step as shown in error messages: `codel-end `move::start` → `brake``.
fn describe_step(step: &TraceStep) -> String {
    let mut s = step.event.as_str().to_owned();
    match (&step.service, &step.codel) {
        (Some(svc), Some(k)) => s.push_str(&format!(" `{svc}::{k}`")),
        (Some(svc), None) => s.push_str(&format!(" `{svc}`")),
        _ => {}
    }
    if let Some(o) = &step.outcome {
        s.push_str(&format!(" → `{o}`"));
    }
    s
}

/// An open request (between `request` and `acknowledge`/`reject`).
#[derive(Debug, Clone)]
pub(super) struct OpenRequest {
    pub(super) service: ServiceId,
    /// The first of rules 1–3 that rejects it.
    pub(super) rule: Option<&'static str>,
    /// Past step 4 (accepted by the control codel, or none): interrupting.
    pub(super) accepted: bool,
}

impl OpenRequest {
    /// The control codel of the request is running (step 4, which takes
    /// time on the control thread while the other threads go on).
    pub(super) fn in_control_codel(&self, c: &Component) -> bool {
        self.rule.is_none() && !self.accepted && c.services[self.service].control.is_some()
    }
}

pub(super) struct Replayer<'c> {
    pub(super) c: &'c Component,
    pub(super) state: State,
    pub(super) replies: VecDeque<(ServiceId, String)>,
    pub(super) autos_due: Vec<ServiceId>,
    pub(super) request: Option<OpenRequest>,
    pub(super) started: BTreeSet<ServiceId>,
    pub(super) fates: BTreeMap<ServiceId, Fate>,
    pub(super) last_time: Option<u64>,
}

pub(super) type StepResult = Result<(), String>;

impl<'c> Replayer<'c> {
    pub(super) fn new(c: &'c Component) -> Self {
        let init_done = c.init_service().is_none();
        Replayer {
            c,
            state: State {
                init_done,
                instances: vec![Vec::new(); c.services.len()],
                next_id: 0,
            },
            replies: VecDeque::new(),
            autos_due: Vec::new(),
            request: None,
            started: BTreeSet::new(),
            fates: BTreeMap::new(),
            last_time: None,
        }
    }

    pub(super) fn run(mut self, trace: &Trace) -> Result<ReplayEnd, ReplayError> {
        let steps = &trace.steps;
        let whole = |why: String| ReplayError {
            step: 0,
            what: String::new(),
            why,
        };
        if steps.first().map(|s| s.event) != Some(Event::ComponentStart) {
            return Err(whole("the first step must be `component-start`".to_owned()));
        }
        let last = steps.len() - 1;
        if steps[last].event != Event::Violation {
            return Err(whole("the last step must be the `violation`".to_owned()));
        }
        if let Some(k) = trace.loop_start {
            if k == 0 || k >= last {
                return Err(whole(format!(
                    "loop_start {k} does not designate a step between component start and the violation (steps 2 to {last})"
                )));
            }
        }
        let mut loop_states = Vec::new();
        let mut loop_steps = Vec::new();
        for (k, step) in steps.iter().enumerate() {
            let fail = |why: String| ReplayError {
                step: k + 1,
                what: describe_step(step),
                why,
            };
            if trace.loop_start.is_some_and(|l| k >= l && k < last) {
                loop_states.push(self.state.clone());
                loop_steps.push((
                    k,
                    step.event,
                    step.service
                        .as_deref()
                        .and_then(|n| self.c.service_named(n)),
                ));
            }
            if let Some(t) = step.time_ns {
                if self.last_time.is_some_and(|p| t < p) {
                    return Err(fail(format!(
                        "time goes backwards ({t} ns after {} ns)",
                        self.last_time.unwrap_or(0)
                    )));
                }
                self.last_time = Some(t);
            }
            if step.event == Event::Violation && k != last {
                return Err(fail("a violation can only be the last step".to_owned()));
            }
            if step.event == Event::ComponentStart && k != 0 {
                return Err(fail(
                    "the component starts only once, at the first step".to_owned(),
                ));
            }
            self.step(step).map_err(fail)?;
        }
        if trace.loop_start.is_some() {
            loop_states.push(self.state.clone());
            let (first, end) = (&loop_states[0], &self.state);
            if first.shape(self.c) != end.shape(self.c) {
                return Err(ReplayError {
                    step: last + 1,
                    what: "violation".to_owned(),
                    why: format!(
                        "the steps from the loop start do not lead back to the state where the loop starts, so they cannot repeat forever: at the loop start {}; after the loop {}",
                        first.describe(self.c),
                        end.describe(self.c)
                    ),
                });
            }
        }
        Ok(ReplayEnd {
            state: self.state,
            loop_states,
            loop_steps,
            started: self.started,
            fates: self.fates,
            violation_step: last + 1,
        })
    }

    pub(super) fn name(&self, s: ServiceId) -> &'c str {
        &self.c.services[s].name.name
    }

    pub(super) fn codel_name(&self, k: CodelId) -> &'c str {
        &self.c.codels[k].name.name
    }

    pub(super) fn thread_name(&self, s: ServiceId) -> &'c str {
        self.c.services[s]
            .thread
            .map_or("control", |t| self.c.threads[t.id].name.name.as_str())
    }

    /// The service a step names.
    pub(super) fn service_of(&self, step: &TraceStep) -> Result<ServiceId, String> {
        let name = step.service.as_deref().ok_or("the step names no service")?;
        self.c
            .service_named(name)
            .ok_or_else(|| format!("the component has no service `{name}`"))
    }

    pub(super) fn codel_of(
        &self,
        s: ServiceId,
        step: &TraceStep,
    ) -> Result<Option<CodelId>, String> {
        match step.codel.as_deref() {
            None => Ok(None),
            Some(k) => self
                .c
                .codel_named(s, k)
                .map(Some)
                .ok_or_else(|| format!("service `{}` has no codel `{k}`", self.name(s))),
        }
    }

    pub(super) fn check_thread(&self, step: &TraceStep, expected: &str) -> StepResult {
        match step.thread.as_deref() {
            Some(t) if t != expected => {
                Err(format!("this happens on thread `{expected}`, not `{t}`"))
            }
            _ => Ok(()),
        }
    }

    pub(super) fn step(&mut self, step: &TraceStep) -> StepResult {
        if step.event != Event::Reply {
            if let Some((s, v)) = self.replies.front() {
                return Err(format!(
                    "`{}` has ended: its final reply `{v}` must come first",
                    self.name(*s)
                ));
            }
        }
        match step.event {
            Event::ComponentStart => {
                if self.state.init_done {
                    self.initialised();
                }
                Ok(())
            }
            Event::Request => self.request(step),
            Event::Accept => self.accept(step),
            Event::Reject => self.reject(step),
            Event::Interrupt => self.interrupt(step),
            Event::Acknowledge => self.acknowledge(step),
            Event::Start => self.start(step),
            Event::CodelStart => self.codel_start(step),
            Event::CodelEnd => self.codel_end(step),
            Event::Watchdog => self.watchdog(step),
            Event::Reply => self.reply(step),
            Event::WakeUp | Event::Delay | Event::Violation => self.settled(),
            Event::LockWait => Err("`lock-wait` is a GenoM3 step (its resource queue)".into()),
        }
    }

    /// Initialisation is complete: every auto service is due.
    pub(super) fn initialised(&mut self) {
        self.autos_due = self
            .c
            .services
            .iter()
            .filter(|(_, s)| s.kind == ServiceKind::Auto)
            .map(|(id, _)| id)
            .collect();
    }

    /// The state is stable: no open request (except one whose control
    /// codel runs, while the other threads go on), no owed reply or auto
    /// acknowledgment, no pending instance that can start.
    pub(super) fn settled(&self) -> StepResult {
        if let Some(r) = self
            .request
            .as_ref()
            .filter(|r| !r.in_control_codel(self.c))
        {
            return Err(format!(
                "the request for `{}` is still being handled (it must be acknowledged or rejected first)",
                self.name(r.service)
            ));
        }
        if let Some(&a) = self.autos_due.first() {
            return Err(format!(
                "initialisation is complete: auto service `{}` must start before anything else",
                self.name(a)
            ));
        }
        for (s, _) in self.c.services.iter() {
            if self.state.pending(s).is_some() && self.start_blocker(s).is_none() {
                return Err(format!(
                    "`{}` is pending and nothing stops it from starting: it must start first (step 7: as soon as it can)",
                    self.name(s)
                ));
            }
        }
        Ok(())
    }

    pub(super) fn start(&mut self, step: &TraceStep) -> StepResult {
        let s = self.service_of(step)?;
        if let Some(at) = self.autos_due.iter().position(|&a| a == s) {
            // An auto service is not a request: it gets its instance and
            // starts at once, whatever delays or forbids it (section 3).
            self.autos_due.remove(at);
            if self.state.has_instance(s) {
                return Err(format!(
                    "auto service `{}` already has an instance",
                    self.name(s)
                ));
            }
            self.new_pending(s, BTreeSet::new());
            // No client requests an auto service: its start is its fate.
            self.fates.insert(s, Fate::Acknowledged);
        } else if let Some(why) = self.start_blocker(s) {
            return Err(format!("`{}` cannot start: {why}", self.name(s)));
        }
        let codel = self.codel_of(s, step)?;
        let svc = &self.c.services[s];
        let pos = self.state.instances[s.0 as usize]
            .iter()
            .position(Instance::is_pending)
            .unwrap_or_default();
        self.started.insert(s);
        match svc.start {
            Some(start) => {
                if codel.is_some_and(|k| k != start) {
                    return Err(format!(
                        "`{}` starts at its start codel, not at `{}`",
                        self.name(s),
                        step.codel.as_deref().unwrap_or("")
                    ));
                }
                self.state.instances[s.0 as usize][pos].phase = Phase::Active {
                    codel: start,
                    running: false,
                    last_ran: None,
                    interrupted: false,
                };
            }
            None => {
                if codel.is_some() {
                    return Err(format!(
                        "`{}` has no start codel: it completes at once",
                        self.name(s)
                    ));
                }
                self.end(s, pos, "end".to_owned(), true);
            }
        }
        Ok(())
    }

    pub(super) fn codel_start(&mut self, step: &TraceStep) -> StepResult {
        self.settled()?;
        let s = self.service_of(step)?;
        let thread = self.thread_name(s);
        self.check_thread(step, thread)?;
        let Some(k) = self.codel_of(s, step)? else {
            return Err("the step names no codel".to_owned());
        };
        let pos = self.state.instances[s.0 as usize]
            .iter()
            .position(|i| i.codel() == Some(k) && i.running().is_none())
            .ok_or_else(|| {
                format!(
                    "`{}` is not ready to run `{}`: {}",
                    self.name(s),
                    self.codel_name(k),
                    self.state.describe(self.c)
                )
            })?;
        let my_thread = self.c.services[s].thread.map(|t| t.id);
        for (t, ts) in self.c.services.iter() {
            for running in self.state.of(t).iter().filter_map(Instance::running) {
                if ts.thread.map(|x| x.id) == my_thread {
                    return Err(format!(
                        "thread `{thread}` is busy running `{}::{}`: a thread runs one codel at a time",
                        ts.name.name,
                        self.codel_name(running)
                    ));
                }
                if self.c.conflicts(k, running) {
                    return Err(format!(
                        "`{}` conflicts with `{}::{}`, running on another thread: conflicting codels never run at the same time",
                        self.codel_name(k),
                        ts.name.name,
                        self.codel_name(running)
                    ));
                }
            }
        }
        if let Some(r) = self.request.as_ref().filter(|r| r.in_control_codel(self.c)) {
            let control = self.c.services[r.service].control;
            if control.is_some_and(|ctl| self.c.conflicts(k, ctl)) {
                return Err(format!(
                    "`{}` conflicts with the control codel of `{}`, running on the control thread: conflicting codels never run at the same time",
                    self.codel_name(k),
                    self.name(r.service)
                ));
            }
        }
        match &mut self.state.instances[s.0 as usize][pos].phase {
            Phase::Active { running, .. } | Phase::Stopping { running, .. } => *running = true,
            Phase::Pending { .. } => {}
        }
        Ok(())
    }

    pub(super) fn codel_end(&mut self, step: &TraceStep) -> StepResult {
        self.settled()?;
        let s = self.service_of(step)?;
        self.check_thread(step, self.thread_name(s))?;
        let Some(k) = self.codel_of(s, step)? else {
            return Err("the step names no codel".to_owned());
        };
        let pos = self.state.instances[s.0 as usize]
            .iter()
            .position(|i| i.running() == Some(k))
            .ok_or_else(|| {
                format!(
                    "`{}` is not running `{}`: {}",
                    self.name(s),
                    self.codel_name(k),
                    self.state.describe(self.c)
                )
            })?;
        let codel = &self.c.codels[k];
        let outcome = match step.outcome.as_deref() {
            None => None,
            Some(o) => Some(self.outcome_named(s, k, o)?),
        };
        let inst = self.state.instances[s.0 as usize][pos].clone();
        let interrupted_reply = if inst.by_watchdog {
            "TIMEOUT"
        } else {
            "INTERRUPTED"
        };
        let report = |r: usize| {
            self.c.services[s]
                .reports
                .get(r)
                .map_or_else(String::new, |r| r.name.clone())
        };
        // Where the instance goes: a new phase, or an ending (reply, success).
        let next: Result<Phase, (String, bool)> = match inst.phase {
            Phase::Active {
                interrupted: true, ..
            } => match codel.on_inter {
                Some(x) => Ok(Phase::Stopping {
                    codel: x.id,
                    running: false,
                }),
                None => Err((interrupted_reply.to_owned(), false)),
            },
            Phase::Active { .. } => match outcome {
                None => {
                    return Err(format!(
                        "`{}` was not interrupted: the step must give its outcome",
                        self.codel_name(k)
                    ));
                }
                Some(Outcome::Codel(x)) => Ok(Phase::Active {
                    codel: x,
                    running: false,
                    last_ran: Some(k),
                    interrupted: false,
                }),
                Some(Outcome::End) => Err(("end".to_owned(), true)),
                Some(Outcome::Report(r)) => Err((report(r), false)),
            },
            Phase::Stopping { .. } => match outcome {
                None => {
                    return Err(format!(
                        "stopping services follow the `next` of their codels: the step must give the outcome of `{}`",
                        self.codel_name(k)
                    ));
                }
                Some(Outcome::Codel(x)) => Ok(Phase::Stopping {
                    codel: x,
                    running: false,
                }),
                Some(Outcome::End) => Err((interrupted_reply.to_owned(), false)),
                Some(Outcome::Report(r)) => Err((report(r), false)),
            },
            Phase::Pending { .. } => return Err("a pending instance runs no codel".to_owned()),
        };
        match next {
            Ok(phase) => self.state.instances[s.0 as usize][pos].phase = phase,
            Err((reply, success)) => self.end(s, pos, reply, success),
        }
        Ok(())
    }

    /// The outcome `o` of codel `k`, which must be in its `next`.
    pub(super) fn outcome_named(
        &self,
        s: ServiceId,
        k: CodelId,
        o: &str,
    ) -> Result<Outcome, String> {
        let outcomes = self.c.codels[k].outcomes();
        let found = outcomes.iter().copied().find(|&x| match x {
            Outcome::End => o == "end",
            Outcome::Codel(x) => self.codel_name(x) == o,
            Outcome::Report(r) => self.c.services[s]
                .reports
                .get(r)
                .is_some_and(|r| r.name == o),
        });
        found.ok_or_else(|| {
            let names: Vec<String> = outcomes
                .iter()
                .map(|&x| match x {
                    Outcome::End => "`end`".to_owned(),
                    Outcome::Codel(x) => format!("`{}`", self.codel_name(x)),
                    Outcome::Report(r) => format!(
                        "`{}`",
                        self.c.services[s]
                            .reports
                            .get(r)
                            .map_or("?", |r| r.name.as_str())
                    ),
                })
                .collect();
            format!(
                "`{o}` is not an outcome of `{}` (its `next` is {})",
                self.codel_name(k),
                names.join(", ")
            )
        })
    }

    /// The instance at `pos` of `s` ends with `reply`.
    pub(super) fn end(&mut self, s: ServiceId, pos: usize, reply: String, success: bool) {
        self.state.instances[s.0 as usize].remove(pos);
        self.replies.push_back((s, reply));
        if success && !self.state.init_done && self.c.init_service() == Some(s) {
            self.state.init_done = true;
            self.initialised();
        }
    }

    pub(super) fn reply(&mut self, step: &TraceStep) -> StepResult {
        let s = self.service_of(step)?;
        let Some((owed, value)) = self.replies.front().cloned() else {
            return Err(format!(
                "no instance of `{}` has just ended: a final reply comes exactly once, when its instance ends",
                self.name(s)
            ));
        };
        if owed != s {
            return Err(format!(
                "`{}` has ended and must reply first (with `{value}`)",
                self.name(owed)
            ));
        }
        match step.outcome.as_deref() {
            None => {
                return Err(format!(
                    "a final reply must give its value (here `{value}`); none is given"
                ));
            }
            Some(v) if v != value => {
                return Err(format!(
                    "`{}` must reply `{value}` (how its instance ended), not `{v}`",
                    self.name(s)
                ));
            }
            Some(_) => {}
        }
        self.replies.pop_front();
        Ok(())
    }
}
