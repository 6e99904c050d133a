//! An independent replay of the GenoM3 engine's traces against GenoM3's
//! execution rules (`docs/genom3-semantics.md` sections 1-10, untimed).
//!
//! It shares no code with the engine it checks (`crate::genom3`): it reads
//! only the resolved [`Component`] (threads, services, their `stops`, and
//! the GenoM3 facts of [`Component::genom3`]: task and activity codel state
//! machines, `after`/`before`, the built-in `genom` services) and the
//! trace, and re-applies the rules on a plain state: the phase of the
//! component (boot, run, drain after `kill`, the stop of the permanent
//! activities, stopped, failed), the services completed successfully, each
//! task's permanent activity and a list of activity instances (delayed,
//! ready, running or stopping, at a state).
//!
//! Checked, step by step (steps numbered from 1):
//! - `component-start` first, `violation` (if any) last;
//! - boot: tasks run their first permanent codel in declaration order,
//!   requests only once all booted, an exception there fails the start;
//! - `reject` (thread `control`, outcome `genom::disallowed`): a request
//!   that `after`/`before` refuse; nothing changes;
//! - `accept` (thread `control`): `after`/`before`, the task's slot pool,
//!   `interrupts` flagging (not started: ends; running: to `stop` or ends;
//!   stopping: untouched), the `pending` outcome exactly when the new
//!   instance waits for a stopping one; functions and attributes complete
//!   and flag their targets; `kill` flags everything and drains;
//! - `interrupt` (`abort_activity`): one instance, not a stopping one;
//! - `start`: a ready instance goes to `start` (or completes without one)
//!   and runs that codel at once: the next step is its `codel-end` there;
//! - `codel-end`: a started instance (or the task's permanent activity) at
//!   that state, an outcome among the state's yields (`pause::` included)
//!   or `exception`;
//! - after every end, pending interrupters re-examined (each waiting
//!   instance no longer delayed becomes ready, as GenoM3's control thread
//!   does: docs 5.3); after the drain, the permanent stop codels last task
//!   first, then stopped;
//! - a lasso (`loop_start`): `codel-end` steps of one owner, unpaused
//!   yields chained state to state, back to where the loop starts.
//!
//! A trace does not say which instance of an activity a step moves. Equal
//! instances are interchangeable; when instances of different status match
//! (a running and a stopping one at one state, a delayed and a ready one),
//! every choice is kept, and a step fails only when it fits none.

use genom_model::component::genom3::FsmCodel;
use genom_model::component::{Component, Idx};
use genom_model::trace::{Event, Trace, TraceStep};

/// Slots of a task (its permanent activity included), as genom3-ros.
const POOL: usize = 32;

/// A state of a codel state machine: its name and its codel's yields
/// (target state, `pause::`).
#[derive(Debug)]
struct StateDef {
    name: String,
    yields: Vec<(String, bool)>,
}

/// A codel state machine: an activity's, or a task's permanent one.
#[derive(Debug, Default)]
struct Fsm {
    states: Vec<StateDef>,
}

impl Fsm {
    /// The states of `codels`; a codel runs in each state it names.
    fn new<'c>(codels: impl Iterator<Item = &'c FsmCodel>) -> Fsm {
        let mut fsm = Fsm::default();
        for codel in codels {
            for s in &codel.states {
                let yields = codel.yields.iter().map(|y| (y.state.name.clone(), y.pause));
                if fsm.get(&s.name).is_none() {
                    let name = s.name.clone();
                    fsm.states.push(StateDef {
                        name,
                        yields: yields.collect(),
                    });
                }
            }
        }
        fsm
    }

    fn get(&self, name: &str) -> Option<&StateDef> {
        self.states.iter().find(|s| s.name == name)
    }

    fn has(&self, name: &str) -> bool {
        self.get(name).is_some()
    }
}

/// A task: its name and permanent state machine (`None`: no codel).
#[derive(Debug)]
struct TaskDef {
    name: String,
    fsm: Option<Fsm>,
}

