//! The GenoM3 component as the untimed translations (the Promela model,
//! the Petri net) read it, from the resolved [`Component`] and its
//! [`Genom3Info`] only (written independently of the GenoM3 engine,
//! `checker/engine/src/genom3/`): each task's permanent
//! state machine, each activity's state machine and the activities it
//! interrupts, the functions and attributes (the built-in `kill` and
//! `abort_activity` recognised), and `after`/`before`.

use std::collections::{BTreeMap, BTreeSet};

use genom_model::component::genom3::{FsmCodel, Genom3Info};
use genom_model::component::{Component, ServiceId, ThreadId};
use genom_model::kinds::CodelKind;
use genom_model::span::Span;

/// Where one yield of a codel leads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Next {
    /// A state of the same machine (index into [`Fsm::states`]).
    State(usize),
    /// `ether`: the machine ends successfully.
    Ether,
}

/// One state of a codel state machine.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct State {
    /// The state's name.
    pub name: String,
    /// The codel function run in it.
    pub function: String,
    /// Its yields (`pause::` dropped: it changes no untimed verdict,
    /// docs/genom3-semantics.md 14.3), in the written order.
    pub yields: Vec<Next>,
    /// Where its codel is written.
    pub span: Span,
}

/// A codel state machine (an activity's or a task's permanent one).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Fsm {
    /// Its states, in the order their codels are written.
    pub states: Vec<State>,
    /// The `start` state.
    pub start: Option<usize>,
    /// The `stop` state.
    pub stop: Option<usize>,
}

impl Fsm {
    /// The machine of a list of FSM codels: one state per state name (the
    /// first codel declaring a name wins); yields to undeclared states are
    /// left out (a static error of the component).
    fn of(codels: &[&FsmCodel]) -> Fsm {
        let mut states: Vec<State> = Vec::new();
        let mut owner: Vec<usize> = Vec::new();
        for (k, codel) in codels.iter().enumerate() {
            for s in &codel.states {
                if states.iter().all(|x| x.name != s.name) {
                    states.push(State {
                        name: s.name.clone(),
                        function: codel.function.name.clone(),
                        yields: Vec::new(),
                        span: codel.span,
                    });
                    owner.push(k);
                }
            }
        }
        let index = |name: &str| states.iter().position(|x| x.name == name);
        let yields: Vec<Vec<Next>> = owner
            .iter()
            .map(|&k| {
                codels[k]
                    .yields
                    .iter()
                    .filter_map(|y| match index(&y.state.name) {
                        Some(i) => Some(Next::State(i)),
                        None => (y.state.name == "ether").then_some(Next::Ether),
                    })
                    .collect()
            })
            .collect();
        for (s, y) in states.iter_mut().zip(yields) {
            s.yields = y;
        }
        Fsm {
            start: states.iter().position(|x| x.name == "start"),
            stop: states.iter().position(|x| x.name == "stop"),
            states,
        }
    }
}

/// A task and its permanent activity.
#[derive(Debug, Clone)]
pub struct Task {
    /// Its name.
    pub name: String,
    /// Where it is named.
    pub span: Span,
    /// Its permanent state machine (no state: no permanent codel).
    pub fsm: Fsm,
}

/// An activity: a service run by a task.
#[derive(Debug, Clone)]
pub struct Activity {
    /// The service.
    pub service: ServiceId,
    /// Its name.
    pub name: String,
    /// Index of its task in [`Reading::tasks`].
    pub task: usize,
    /// Its state machine.
    pub fsm: Fsm,
    /// The other activities it interrupts (indices, sorted; itself left
    /// out: with one instance per activity a new instance never meets an
    /// older one of its own activity).
    pub targets: Vec<usize>,
}

/// What a function or attribute does besides succeeding.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ControlKind {
    /// An ordinary function or attribute (its `interrupts` after success).
    Plain,
    /// The built-in `kill`: interrupts every instance, then shutdown.
    Kill,
    /// The built-in `abort_activity`: interrupts one instance.
    Abort,
}

/// A function or attribute (control thread).
#[derive(Debug, Clone)]
pub struct Control {
    /// The service.
    pub service: ServiceId,
    /// Its name.
    pub name: String,
    /// What it does.
    pub kind: ControlKind,
    /// The activities it interrupts once it succeeded (indices, sorted).
    pub targets: Vec<usize>,
}

