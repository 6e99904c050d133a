//! The GenoM3 component as the GenoM3 engine reads it: each activity's and
//! each task's codel state machine (states, yields, `pause::`, `async`),
//! who interrupts whom, `after`/`before`, and which control services are
//! the built-in `kill` and `abort_activity`. Built once from the resolved
//! [`Component`] and its [`Genom3Info`]; every step of the engine reads it.

use std::collections::BTreeMap;

use genom_model::component::genom3::{FsmCodel, Genom3Info, ParamSource};
use genom_model::component::{CodelId, Component, Idx, ServiceId, ThreadId};
use genom_model::span::Span;

/// Where a yield leads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// Another state (index into [`Fsm::states`]); `pause` for `pause::`.
    State { state: u8, pause: bool },
    /// `ether`: the instance ends successfully.
    Ether,
}

/// One state of a codel state machine and the codel that runs in it.
#[derive(Debug, Clone)]
pub struct FsmState {
    /// The state's name (`start`, `stop`, user states).
    pub name: String,
    /// The codel function.
    pub function: String,
    /// The model codel standing for it (activities only).
    pub codel: Option<CodelId>,
    /// The FSM codel's span.
    pub span: Span,
    /// Where its yields lead, in the written order.
    pub yields: Vec<Target>,
    /// `async`: may block on an external event, the task does not spin.
    pub is_async: bool,
    /// Its WCET in nanoseconds (from a WCET side file).
    pub wcet_ns: Option<u64>,
    /// The data it accesses (for GenoM3's locks).
    pub access: Vec<Access>,
}

/// One data access of a codel, as GenoM3's `param_mutex` compares them.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Access {
    /// Ids member path (`None` for the ids) or port/remote name.
    pub base: Base,
    /// The member path below the base, segment by segment.
    pub path: Vec<String>,
    /// `out` or `inout`.
    pub write: bool,
}

/// What an access reaches.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Base {
    /// The ids.
    Ids,
    /// A port, by name.
    Port(String),
    /// A remote service, by name.
    Remote(String),
}

impl Access {
    /// The accesses of an FSM codel (`local` parameters never conflict).
    fn of(fsm: &FsmCodel) -> Vec<Access> {
        fsm.params
            .iter()
            .filter_map(|p| {
                let mut segs: Vec<String> = p
                    .path
                    .split(['.', '['])
                    .map(|x| x.trim_end_matches(']').trim().to_owned())
                    .filter(|x| !x.is_empty() && x != "::ids")
                    .collect();
                let base = match p.source {
                    ParamSource::Ids => Base::Ids,
                    ParamSource::Port if !segs.is_empty() => Base::Port(segs.remove(0)),
                    ParamSource::Remote if !segs.is_empty() => Base::Remote(segs.remove(0)),
                    _ => return None,
                };
                Some(Access {
                    base,
                    path: segs,
                    write: p.dir != "in",
                })
            })
            .collect()
    }

    /// GenoM3's `param_mutex`: same port or remote, whatever the
    /// directions; ids paths equal on their common prefix, one writing.
    pub fn conflicts(&self, other: &Access) -> bool {
        match (&self.base, &other.base) {
            (Base::Port(a), Base::Port(b)) | (Base::Remote(a), Base::Remote(b)) => a == b,
            (Base::Ids, Base::Ids) => {
                (self.write || other.write)
                    && self.path.iter().zip(&other.path).all(|(a, b)| a == b)
            }
            _ => false,
        }
    }
}

/// A codel state machine (an activity's or a task's permanent one).
#[derive(Debug, Clone, Default)]
pub struct Fsm {
    /// Its states.
    pub states: Vec<FsmState>,
    /// The `start` state.
    pub start: Option<u8>,
    /// The `stop` state.
    pub stop: Option<u8>,
}