/// A service. An activity has a task and a state machine.
#[derive(Debug)]
struct ServiceDef {
    name: String,
    task: Option<usize>,
    fsm: Fsm,
    /// A service of the built-in `genom` interface.
    builtin: bool,
    after: Vec<usize>,
    before: Vec<usize>,
    /// The activities its `interrupts` names.
    stops: Vec<usize>,
}

/// The component as this replay reads it (services by index).
#[derive(Debug)]
struct Rules {
    tasks: Vec<TaskDef>,
    services: Vec<ServiceDef>,
}

impl Rules {
    fn new(c: &Component) -> Result<Rules, String> {
        let g = c.genom3.as_deref().ok_or("not a GenoM3 component")?;
        let mut tasks = Vec::new();
        for (tid, t) in c.threads.iter() {
            let mine = g.tasks.iter().filter(|k| k.thread == tid);
            let codels: Vec<&FsmCodel> = mine.flat_map(|k| &k.codels).collect();
            let fsm = (!codels.is_empty()).then(|| Fsm::new(codels.into_iter()));
            let name = t.name.name.clone();
            tasks.push(TaskDef { name, fsm });
        }
        let threads: Vec<_> = c.threads.ids().collect();
        let mut services = Vec::new();
        for (sid, s) in c.services.iter() {
            let info = g.services.iter().find(|i| i.service == sid);
            let refs = |after: bool| -> Vec<usize> {
                let v = info.map(|i| if after { &i.after } else { &i.before });
                v.into_iter().flatten().map(|r| r.id.index()).collect()
            };
            let codels = g.codels.iter().filter(|i| s.codels.contains(&i.codel));
            services.push(ServiceDef {
                name: s.name.name.clone(),
                task: s
                    .thread
                    .and_then(|r| threads.iter().position(|&t| t == r.id)),
                fsm: Fsm::new(codels.map(|i| &i.fsm)),
                builtin: info.is_some_and(|i| i.interface.as_deref() == Some("genom")),
                after: refs(true),
                before: refs(false),
                stops: Vec::new(),
            });
        }
        for (k, s) in c.services.values().enumerate() {
            for r in &s.stops {
                let t = r.id.index();
                let activity = services.get(t).is_some_and(|d| d.task.is_some());
                if activity && !services[k].stops.contains(&t) {
                    services[k].stops.push(t);
                }
            }
        }
        Ok(Rules { tasks, services })
    }

    fn service(&self, name: Option<&str>) -> Result<usize, String> {
        let name = name.ok_or("the step names no service")?;
        let found = self.services.iter().position(|s| s.name == name);
        found.ok_or_else(|| format!("there is no service `{name}`"))
    }

    fn activity(&self, name: Option<&str>) -> Result<usize, String> {
        let s = self.service(name)?;
        match self.services[s].task {
            Some(_) => Ok(s),
            None => Err(format!("`{}` is not an activity", self.services[s].name)),
        }
    }

    fn builtin(&self, name: &str) -> Option<usize> {
        self.services
            .iter()
            .position(|s| s.builtin && s.name == name)
    }

