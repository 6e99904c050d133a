//! The GenoM3 component as the timed replay reads it, straight from the
//! model ([`Component`] and its [`Genom3Info`]) and written from
//! `docs/genom3-semantics.md`, not from the engine's reading: the tasks
//! (period, `delay`, permanent codels, 1.2 and 1.8), the activities and
//! their codel state machines (states, yields, `pause::`, `async`, WCETs,
//! the data each codel touches, 8.1), the built-in `kill` and
//! `abort_activity` (5.6, 5.7), `after`/`before` (4.1, 4.2) and the codels
//! each service runs on the control thread (6.1, 15.5).
//!
//! How the GenoM3 front-end puts GenoM3 into the model
//! (`genom_model::component::genom3`): tasks are threads; an activity is
//! a service on its task with one model codel per state of its state
//! machine, each with a [`genom_model::component::genom3::CodelInfo`]
//! giving the FSM codel that runs in it; `validate` and a function's
//! codels are the service's control codels; the WCET side file sets a
//! state's WCET on its model codel, a permanent codel's on the task's
//! [`FsmCodel`], a control codel's on its model codel.

use std::collections::BTreeMap;

use genom_model::component::genom3::{CodelParam, FsmCodel, Genom3Info, ParamSource, Task};
use genom_model::component::{Component, Param, Service, ServiceId};
use genom_model::kinds::CodelKind;

/// Slots of a task, its permanent activity included (3.2: genom3-ros
/// `MAX_ACTIVITIES`).
const SLOTS: usize = 32;

/// The name traces give an attribute's ids copy (6.1 step 4, 15.5).
const IDS_COPY: &str = "ids-copy";

/// Whose codel state machine: an activity's, or a task's permanent one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Owner {
    /// Index into [`Rules::activities`].
    Activity(usize),
    /// Index into [`Rules::tasks`].
    Task(usize),
}

/// A built-in service of the `genom` interface that does more than run
/// its codels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Builtin {
    /// Interrupts every instance, then shuts the component down (5.7).
    Kill,
    /// Interrupts one instance (5.6).
    Abort,
}

/// What a codel parameter reaches, as GenoM3's locks compare it (8.1).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum Base {
    /// The ids.
    Ids,
    /// A port, by name.
    Port(String),
    /// A remote, by name.
    Remote(String),
}

/// One piece of data a codel touches.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct Access {
    pub(super) base: Base,
    /// The members below the base (`pose.x` is `["pose", "x"]`).
    pub(super) path: Vec<String>,
    /// Written (`out`, `inout`), else read.
    pub(super) write: bool,
}

/// Where a yield leads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Target {
    /// A state of the same machine (index into [`Fsm::states`]), paused or
    /// not.
    State { state: u8, pause: bool },
    /// `ether`: the instance ends successfully.
    Ether,
}

/// A codel: one state's of a codel state machine, or a control codel.
#[derive(Debug, Clone)]
pub(super) struct CodelDef {
    /// The state's name, or the control codel's (`validate`, `codel`...).
    pub(super) name: String,
    /// Where its yields lead (empty for a control codel).
    pub(super) yields: Vec<Target>,
    /// `async` (7.2): no lock, no upper bound on its duration.
    pub(super) is_async: bool,
    /// Its WCET, if the WCET file gives one.
    pub(super) wcet_ns: Option<u64>,
    /// The data it touches.
    pub(super) access: Vec<Access>,
    /// An attribute's ids copy: no codel of the component, it throws
    /// nothing.
    pub(super) ids_copy: bool,
}

/// A codel state machine.
#[derive(Debug, Clone, Default)]
pub(super) struct Fsm {
    pub(super) states: Vec<CodelDef>,
    /// The `start` state.
    pub(super) start: Option<u8>,
    /// The `stop` state.
    pub(super) stop: Option<u8>,
}

/// A task.
#[derive(Debug, Clone)]
pub(super) struct TaskDef {
    pub(super) name: String,
    /// Its permanent codels (`None` without any).
    pub(super) perm: Option<Fsm>,
    /// `None`: aperiodic.
    pub(super) period_ns: Option<u64>,
    /// Its first tick (`delay`).
    pub(super) delay_ns: u64,
}

/// An activity: a service run by a task.
#[derive(Debug, Clone)]
pub(super) struct ActivityDef {
    pub(super) service: ServiceId,
    /// Index into [`Rules::tasks`].
    pub(super) task: usize,
    pub(super) fsm: Fsm,
}

/// The component as this replay reads it.
#[derive(Debug)]
pub(super) struct Rules<'c> {
    pub(super) c: &'c Component,
    /// In declaration order.
    pub(super) tasks: Vec<TaskDef>,
    pub(super) activities: Vec<ActivityDef>,
    /// Per service: its control codels, in the order the control thread
    /// runs them (`validate`, a function's codels, an attribute's ids
    /// copy).
    pub(super) control_codels: BTreeMap<ServiceId, Vec<CodelDef>>,
    /// `--max-instances`: live requests of one activity.
    max_instances: usize,
    builtins: BTreeMap<ServiceId, Builtin>,
    g: &'c Genom3Info,
}