impl Fsm {
    /// Reads the FSM codels of one owner; `codel_of` names the model codel
    /// of a state, if any.
    fn build(
        codels: &[&FsmCodel],
        codel_of: impl Fn(&str) -> Option<CodelId>,
        wcet_of: impl Fn(Option<CodelId>) -> Option<u64>,
    ) -> Fsm {
        let mut index: BTreeMap<&str, u8> = BTreeMap::new();
        let mut states = Vec::new();
        for fsm in codels {
            for s in &fsm.states {
                if index.contains_key(s.name.as_str()) || states.len() >= usize::from(u8::MAX) {
                    continue;
                }
                index.insert(&s.name, states.len() as u8);
                let codel = codel_of(&s.name);
                states.push(FsmState {
                    name: s.name.clone(),
                    function: fsm.function.name.clone(),
                    codel,
                    span: fsm.span,
                    yields: Vec::new(),
                    is_async: fsm.is_async,
                    wcet_ns: wcet_of(codel).or(fsm.wcet.map(|w| w.ns)),
                    access: Access::of(fsm),
                });
            }
        }
        for fsm in codels {
            let yields: Vec<Target> = fsm
                .yields
                .iter()
                .filter_map(|y| match index.get(y.state.name.as_str()) {
                    Some(&state) => Some(Target::State {
                        state,
                        pause: y.pause,
                    }),
                    None => (y.state.name == "ether").then_some(Target::Ether),
                })
                .collect();
            for s in &fsm.states {
                if let Some(&i) = index.get(s.name.as_str()) {
                    states[usize::from(i)].yields.clone_from(&yields);
                }
            }
        }
        Fsm {
            start: index.get("start").copied(),
            stop: index.get("stop").copied(),
            states,
        }
    }

    /// States `s` leads to without `pause::` (the chain a sweep runs).
    pub fn unpaused(&self, s: u8) -> impl Iterator<Item = u8> + '_ {
        self.states[usize::from(s)]
            .yields
            .iter()
            .filter_map(|t| match *t {
                Target::State {
                    state,
                    pause: false,
                } => Some(state),
                _ => None,
            })
    }
}

/// An activity: a service run by a task, one instance per request.
#[derive(Debug, Clone)]
pub struct Activity {
    /// The service.
    pub service: ServiceId,
    /// Index of its task in [`Machine::tasks`].
    pub task: usize,
    /// Its codel state machine.
    pub fsm: Fsm,
    /// Activities it interrupts (itself included when it does).
    pub interrupts: Vec<usize>,
}

/// What a control service (function or attribute) does besides its codels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ControlKind {
    /// An ordinary function or attribute.
    Plain,
    /// The built-in `kill`: interrupts everything, then shuts down.
    Kill,
    /// The built-in `abort_activity`: interrupts one instance.
    Abort,
}

/// A function or attribute, run on the control thread.
#[derive(Debug, Clone)]
pub struct Control {
    /// The service.
    pub service: ServiceId,
    /// What it does.
    pub kind: ControlKind,
    /// A service of the built-in `genom` interface.
    pub builtin: bool,
    /// Activities it interrupts after its codels succeeded.
    pub interrupts: Vec<usize>,
}

/// A task: a thread with its permanent state machine.
#[derive(Debug, Clone)]
pub struct TaskM {
    /// The thread.
    pub thread: ThreadId,
    /// Its name.
    pub name: String,
    /// Its permanent codels (`None` without any).
    pub perm: Option<Fsm>,
    /// Its period in nanoseconds (`None`: aperiodic).
    pub period_ns: Option<u64>,
    /// Its phase: the first wake-up, in nanoseconds.
    pub delay_ns: u64,
}