/// The whole reading.
#[derive(Debug, Clone)]
pub struct Reading {
    /// Tasks, in declaration order.
    pub tasks: Vec<Task>,
    /// Activities, in service order.
    pub activities: Vec<Activity>,
    /// Functions and attributes, in service order.
    pub controls: Vec<Control>,
    /// `after` lists, per service that has one.
    pub after: BTreeMap<ServiceId, Vec<ServiceId>>,
    /// `before` lists, per service that has one.
    pub before: BTreeMap<ServiceId, Vec<ServiceId>>,
    /// Services of the built-in `genom` interface.
    pub builtin: BTreeSet<ServiceId>,
}

impl Reading {
    /// Reads a GenoM3 component (`None` for a LANGUAGE.md one).
    pub fn new(c: &Component) -> Option<Reading> {
        let g = c.genom3.as_deref()?;
        let threads: Vec<ThreadId> = c.threads.ids().collect();
        let tasks = threads
            .iter()
            .map(|&tid| Task {
                name: c.threads[tid].name.name.clone(),
                span: c.threads[tid].name.span,
                fsm: task_fsm(g, tid),
            })
            .collect();
        let builtin: BTreeSet<ServiceId> = g
            .services
            .iter()
            .filter(|i| i.interface.as_deref() == Some("genom"))
            .map(|i| i.service)
            .collect();
        let mut activities = Vec::new();
        let mut controls = Vec::new();
        for (sid, s) in c.services.iter() {
            let task = s
                .thread
                .and_then(|t| threads.iter().position(|&x| x == t.id));
            match task {
                Some(task) => activities.push(Activity {
                    service: sid,
                    name: s.name.name.clone(),
                    task,
                    fsm: activity_fsm(c, g, sid),
                    targets: Vec::new(),
                }),
                None => controls.push(Control {
                    service: sid,
                    name: s.name.name.clone(),
                    kind: control_kind(&s.name.name, builtin.contains(&sid)),
                    targets: Vec::new(),
                }),
            }
        }
        let index: BTreeMap<ServiceId, usize> = activities
            .iter()
            .enumerate()
            .map(|(k, a)| (a.service, k))
            .collect();
        let targets = |sid: ServiceId, all: bool| -> Vec<usize> {
            let listed = c.services[sid].stops.iter().map(|r| r.id);
            let mut v: Vec<usize> = if all {
                index.values().copied().collect()
            } else {
                listed.filter_map(|x| index.get(&x).copied()).collect()
            };
            let own = index.get(&sid).copied();
            v.retain(|&k| Some(k) != own);
            v.sort_unstable();
            v.dedup();
            v
        };
        let all_of = |sid: ServiceId| {
            g.services
                .iter()
                .any(|i| i.service == sid && i.interrupts_all)
        };
        for a in &mut activities {
            a.targets = targets(a.service, all_of(a.service));
        }
        for k in &mut controls {
            let all = k.kind == ControlKind::Kill || all_of(k.service);
            k.targets = targets(k.service, all);
        }
        let mut after = BTreeMap::new();
        let mut before = BTreeMap::new();
        for i in &g.services {
            if !i.after.is_empty() {
                after.insert(i.service, i.after.iter().map(|r| r.id).collect());
            }
            if !i.before.is_empty() {
                before.insert(i.service, i.before.iter().map(|r| r.id).collect());
            }
        }
        Some(Reading {
            tasks,
            activities,
            controls,
            after,
            before,
            builtin,
        })
    }

    /// The services whose completion some `after` or `before` reads.
    pub fn watched(&self) -> BTreeSet<ServiceId> {
        self.after
            .values()
            .chain(self.before.values())
            .flatten()
            .copied()
            .collect()
    }
}

fn control_kind(name: &str, builtin: bool) -> ControlKind {
    match name {
        "kill" if builtin => ControlKind::Kill,
        "abort_activity" if builtin => ControlKind::Abort,
        _ => ControlKind::Plain,
    }
}

/// A task's permanent machine: the FSM codels declared in the task.
fn task_fsm(g: &Genom3Info, tid: ThreadId) -> Fsm {
    let codels: Vec<&FsmCodel> = g
        .tasks
        .iter()
        .filter(|t| t.thread == tid)
        .flat_map(|t| t.codels.iter())
        .collect();
    Fsm::of(&codels)
}

/// An activity's machine: the FSM codels behind its (non-control) model
/// codels, each once.
fn activity_fsm(c: &Component, g: &Genom3Info, sid: ServiceId) -> Fsm {
    let mut codels: Vec<&FsmCodel> = Vec::new();
    for &k in &c.services[sid].codels {
        if c.codels[k].kind == CodelKind::Control {
            continue;
        }
        if let Some(info) = g.codels.iter().find(|i| i.codel == k) {
            if !codels.contains(&&info.fsm) {
                codels.push(&info.fsm);
            }
        }
    }
    Fsm::of(&codels)
}