/// An empty machine, for a task without permanent codels.
static NO_CODELS: Fsm = Fsm {
    states: Vec::new(),
    start: None,
    stop: None,
};

impl<'c> Rules<'c> {
    /// Reads `c`; `None` when it is no GenoM3 component.
    pub(super) fn new(c: &'c Component, max_instances: usize) -> Option<Rules<'c>> {
        let g = c.genom3.as_deref()?;
        let threads: Vec<_> = c.threads.ids().collect();
        let tasks = c
            .threads
            .iter()
            .map(|(tid, t)| {
                let info = g.tasks.iter().find(|k| k.thread == tid);
                let perm = info
                    .filter(|k| !k.codels.is_empty())
                    .map(|k| machine(task_states(k)));
                TaskDef {
                    name: t.name.name.clone(),
                    perm,
                    period_ns: t.period.map(|p| p.ns),
                    delay_ns: info.and_then(|k| k.delay).map_or(0, |d| d.ns),
                }
            })
            .collect();
        let mut activities = Vec::new();
        let mut builtins = BTreeMap::new();
        let mut control_codels = BTreeMap::new();
        for (sid, s) in c.services.iter() {
            let info = g.services.iter().find(|i| i.service == sid);
            match s
                .thread
                .and_then(|r| threads.iter().position(|&t| t == r.id))
            {
                Some(task) => activities.push(ActivityDef {
                    service: sid,
                    task,
                    fsm: machine(activity_states(c, g, s)),
                }),
                None if info.is_some_and(|i| i.interface.as_deref() == Some("genom")) => {
                    let builtin = match s.name.name.as_str() {
                        "kill" => Some(Builtin::Kill),
                        "abort_activity" => Some(Builtin::Abort),
                        _ => None,
                    };
                    builtins.extend(builtin.map(|b| (sid, b)));
                }
                None => {}
            }
            let mut run = control_of(c, g, s);
            if info.is_some_and(|i| i.kind == "attribute") {
                run.push(ids_copy(s));
            }
            if !run.is_empty() {
                control_codels.insert(sid, run);
            }
        }
        Some(Rules {
            c,
            tasks,
            activities,
            control_codels,
            max_instances: max_instances.max(1),
            builtins,
            g,
        })
    }

    /// The codel state machine of `o`.
    pub(super) fn fsm(&self, o: Owner) -> &Fsm {
        match o {
            Owner::Activity(a) => &self.activities[a].fsm,
            Owner::Task(t) => self.tasks[t].perm.as_ref().unwrap_or(&NO_CODELS),
        }
    }

    /// The task `o` runs on.
    pub(super) fn task_of(&self, o: Owner) -> usize {
        match o {
            Owner::Activity(a) => self.activities[a].task,
            Owner::Task(t) => t,
        }
    }

    /// The activity of service `sid`, if it is one.
    pub(super) fn activity_of(&self, sid: ServiceId) -> Option<usize> {
        self.activities.iter().position(|a| a.service == sid)
    }

    /// What built-in service `sid` is, if it is `kill` or `abort_activity`.
    pub(super) fn builtin(&self, sid: ServiceId) -> Option<Builtin> {
        self.builtins.get(&sid).copied()
    }

    /// The service of built-in `b`, if the component has it.
    pub(super) fn builtin_service(&self, b: Builtin) -> Option<ServiceId> {
        self.builtins
            .iter()
            .find(|&(_, &x)| x == b)
            .map(|(&sid, _)| sid)
    }

    /// The services `sid` is `after` (`after` true) or `before`.
    pub(super) fn ordered(&self, sid: ServiceId, after: bool) -> Vec<ServiceId> {
        let info = self.g.services.iter().find(|i| i.service == sid);
        let refs = info.map(|i| if after { &i.after } else { &i.before });
        refs.into_iter().flatten().map(|r| r.id).collect()
    }

    /// The name of service `sid`.
    pub(super) fn service_name(&self, sid: ServiceId) -> &str {
        &self.c.services[sid].name.name
    }

    /// The name of activity `a`.
    pub(super) fn activity_name(&self, a: usize) -> &str {
        self.service_name(self.activities[a].service)
    }

    /// The most live instances of activity `a`: `--max-instances`, one more
    /// for an activity that interrupts itself (its restart, 15.8), within
    /// its task's slots beside the permanent activity (3.2).
    pub(super) fn instance_bound(&self, a: usize) -> usize {
        let sid = self.activities[a].service;
        let restart = self.c.services[sid].stops.iter().any(|r| r.id == sid);
        (self.max_instances + usize::from(restart)).min(SLOTS - 1)
    }
}

/// One state before its yields are resolved: its name, the FSM codel that
/// runs in it, and its WCET.
type Raw<'a> = (String, &'a FsmCodel, Option<u64>);