/// The GenoM3 component as the engine reads it.
#[derive(Debug, Clone)]
pub struct Machine<'a> {
    /// The component.
    pub c: &'a Component,
    /// Its tasks, in declaration order.
    pub tasks: Vec<TaskM>,
    /// Its activities.
    pub activities: Vec<Activity>,
    /// Its functions and attributes.
    pub controls: Vec<Control>,
    /// Per service: the activity or control standing for it.
    pub role: BTreeMap<ServiceId, Role>,
    /// Per service: `after` services.
    pub after: BTreeMap<ServiceId, Vec<ServiceId>>,
    /// Per service: `before` services.
    pub before: BTreeMap<ServiceId, Vec<ServiceId>>,
    /// The most instances of one activity explored at once.
    pub max_instances: usize,
    /// Slots of one task (its permanent activity included).
    pub pool: usize,
    /// Per service: its control codels (`validate`, then a function's
    /// codels), run in that order on the control thread.
    pub control_codels: BTreeMap<ServiceId, Vec<FsmState>>,
}

/// What a service is to the engine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// Index into [`Machine::activities`].
    Activity(usize),
    /// Index into [`Machine::controls`].
    Control(usize),
}

/// Slots per task in GenoM3's templates (genom3-ros `MAX_ACTIVITIES`).
pub const POOL: usize = 32;

impl<'a> Machine<'a> {
    /// The services whose completion some step reads (`after`/`before`
    /// name them), as bits by service index: the only completion flags an
    /// engine keeps in its states (genom3-semantics 14.1).
    pub fn completions_read(&self) -> Vec<u64> {
        let mut bits = vec![0u64; self.c.services.len().div_ceil(64).max(1)];
        for s in self.after.values().chain(self.before.values()).flatten() {
            bits[s.index() / 64] |= 1 << (s.index() % 64);
        }
        bits
    }

    /// The services an exploration requests (per activity `acts`, per
    /// control service `ctls`), in service order, but the built-in ones
    /// every exploration has.
    pub fn requested(&self, acts: &[bool], ctls: &[bool]) -> Vec<ServiceId> {
        let acts = self
            .activities
            .iter()
            .zip(acts)
            .filter(|(_, on)| **on)
            .map(|(a, _)| a.service);
        let ctls = self
            .controls
            .iter()
            .zip(ctls)
            .filter(|(k, on)| **on && !k.builtin)
            .map(|(k, _)| k.service);
        let mut out: Vec<ServiceId> = acts.chain(ctls).collect();
        out.sort_unstable();
        out
    }