    /// The step runs on the task of activity `a` (when it names one).
    fn on_task(&self, step: &TraceStep, a: usize) -> Result<(), String> {
        let task = &self.tasks[self.services[a].task.unwrap_or_default()].name;
        match step.thread.as_deref() {
            Some(t) if t != task => Err(format!("that activity runs on task `{task}`")),
            _ => Ok(()),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    Boot,
    Run,
    Drain,
    /// The permanent activity of this task runs its stop path.
    PermStop(usize),
    Stopped,
    Failed,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Status {
    Delayed,
    Ready,
    Run,
    Stop,
}

/// An instance of an activity (a service index).
#[derive(Debug, Clone, PartialEq, Eq)]
struct Instance {
    service: usize,
    status: Status,
    /// The state whose codel runs next (empty before it starts).
    state: String,
}

impl Instance {
    fn started(&self) -> bool {
        matches!(self.status, Status::Run | Status::Stop)
    }
}

/// One possible state of the component.
#[derive(Debug, Clone, PartialEq, Eq)]
struct World {
    phase: Phase,
    /// Tasks booted so far, in declaration order.
    booted: usize,
    /// Per service: completed successfully once.
    done: Vec<bool>,
    /// Per task: the state of its permanent activity, if it has one.
    perm: Vec<Option<String>>,
    instances: Vec<Instance>,
}

/// What a codel yields.
enum Outcome {
    To(String),
    Ether,
    Exception,
}

fn phase_name(p: Phase) -> &'static str {
    match p {
        Phase::Boot => "is still starting",
        Phase::Run => "is running",
        Phase::Drain => "is shutting down (kill)",
        Phase::PermStop(_) => "is stopping its tasks",
        Phase::Stopped => "has stopped",
        Phase::Failed => "failed to start",
    }
}

impl World {
    fn initial(r: &Rules) -> World {
        let has_start = |t: &TaskDef| t.fsm.as_ref().is_some_and(|f| f.has("start"));
        let start = |t| has_start(t).then(|| "start".to_owned());
        let mut w = World {
            phase: Phase::Boot,
            booted: 0,
            done: vec![false; r.services.len()],
            perm: r.tasks.iter().map(start).collect(),
            instances: Vec::new(),
        };
        w.settle(r, false);
        w
    }

    /// Equal up to the order of instances.
    fn same(&self, o: &World) -> bool {
        let head = (self.phase, self.booted, &self.done, &self.perm);
        if head != (o.phase, o.booted, &o.done, &o.perm)
            || self.instances.len() != o.instances.len()
        {
            return false;
        }
        let mut rest: Vec<&Instance> = o.instances.iter().collect();
        for i in &self.instances {
            let Some(p) = rest.iter().position(|j| *j == i) else {
                return false;
            };
            rest.swap_remove(p);
        }
        true
    }

    /// Whether `after`/`before` let service `s` run.
    fn admissible(&self, r: &Rules, s: usize) -> Result<(), String> {
        let d = &r.services[s];
        let me = &d.name;
        if let Some(&x) = d.after.iter().find(|&&x| !self.done[x]) {
            let x = &r.services[x].name;
            return Err(format!("`{me}` is `after {x}`, which never completed"));
        }
        if let Some(&x) = d.before.iter().find(|&&x| self.done[x]) {
            let x = &r.services[x].name;
            return Err(format!("`{me}` is `before {x}`, which completed already"));
        }
        Ok(())
    }

    /// Interrupts instance `i`: not started, it ends; running, it goes to
    /// `stop` (or ends without one); stopping, nothing changes.
    fn interrupted(r: &Rules, i: Instance) -> Option<Instance> {
        match i.status {
            Status::Delayed | Status::Ready => None,
            Status::Run if r.services[i.service].fsm.has("stop") => Some(Instance {
                status: Status::Stop,
                state: "stop".into(),
                ..i
            }),
            Status::Run => None,
            Status::Stop => Some(i),
        }
    }

    /// Interrupts every instance of activity `a` (`spare`: not those not
    /// started yet). Returns whether one of them is stopping afterwards.
    fn flag(&mut self, r: &Rules, a: usize, spare: bool) -> bool {
        let mut kept = Vec::new();
        for i in std::mem::take(&mut self.instances) {
            if i.service != a || (spare && !i.started()) {
                kept.push(i);
            } else {
                kept.extend(World::interrupted(r, i));
            }
        }
        self.instances = kept;
        let stopping = |i: &Instance| i.service == a && i.status == Status::Stop;
        self.instances.iter().any(stopping)
    }

    /// What follows a transition at once: boot progress, pending
    /// interrupters re-examined after an end, the shutdown sequence.
    fn settle(&mut self, r: &Rules, ended: bool) {
        if self.phase == Phase::Boot {
            while self.booted < r.tasks.len() && self.perm[self.booted].is_none() {
                self.booted += 1;
            }
            if self.booted == r.tasks.len() {
                self.phase = Phase::Run;
            }
        }
        // Repeated while the re-examination itself ends instances.
        let mut again = ended;
        while again {
            let count = self.instances.len();
            for (a, d) in r.services.iter().enumerate() {
                let pending = |i: &Instance| i.service == a && !i.started();
                let pending = self.instances.iter().any(pending);
                if !pending || d.stops.is_empty() {
                    continue;
                }
                let mut wait = false;
                for &t in &d.stops {
                    wait |= self.flag(r, t, t == a);
                }
                for i in self.instances.iter_mut().filter(|i| i.service == a) {
                    if i.status == Status::Delayed && !wait {
                        i.status = Status::Ready;
                    }
                }
            }
            again = self.instances.len() < count;
        }
        if self.phase == Phase::Drain && self.instances.is_empty() {
            self.perm.iter_mut().for_each(|p| *p = None);
            self.next_perm_stop(r, r.tasks.len());
        }
        if let Phase::PermStop(t) = self.phase {
            if self.perm[t].is_none() {
                self.next_perm_stop(r, t);
            }
        }
    }

    /// The last task before `below` with a permanent `stop` state goes to
    /// it; none left: stopped.
    fn next_perm_stop(&mut self, r: &Rules, below: usize) {
        let has_stop = |t: &usize| r.tasks[*t].fsm.as_ref().is_some_and(|f| f.has("stop"));
        match (0..below).rev().find(has_stop) {
            Some(t) => {
                self.perm[t] = Some("stop".into());
                self.phase = Phase::PermStop(t);
            }
            None => self.phase = Phase::Stopped,
        }
    }

    /// Checks a request for service `s` can be handled now.
    fn request(&self, r: &Rules, step: &TraceStep, s: usize) -> Result<(), String> {
        if step.thread.as_deref() != Some("control") {
            return Err("requests are handled by the `control` thread".into());
        }
        if self.phase != Phase::Run {
            let now = phase_name(self.phase);
            return Err(format!("no request is handled: the component {now}"));
        }
        self.admissible(r, s)
    }

    /// `reject` with `genom::disallowed`: a request that `after`/`before`
    /// refuse (the state does not change).
    fn reject(&self, r: &Rules, step: &TraceStep) -> Result<Vec<World>, String> {
        let s = r.service(step.service.as_deref())?;
        if step.outcome.as_deref() != Some("genom::disallowed") {
            return Err("a refused request replies `genom::disallowed`".into());
        }
        if step.thread.as_deref() != Some("control") || self.phase != Phase::Run {
            return Err(
                "requests are handled by the `control` thread once the component runs".into(),
            );
        }
        match self.admissible(r, s) {
            Ok(()) => Err(format!(
                "`{}` is not refused: `after`/`before` allow it",
                r.services[s].name
            )),
            Err(_) => Ok(vec![self.clone()]),
        }
    }

    /// `accept`: a new instance of an activity, or a function, attribute
    /// or `kill` that runs and succeeds.
    fn accept(&self, r: &Rules, step: &TraceStep) -> Result<Vec<World>, String> {
        let s = r.service(step.service.as_deref())?;
        self.request(r, step, s)?;
        let d = &r.services[s];
        let mut n = self.clone();
        let count = n.instances.len();
        if let Some(task) = d.task {
            let mine = |i: &&Instance| r.services[i.service].task == Some(task);
            if n.instances.iter().filter(mine).count() + usize::from(n.perm[task].is_some()) >= POOL
            {
                return Err(format!("task `{}` has no free slot", r.tasks[task].name));
            }
            let mut wait = false;
            for &t in &d.stops {
                wait |= n.flag(r, t, false);
            }
            let pending = match step.outcome.as_deref() {
                None => false,
                Some("pending") => true,
                Some(o) => return Err(format!("an accepted request has no outcome `{o}`")),
            };
            if wait != pending {
                let not = if wait { "" } else { "not " };
                let me = &d.name;
                return Err(format!("the new instance of `{me}` is {not}`pending`"));
            }
            let status = if wait { Status::Delayed } else { Status::Ready };
            let state = String::new();
            n.instances.push(Instance {
                service: s,
                status,
                state,
            });
            let ended = n.instances.len() <= count;
            n.settle(r, ended);
            return Ok(vec![n]);
        }
        if r.builtin("abort_activity") == Some(s) || step.outcome.is_some() {
            return Err(format!(
                "a call of `{}` is accepted with no outcome",
                d.name
            ));
        }
        n.done[s] = true;
        let kill = r.builtin("kill") == Some(s);
        for a in 0..r.services.len() {
            if (kill && r.services[a].task.is_some()) || d.stops.contains(&a) {
                n.flag(r, a, false);
            }
        }
        if kill {
            n.phase = Phase::Drain;
        }
        let ended = n.instances.len() < count;
        n.settle(r, ended);
        Ok(vec![n])
    }

    /// Positions of the instances of `a` that `fits` accepts, one per
    /// distinct instance (equal ones are interchangeable).
    fn candidates(&self, a: usize, fits: impl Fn(&Instance) -> bool) -> Vec<usize> {
        let mut out: Vec<usize> = Vec::new();
        for (p, i) in self.instances.iter().enumerate() {
            if i.service == a && fits(i) && !out.iter().any(|&q| self.instances[q] == *i) {
                out.push(p);
            }
        }
        out
    }

    /// `abort_activity` flags one instance (`codel`: its state if started).
    fn abort(&self, r: &Rules, step: &TraceStep) -> Result<Vec<World>, String> {
        let k = r.builtin("abort_activity");
        let k = k.ok_or("there is no `abort_activity`")?;
        self.request(r, step, k)?;
        if step.outcome.as_deref() != Some("abort_activity") {
            return Err("an `interrupt` is an `abort_activity` (its outcome)".into());
        }
        let a = r.activity(step.service.as_deref())?;
        let fits = |i: &Instance| match step.codel.as_deref() {
            Some(c) => i.status == Status::Run && i.state == c,
            None => !i.started(),
        };
        let mut out = Vec::new();
        for p in self.candidates(a, fits) {
            let mut n = self.clone();
            n.done[k] = true;
            let i = n.instances.remove(p);
            n.instances.extend(World::interrupted(r, i));
            let ended = n.instances.len() < self.instances.len();
            n.settle(r, ended);
            out.push(n);
        }
        if out.is_empty() {
            let at = step.codel.as_deref().map(|c| format!(" running at `{c}`"));
            let at = at.unwrap_or_else(|| " not started".into());
            return Err(format!("no instance of `{}` is{at}", r.services[a].name));
        }
        Ok(out)
    }

    /// `start`: a ready instance goes to its `start` state, or completes
    /// at once without one.
    fn start(&self, r: &Rules, step: &TraceStep) -> Result<Vec<World>, String> {
        let a = r.activity(step.service.as_deref())?;
        r.on_task(step, a)?;
        let d = &r.services[a];
        let has_start = d.fsm.has("start");
        if step.codel.is_some() && step.codel.as_deref() != has_start.then_some("start") {
            return Err(format!("`{}` does not start at that state", d.name));
        }
        let ready = |i: &Instance| i.service == a && i.status == Status::Ready;
        let ready = self.instances.iter().position(ready);
        let p = ready.ok_or_else(|| format!("no instance of `{}` is ready to start", d.name))?;
        let mut n = self.clone();
        if has_start {
            n.instances[p].status = Status::Run;
            n.instances[p].state = "start".into();
        } else {
            n.instances.remove(p);
            n.done[a] = true;
        }
        n.settle(r, !has_start);
        Ok(vec![n])
    }

    /// `codel-end`: the codel of a started instance of an activity at a
    /// state, or of a task's permanent activity, ends with an outcome.
    fn codel(&self, r: &Rules, step: &TraceStep) -> Result<Vec<World>, String> {
        if matches!(self.phase, Phase::Stopped | Phase::Failed) {
            let now = phase_name(self.phase);
            return Err(format!("no codel runs: the component {now}"));
        }
        let state = step.codel.as_deref().ok_or("the step names no state")?;
        let text = step.outcome.as_deref().ok_or("the step has no outcome")?;
        if step.service.is_none() {
            return self.perm_codel(r, step, state);
        }
        let a = r.activity(step.service.as_deref())?;
        r.on_task(step, a)?;
        let name = &r.services[a].name;
        let outcome =
            outcome(&r.services[a].fsm, state, text).map_err(|e| format!("`{name}`: {e}"))?;
        let mut out = Vec::new();
        for p in self.candidates(a, |i| i.started() && i.state == state) {
            let mut n = self.clone();
            match &outcome {
                Outcome::To(to) => n.instances[p].state.clone_from(to),
                Outcome::Ether | Outcome::Exception => {
                    n.instances.remove(p);
                    n.done[a] |= matches!(outcome, Outcome::Ether);
                }
            }
            let ended = n.instances.len() < self.instances.len();
            n.settle(r, ended);
            out.push(n);
        }
        if out.is_empty() {
            return Err(format!(
                "no started instance of `{name}` is at state `{state}`"
            ));
        }
        Ok(out)
    }

    /// A codel of task `step.thread`'s permanent activity.
    fn perm_codel(&self, r: &Rules, step: &TraceStep, state: &str) -> Result<Vec<World>, String> {
        let task = step.thread.as_deref().ok_or("the step names no task")?;
        let text = step.outcome.as_deref().unwrap_or_default();
        let t = r.tasks.iter().position(|t| t.name == task);
        let t = t.ok_or_else(|| format!("there is no task `{task}`"))?;
        let fsm = r.tasks[t].fsm.as_ref();
        let fsm = fsm.ok_or_else(|| format!("task `{task}` has no codel"))?;
        let outcome = outcome(fsm, state, text).map_err(|e| format!("task `{task}`: {e}"))?;
        if self.perm[t].as_deref() != Some(state) {
            return Err(format!(
                "task `{task}`'s permanent activity is not at `{state}`"
            ));
        }
        if self.phase == Phase::Boot && t > self.booted {
            return Err(format!(
                "task `{task}` runs before the tasks before it started"
            ));
        }
        let booting = self.phase == Phase::Boot && t == self.booted;
        let mut n = self.clone();
        match outcome {
            Outcome::To(to) => n.perm[t] = Some(to),
            Outcome::Exception if booting => n.phase = Phase::Failed,
            Outcome::Ether | Outcome::Exception => n.perm[t] = None,
        }
        n.booted += usize::from(booting);
        n.settle(r, false);
        Ok(vec![n])
    }

    /// Every state `step` may lead to.
    fn step(&self, r: &Rules, step: &TraceStep) -> Result<Vec<World>, String> {
        match step.event {
            Event::Accept => self.accept(r, step),
            Event::Reject => self.reject(r, step),
            Event::Interrupt => self.abort(r, step),
            Event::Start => self.start(r, step),
            Event::CodelEnd => self.codel(r, step),
            Event::ComponentStart => Err("`component-start` is only the first step".into()),
            e => Err(format!("`{}` is no step of the GenoM3 engine", e.as_str())),
        }
    }
}

/// Outcome `text` of the codel of `state` in `fsm`: a yield, or
/// `exception`.
fn outcome(fsm: &Fsm, state: &str, text: &str) -> Result<Outcome, String> {
    let def = fsm.get(state);
    let def = def.ok_or_else(|| format!("there is no state `{state}`"))?;
    if text == "exception" {
        return Ok(Outcome::Exception);
    }
    let to = text.strip_prefix("pause::");
    let (to, pause) = to.map_or((text, false), |to| (to, true));
    if !def.yields.iter().any(|(y, p)| y == to && *p == pause) {
        return Err(format!(
            "the codel of state `{state}` does not yield `{text}`"
        ));
    }
    match to {
        "ether" if !pause => Ok(Outcome::Ether),
        _ if fsm.has(to) => Ok(Outcome::To(to.to_owned())),
        _ => Err(format!("`{text}` leads to no state")),
    }
}

/// Replays a GenoM3 engine trace against GenoM3's rules; Err says which
/// step (1-based index into `trace.steps`) is illegal and why.
pub fn replay_genom3(c: &Component, trace: &Trace) -> Result<(), String> {
    let r = Rules::new(c)?;
    let last = trace.steps.len().checked_sub(1);
    let last = last.ok_or("the trace is empty")?;
    if trace.steps[0].event != Event::ComponentStart {
        return Err("step 1: a trace starts with `component-start`".into());
    }
    first_codels(&r, trace)?;
    let mut worlds = vec![World::initial(&r)];
    for (k, step) in trace.steps.iter().enumerate().skip(1) {
        let at = |e: String| format!("step {} ({}): {e}", k + 1, step.event.as_str());
        if step.event == Event::Violation {
            if k != last {
                return Err(at("a violation is the last step".into()));
            }
            continue;
        }
        let mut next: Vec<World> = Vec::new();
        let mut error = None;
        for w in &worlds {
            match w.step(&r, step) {
                Ok(v) => {
                    for n in v {
                        if !next.iter().any(|x| x.same(&n)) {
                            next.push(n);
                        }
                    }
                }
                Err(e) => error = error.or(Some(e)),
            }
        }
        if next.is_empty() {
            return Err(at(error.unwrap_or_default()));
        }
        worlds = next;
    }
    trace.loop_start.map_or(Ok(()), |k| lasso(trace, k))
}

/// Every `start` of an activity with a `start` codel is followed at once by
/// that codel's end: GenoM3's sweep starts an instance and runs its first
/// codel together, so nothing (an interruption) comes in between.
fn first_codels(r: &Rules, trace: &Trace) -> Result<(), String> {
    for (k, pair) in trace.steps.windows(2).enumerate() {
        let (start, next) = (&pair[0], &pair[1]);
        if start.event != Event::Start {
            continue;
        }
        let a = r.activity(start.service.as_deref())?;
        let first = next.event == Event::CodelEnd
            && next.service == start.service
            && next.codel.as_deref() == Some("start");
        if r.services[a].fsm.has("start") && !first {
            return Err(format!(
                "step {} ({}): `{}` started at step {} but did not run its `start` codel at once",
                k + 2,
                next.event.as_str(),
                r.services[a].name,
                k + 1
            ));
        }
    }
    Ok(())
}

/// The loop from step `k` (0-based) to the violation: `codel-end` steps of
/// one owner, unpaused yields chained state to state, back to the first.
fn lasso(trace: &Trace, k: usize) -> Result<(), String> {
    let steps = &trace.steps;
    let violation = steps.last().is_some_and(|s| s.event == Event::Violation);
    let end = steps.len() - usize::from(violation);
    if k == 0 || k >= end {
        let k = k + 1;
        return Err(format!("the loop starts at step {k}, outside the trace"));
    }
    let first = &steps[k];
    for (j, s) in steps.iter().enumerate().take(end).skip(k) {
        let out = s.outcome.as_deref().unwrap_or_default();
        let why = if s.event != Event::CodelEnd {
            "a loop has only `codel-end` steps"
        } else if (&s.service, &s.thread) != (&first.service, &first.thread) {
            "a loop runs the codels of one activity, or of one task's permanent activity"
        } else if ["", "ether", "exception"].contains(&out) || out.starts_with("pause::") {
            "a loop goes on with yields without `pause::`"
        } else if j > k && s.codel != steps[j - 1].outcome {
            "the codel does not run in the state the previous one yielded"
        } else {
            continue;
        };
        return Err(format!("step {} (loop): {why}", j + 1));
    }
    if steps[end - 1].outcome != first.codel {
        let back = first.codel.as_deref().unwrap_or_default();
        return Err(format!(
            "step {end} (loop): the loop is not closed: no yield back to `{back}`"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests;