/// The states of a task's permanent codels; a codel's WCET is that of
/// every state it runs in.
fn task_states(task: &Task) -> Vec<Raw<'_>> {
    task.codels
        .iter()
        .flat_map(|f| {
            let wcet = f.wcet.map(|w| w.ns);
            f.states.iter().map(move |s| (s.name.clone(), f, wcet))
        })
        .collect()
}

/// The states of an activity: one per model codel that is no control
/// codel, named after it, with its WCET.
fn activity_states<'a>(c: &Component, g: &'a Genom3Info, s: &Service) -> Vec<Raw<'a>> {
    let mut out = Vec::new();
    for &k in &s.codels {
        let codel = &c.codels[k];
        if codel.kind == CodelKind::Control {
            continue;
        }
        if let Some(info) = g.codels.iter().find(|i| i.codel == k) {
            out.push((codel.name.name.clone(), &info.fsm, codel.wcet.map(|w| w.ns)));
        }
    }
    out
}

/// Builds a machine from its states (a name met twice: its first
/// reading), then resolves the yields by state name.
fn machine(raw: Vec<Raw<'_>>) -> Fsm {
    let mut kept: Vec<Raw<'_>> = Vec::new();
    for r in raw {
        if !kept.iter().any(|k| k.0 == r.0) && kept.len() < usize::from(u8::MAX) {
            kept.push(r);
        }
    }
    let index = |name: &str| {
        let at = kept.iter().position(|k| k.0 == name)?;
        u8::try_from(at).ok()
    };
    let states = kept
        .iter()
        .map(|(name, f, wcet)| CodelDef {
            name: name.clone(),
            yields: f
                .yields
                .iter()
                .filter_map(|y| match index(&y.state.name) {
                    Some(state) => Some(Target::State {
                        state,
                        pause: y.pause,
                    }),
                    None if y.state.name == "ether" => Some(Target::Ether),
                    None => None,
                })
                .collect(),
            is_async: f.is_async,
            wcet_ns: *wcet,
            access: f.params.iter().filter_map(param_access).collect(),
            ids_copy: false,
        })
        .collect();
    Fsm {
        start: index("start"),
        stop: index("stop"),
        states,
    }
}

/// The members of a path as written (`a.b[2]`: `a`, `b`, `2`); `::ids`
/// (the whole ids) has none.
fn members(text: &str) -> Vec<String> {
    text.split(['.', '['])
        .map(|m| m.trim().trim_end_matches(']').trim())
        .filter(|m| !m.is_empty() && *m != "::ids")
        .map(str::to_owned)
        .collect()
}

/// What a codel parameter touches (`local` data and service parameters
/// never conflict, 8.1).
fn param_access(p: &CodelParam) -> Option<Access> {
    let mut path = members(&p.path);
    let base = match p.source {
        ParamSource::Ids => Base::Ids,
        ParamSource::Port if !path.is_empty() => Base::Port(path.remove(0)),
        ParamSource::Remote if !path.is_empty() => Base::Remote(path.remove(0)),
        ParamSource::Local | ParamSource::Port | ParamSource::Remote => return None,
    };
    Some(Access {
        base,
        path,
        write: p.dir != "in",
    })
}

/// The control codels of `s` (`validate`, a function's codels), in its
/// order.
fn control_of(c: &Component, g: &Genom3Info, s: &Service) -> Vec<CodelDef> {
    s.codels
        .iter()
        .filter(|&&k| c.codels[k].kind == CodelKind::Control)
        .map(|&k| {
            let fsm = g.codels.iter().find(|i| i.codel == k).map(|i| &i.fsm);
            CodelDef {
                name: c.codels[k].name.name.clone(),
                yields: Vec::new(),
                is_async: false,
                wcet_ns: c.codels[k].wcet.map(|w| w.ns),
                access: fsm
                    .into_iter()
                    .flat_map(|f| &f.params)
                    .filter_map(param_access)
                    .collect(),
                ids_copy: false,
            }
        })
        .collect()
}

/// An attribute's ids copy (6.1 step 4): it writes the ids members of its
/// inputs and reads those of its outputs, in no time.
fn ids_copy(s: &Service) -> CodelDef {
    let member = |p: &Param, write: bool| {
        let data = p.data.as_ref()?;
        Some(Access {
            base: Base::Ids,
            path: members(&data.text),
            write,
        })
    };
    let written = s.inputs.iter().filter_map(|p| member(p, true));
    let read = s.outputs.iter().filter_map(|p| member(p, false));
    CodelDef {
        name: IDS_COPY.to_owned(),
        yields: Vec::new(),
        is_async: false,
        wcet_ns: None,
        access: written.chain(read).collect(),
        ids_copy: true,
    }
}