    /// Reads a GenoM3 component; `None` for a LANGUAGE.md one.
    pub fn new(c: &'a Component, max_instances: usize) -> Option<Machine<'a>> {
        let g = c.genom3.as_deref()?;
        let tasks = tasks(c, g);
        let task_of: BTreeMap<ThreadId, usize> = tasks
            .iter()
            .enumerate()
            .map(|(i, t)| (t.thread, i))
            .collect();
        let mut role = BTreeMap::new();
        let mut activities = Vec::new();
        for (sid, s) in c.services.iter() {
            let Some(task) = s.thread.and_then(|t| task_of.get(&t.id).copied()) else {
                continue;
            };
            role.insert(sid, Role::Activity(activities.len()));
            activities.push(Activity {
                service: sid,
                task,
                fsm: service_fsm(c, g, sid),
                interrupts: Vec::new(),
            });
        }
        let mut controls = Vec::new();
        for (sid, s) in c.services.iter() {
            if role.contains_key(&sid) {
                continue;
            }
            let builtin = g.services.iter().find(|i| i.service == sid);
            let genom = builtin.is_some_and(|i| i.interface.as_deref() == Some("genom"));
            let kind = match s.name.name.as_str() {
                "kill" if genom => ControlKind::Kill,
                "abort_activity" if genom => ControlKind::Abort,
                _ => ControlKind::Plain,
            };
            role.insert(sid, Role::Control(controls.len()));
            controls.push(Control {
                service: sid,
                kind,
                builtin: genom,
                interrupts: Vec::new(),
            });
        }
        let targets = |sid: ServiceId| -> Vec<usize> {
            let mut out: Vec<usize> = c.services[sid]
                .stops
                .iter()
                .filter_map(|r| match role.get(&r.id) {
                    Some(Role::Activity(a)) => Some(*a),
                    _ => None,
                })
                .collect();
            out.sort_unstable();
            out.dedup();
            out
        };
        for a in &mut activities {
            a.interrupts = targets(a.service);
        }
        for k in &mut controls {
            k.interrupts = match k.kind {
                ControlKind::Kill => (0..activities.len()).collect(),
                _ => targets(k.service),
            };
        }
        let mut after = BTreeMap::new();
        let mut before = BTreeMap::new();
        for i in &g.services {
            after.insert(i.service, i.after.iter().map(|r| r.id).collect());
            before.insert(i.service, i.before.iter().map(|r| r.id).collect());
        }
        let control_codels = control_codels(c, g);
        Some(Machine {
            c,
            control_codels,
            tasks,
            activities,
            controls,
            role,
            after,
            before,
            max_instances: max_instances.clamp(1, POOL - 1),
            pool: POOL,
        })
    }

    /// The most instances of activity `a` explored at once:
    /// `max_instances`, plus one for an activity that interrupts itself.
    /// A client restarts such an activity by sending its request again: the
    /// new instance interrupts the running ones and waits for them to end
    /// (3.4, 5.3), its `validate` and their stop paths running meanwhile,
    /// so `max_instances` running instances and one request interrupting
    /// them live at once.
    pub fn instance_bound(&self, a: usize) -> usize {
        (self.max_instances + usize::from(self.interrupts_itself(a))).min(self.pool - 1)
    }

    /// Whether activity `a` lists itself in its `interrupts`.
    pub fn interrupts_itself(&self, a: usize) -> bool {
        self.activities[a].interrupts.contains(&a)
    }

    /// Slots per activity in a packed state: the largest
    /// [`Machine::instance_bound`].
    pub fn slots(&self) -> usize {
        (0..self.activities.len())
            .map(|a| self.instance_bound(a))
            .max()
            .unwrap_or(self.max_instances)
    }

    /// Whether some activity interrupts itself (explored with one more
    /// instance, [`Machine::instance_bound`]).
    pub fn has_self_interrupts(&self) -> bool {
        (0..self.activities.len()).any(|a| self.interrupts_itself(a))
    }

    /// The name of service `s`.
    pub fn service_name(&self, s: ServiceId) -> &str {
        &self.c.services[s].name.name
    }

    /// Whether `s` is a service of the built-in `genom` interface.
    pub fn is_builtin(&self, s: ServiceId) -> bool {
        matches!(self.role.get(&s), Some(Role::Control(k)) if self.controls[*k].builtin)
    }

    /// The name of activity `a`.
    pub fn activity_name(&self, a: usize) -> &str {
        self.service_name(self.activities[a].service)
    }

    /// The codel state machine of activity `a`.
    pub fn fsm(&self, owner: Owner) -> &Fsm {
        match owner {
            Owner::Activity(a) => &self.activities[a].fsm,
            Owner::Task(t) => self.tasks[t].perm.as_ref().unwrap_or(&EMPTY),
        }
    }

    /// The name of an owner: the activity, or `task T` for a permanent one.
    pub fn owner_name(&self, owner: Owner) -> String {
        match owner {
            Owner::Activity(a) => self.activity_name(a).to_owned(),
            Owner::Task(t) => format!("task {}", self.tasks[t].name),
        }
    }

    /// The task an owner runs on.
    pub fn task_of(&self, owner: Owner) -> usize {
        match owner {
            Owner::Activity(a) => self.activities[a].task,
            Owner::Task(t) => t,
        }
    }
}

static EMPTY: Fsm = Fsm {
    states: Vec::new(),
    start: None,
    stop: None,
};

/// Whose state machine: an activity's or a task's permanent one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Owner {
    /// Index into [`Machine::activities`].
    Activity(usize),
    /// Index into [`Machine::tasks`].
    Task(usize),
}

fn tasks(c: &Component, g: &Genom3Info) -> Vec<TaskM> {
    c.threads
        .iter()
        .map(|(tid, t)| {
            let codels: Vec<&FsmCodel> = g
                .tasks
                .iter()
                .filter(|k| k.thread == tid)
                .flat_map(|k| k.codels.iter())
                .collect();
            TaskM {
                thread: tid,
                name: t.name.name.clone(),
                perm: (!codels.is_empty()).then(|| Fsm::build(&codels, |_| None, |_| None)),
                period_ns: t.period.map(|p| p.ns),
                delay_ns: g
                    .tasks
                    .iter()
                    .find(|k| k.thread == tid)
                    .and_then(|k| k.delay)
                    .map_or(0, |d| d.ns),
            }
        })
        .collect()
}

/// The name of an attribute's ids copy among its control codels.
pub const IDS_COPY: &str = "ids-copy";

/// The control codels of every service that has some, in order; an
/// attribute's ids copy (6.1 step 4: under its own ticket, after
/// `validate`) comes last, as a codel [`IDS_COPY`] without a model codel
/// and without a WCET (it takes no time).
fn control_codels(c: &Component, g: &Genom3Info) -> BTreeMap<ServiceId, Vec<FsmState>> {
    let mut out: BTreeMap<ServiceId, Vec<FsmState>> = BTreeMap::new();
    for (sid, s) in c.services.iter() {
        let attribute = g
            .services
            .iter()
            .any(|i| i.service == sid && i.kind == "attribute");
        for &k in &s.codels {
            let codel = &c.codels[k];
            if codel.kind != genom_model::kinds::CodelKind::Control {
                continue;
            }
            let Some(info) = g.codels.iter().find(|i| i.codel == k) else {
                continue;
            };
            out.entry(sid).or_default().push(FsmState {
                name: codel.name.name.clone(),
                function: info.fsm.function.name.clone(),
                codel: Some(k),
                span: info.fsm.span,
                yields: Vec::new(),
                is_async: false,
                wcet_ns: codel.wcet.map(|w| w.ns),
                access: Access::of(&info.fsm),
            });
        }
        if attribute {
            out.entry(sid).or_default().push(FsmState {
                name: IDS_COPY.to_owned(),
                function: "ids copy".to_owned(),
                codel: None,
                span: s.name.span,
                yields: Vec::new(),
                is_async: false,
                wcet_ns: None,
                access: ids_copy_access(s),
            });
        }
    }
    out
}

/// What an attribute's ids copy accesses: it writes the members of its
/// inputs and reads those of its outputs.
fn ids_copy_access(s: &genom_model::component::Service) -> Vec<Access> {
    let of = |p: &genom_model::component::Param, write: bool| {
        // The member as written (`x`, `a.b[2]`): an attribute's parameter
        // names its ids member.
        let data = p.data.as_ref()?;
        let path = data
            .text
            .split(['.', '['])
            .map(|x| x.trim_end_matches(']').trim().to_owned())
            .filter(|x| !x.is_empty() && x != "::ids")
            .collect();
        Some(Access {
            base: Base::Ids,
            path,
            write,
        })
    };
    let inputs = s.inputs.iter().filter_map(|p| of(p, true));
    inputs
        .chain(s.outputs.iter().filter_map(|p| of(p, false)))
        .collect()
}

fn service_fsm(c: &Component, g: &Genom3Info, sid: ServiceId) -> Fsm {
    let s = &c.services[sid];
    let infos: Vec<_> = g
        .codels
        .iter()
        .filter(|i| s.codels.contains(&i.codel))
        .collect();
    let mut seen: Vec<&FsmCodel> = Vec::new();
    for i in &infos {
        if !seen.iter().any(|f| f.span == i.fsm.span) {
            seen.push(&i.fsm);
        }
    }
    Fsm::build(
        &seen,
        |state| {
            infos
                .iter()
                .find(|i| c.codels[i.codel].name.name == state)
                .map(|i| i.codel)
        },
        |k| k.and_then(|k| c.codels[k].wcet).map(|w| w.ns),
    )
}
