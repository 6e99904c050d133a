//! The diagrams of a GenoM3 component, in GenoM3's words: the model
//! ([`G3Diagrams`]) that both the `dot` and the `svg` exports draw.
//!
//! - the overview: one cluster per task (the control task first) holding
//!   the task's permanent codels (one box) and the activities it runs (one
//!   box each); the control task holds one table listing every function
//!   and attribute with its `validate` and codels;
//! - per task, its permanent machine: the task's own codels, one node per
//!   state, from `start` (entered when the component starts) to `ether`,
//!   `stop` entered on `kill`;
//! - per activity, its machine: the request, the `validate` codel (run by
//!   the control task), one node per state, `ether`, and the interrupt
//!   leading to `stop` when the activity has one.
//!
//! `pause::` yields are [`G3EdgeKind::Pause`] edges (drawn dashed and
//! labelled `pause`), immediate ones [`G3EdgeKind::Yield`]; `async` codels
//! and known WCETs are written in their state's label.

use genom_model::component::genom3::{FsmCodel, Genom3Info, ServiceInfo};
use std::fmt::Write as _;

use genom_model::component::{Component, Service, ServiceId, ThreadId};

use super::duration;

mod table;
mod text;

pub(crate) use table::{ControlTable, TABLE_HEADER};
pub(crate) use text::render;

/// Everything drawn for a GenoM3 component.
#[derive(Debug, Clone)]
pub(crate) struct G3Diagrams {
    /// The component's name.
    pub component: String,
    /// The tasks (the control task first) and their boxes.
    pub overview: G3Overview,
    /// The machines, task by task: the permanent machine, then the
    /// activities it runs; then the activities without task.
    pub machines: Vec<G3Machine>,
}

/// The overview: the tasks and what they run.
#[derive(Debug, Clone)]
pub(crate) struct G3Overview {
    /// The control task first, then the tasks in source order.
    pub groups: Vec<TaskGroup>,
    /// The boxes, in group order.
    pub boxes: Vec<G3Box>,
    /// The functions and attributes (drawn in the control task).
    pub table: ControlTable,
}

/// A task (or the control task) in the overview.
#[derive(Debug, Clone)]
pub(crate) struct TaskGroup {
    /// A unique identifier (`cluster.task.main`, `cluster.control`).
    pub id: String,
    /// `task main` or `control task`.
    pub title: String,
    /// `period 1 ms, delay 2 ms, real-time`, or what the control task runs.
    pub detail: String,
    /// Fill colour of its boxes.
    pub color: &'static str,
    /// Indices in [`G3Overview::boxes`].
    pub boxes: Vec<usize>,
}

/// What an overview box stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum BoxKind {
    /// A task's permanent codels.
    Permanent,
    /// An activity.
    Activity,
    /// The functions and attributes (the [`ControlTable`]).
    Table,
}

/// A box of the overview.
#[derive(Debug, Clone)]
pub(crate) struct G3Box {
    /// A unique identifier (`permanent.main`, `service.servo`,
    /// `table.control`).
    pub id: String,
    /// What it is.
    pub kind: BoxKind,
    /// Its lines (the name first); empty for the table.
    pub lines: Vec<String>,
    /// Index in [`G3Overview::groups`].
    pub group: usize,
}

/// A machine: a task's permanent codels or an activity's.
#[derive(Debug, Clone)]
pub(crate) struct G3Machine {
    /// A unique identifier (`machine.task-main`, `machine.servo`).
    pub id: String,
    /// `task main: permanent codels` or `activity servo`.
    pub title: String,
    /// The task, its period, the exceptions thrown.
    pub detail: String,
    /// Index of its task in [`G3Overview::groups`].
    pub group: usize,
    /// Nodes: the events first, then the validate codel, the states in
    /// source order, `ether`.
    pub nodes: Vec<G3Node>,
    /// Edges.
    pub edges: Vec<G3Edge>,
}

/// What a machine node is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum G3NodeKind {
    /// Something happening from outside (a request, an interrupt, the
    /// component starting, `kill`): a dot.
    Event,
    /// The activity's `validate` codel (run by the control task).
    Validate,
    /// The `start` state.
    Start,
    /// A state of the user's.
    State,
    /// The `stop` state.
    Stop,
    /// `ether`: the machine ends.
    Ether,
}

impl G3NodeKind {
    /// A stable word for classes and legends.
    pub fn class(self) -> &'static str {
        match self {
            G3NodeKind::Event => "event",
            G3NodeKind::Validate => "validate",
            G3NodeKind::Start => "start",
            G3NodeKind::State => "state",
            G3NodeKind::Stop => "stop",
            G3NodeKind::Ether => "ether",
        }
    }

    /// Fill colour.
    pub fn fill(self) -> &'static str {
        match self {
            G3NodeKind::Event => "#000000",
            G3NodeKind::Validate => "#eaecee",
            G3NodeKind::Start => "#d5f5e3",
            G3NodeKind::State => "#d6eaf8",
            G3NodeKind::Stop => "#fdebd0",
            G3NodeKind::Ether => "#ffffff",
        }
    }
}

/// A node of a machine.
#[derive(Debug, Clone)]
pub(crate) struct G3Node {
    /// A unique identifier in the whole picture (`state.servo.start`,
    /// `state.task-main.control`, `validate.set`, `ether.servo`,
    /// `event.servo.request`).
    pub id: String,
    /// Its kind.
    pub kind: G3NodeKind,
    /// The state's name, `validate`, `ether`; the event's name.
    pub name: String,
    /// Lines under the name: the codel, `async`, the WCET.
    pub details: Vec<String>,
    /// The codel is `async`.
    pub is_async: bool,
}

/// What a machine edge is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum G3EdgeKind {
    /// From an event: the request, the component's start.
    Event,
    /// An immediate `yield`: the next state runs at once.
    Yield,
    /// A `pause::` yield: the next state runs at the task's next period.
    Pause,
    /// An interrupt or `kill`, leading to `stop`.
    Interrupt,
}

impl G3EdgeKind {
    /// A stable word for classes and legends.
    pub fn class(self) -> &'static str {
        match self {
            G3EdgeKind::Event => "event",
            G3EdgeKind::Yield => "yield",
            G3EdgeKind::Pause => "pause",
            G3EdgeKind::Interrupt => "interrupt",
        }
    }

    /// Colour.
    pub fn color(self) -> &'static str {
        match self {
            G3EdgeKind::Event => "#7f8c8d",
            G3EdgeKind::Yield => "#1c2833",
            G3EdgeKind::Pause => "#2874a6",
            G3EdgeKind::Interrupt => "#b9770e",
        }
    }

    /// Dashed (`pause`) or dotted (interrupt).
    pub fn dashed(self) -> bool {
        self == G3EdgeKind::Pause
    }

    /// Dotted.
    pub fn dotted(self) -> bool {
        self == G3EdgeKind::Interrupt
    }
}

/// An edge of a machine.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct G3Edge {
    /// Source index in [`G3Machine::nodes`].
    pub from: usize,
    /// Target index.
    pub to: usize,
    /// Its kind.
    pub kind: G3EdgeKind,
    /// Its label (`pause`, `request`, `kill`...), may be empty.
    pub label: String,
}

/// Task colours (the control task's is [`CONTROL_COLOR`]).
const PALETTE: [&str; 8] = [
    "#d6eaf8", "#d5f5e3", "#fcf3cf", "#f5eef8", "#d1f2eb", "#fdebd0", "#ebdef0", "#e8f8f5",
];

/// The control task's colour.
const CONTROL_COLOR: &str = "#eaecee";

impl G3Diagrams {
    /// Builds the diagrams of a GenoM3 component.
    pub(crate) fn build(c: &Component, g: &Genom3Info) -> G3Diagrams {
        let mut groups = vec![TaskGroup {
            id: "cluster.control".to_owned(),
            title: "control task".to_owned(),
            detail: "requests, validate codels, functions and attributes".to_owned(),
            color: CONTROL_COLOR,
            boxes: Vec::new(),
        }];
        for (k, (tid, _)) in c.threads.iter().enumerate() {
            groups.push(task_group(c, g, tid, PALETTE[k % PALETTE.len()]));
        }
        let mut boxes = Vec::new();
        let mut machines = Vec::new();
        for (k, (tid, t)) in c.threads.iter().enumerate() {
            let group = k + 1;
            if let Some(task) = task_of(g, tid).filter(|t| !t.codels.is_empty()) {
                let detail = groups
                    .get(group)
                    .map_or_else(String::new, |g| g.detail.clone());
                machines.push(permanent(&t.name.name, &detail, &task.codels, group));
                boxes.push(permanent_box(&t.name.name, &task.codels, group));
            }
            for (sid, s) in activities(c, g).filter(|(_, s)| thread_of(s) == Some(tid)) {
                machines.push(activity(c, g, sid, group));
                boxes.push(activity_box(c, g, sid, s, group));
            }
        }
        for (sid, s) in activities(c, g).filter(|(_, s)| thread_of(s).is_none()) {
            machines.push(activity(c, g, sid, 0));
            boxes.push(activity_box(c, g, sid, s, 0));
        }
        let table = ControlTable::build(c, g);
        if !table.rows.is_empty() {
            boxes.insert(
                0,
                G3Box {
                    id: "table.control".to_owned(),
                    kind: BoxKind::Table,
                    lines: Vec::new(),
                    group: 0,
                },
            );
        }
        for (k, b) in boxes.iter().enumerate() {
            if let Some(group) = groups.get_mut(b.group) {
                group.boxes.push(k);
            }
        }
        G3Diagrams {
            component: c.name.name.clone(),
            overview: G3Overview {
                groups,
                boxes,
                table,
            },
            machines,
        }
    }
}

fn task_of(g: &Genom3Info, tid: ThreadId) -> Option<&genom_model::component::genom3::Task> {
    g.tasks.iter().find(|t| t.thread == tid)
}

fn thread_of(s: &Service) -> Option<ThreadId> {
    s.thread.map(|r| r.id)
}

/// The GenoM3 facts about a service.
pub(crate) fn info_of(g: &Genom3Info, sid: ServiceId) -> Option<&ServiceInfo> {
    g.services.iter().find(|i| i.service == sid)
}

/// The activities, in source order.
fn activities<'a>(
    c: &'a Component,
    g: &'a Genom3Info,
) -> impl Iterator<Item = (ServiceId, &'a Service)> + 'a {
    c.services
        .iter()
        .filter(move |(sid, _)| info_of(g, *sid).is_some_and(|i| i.kind == "activity"))
}

fn task_group(c: &Component, g: &Genom3Info, tid: ThreadId, color: &'static str) -> TaskGroup {
    let t = &c.threads[tid];
    let mut parts = vec![t.period.map_or_else(
        || "aperiodic".to_owned(),
        |p| format!("period {}", duration(p.ns)),
    )];
    if let Some(task) = task_of(g, tid) {
        if let Some(d) = task.delay {
            parts.push(format!("delay {}", duration(d.ns)));
        }
        if task.real_time {
            parts.push("real-time".to_owned());
        }
    }
    TaskGroup {
        id: format!("cluster.task.{}", t.name.name),
        title: format!("task {}", t.name.name),
        detail: parts.join(", "),
        color,
        boxes: Vec::new(),
    }
}

/// The states of FSM codels, in source order, each once.
fn states(codels: &[FsmCodel]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for s in codels.iter().flat_map(|f| &f.states) {
        if !out.contains(&s.name) {
            out.push(s.name.clone());
        }
    }
    out
}

fn permanent_box(task: &str, codels: &[FsmCodel], group: usize) -> G3Box {
    G3Box {
        id: format!("permanent.{task}"),
        kind: BoxKind::Permanent,
        lines: vec![
            "permanent codels".to_owned(),
            format!("states {}", states(codels).join(", ")),
        ],
        group,
    }
}

fn activity_box(c: &Component, g: &Genom3Info, sid: ServiceId, s: &Service, group: usize) -> G3Box {
    let fsm: Vec<FsmCodel> = activity_codels(g, s);
    let mut lines = vec![format!("activity {}", s.name.name)];
    let st = states(&fsm);
    lines.push(if st.is_empty() {
        "no codel".to_owned()
    } else {
        format!("states {}", st.join(", "))
    });
    lines.extend(relations(c, g, sid, s));
    G3Box {
        id: format!("service.{}", s.name.name),
        kind: BoxKind::Activity,
        lines,
        group,
    }
}

/// `throw`, `interrupts`, `after`, `before` lines of a service.
pub(crate) fn relations(c: &Component, g: &Genom3Info, sid: ServiceId, s: &Service) -> Vec<String> {
    let names = |list: &[genom_model::component::Ref<ServiceId>]| {
        list.iter()
            .filter_map(|r| c.services.get(r.id).map(|s| s.name.name.clone()))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut out = Vec::new();
    if !s.reports.is_empty() {
        out.push(format!("throw {}", thrown(c, s)));
    }
    let info = info_of(g, sid);
    if info.is_some_and(|i| i.interrupts_all) {
        out.push("interrupts all".to_owned());
    } else if !s.stops.is_empty() {
        out.push(format!("interrupts {}", names(&s.stops)));
    }
    if let Some(i) = info {
        if !i.after.is_empty() {
            out.push(format!("after {}", names(&i.after)));
        }
        if !i.before.is_empty() {
            out.push(format!("before {}", names(&i.before)));
        }
    }
    out
}

/// The exceptions a service throws, without the component's scope.
fn thrown(c: &Component, s: &Service) -> String {
    let scope = format!("{}::", c.name.name);
    let names: Vec<&str> = s
        .reports
        .iter()
        .map(|r| r.name.strip_prefix(&scope).unwrap_or(&r.name))
        .collect();
    names.join(", ")
}

/// An activity's FSM codels (one per distinct codel, in source order).
fn activity_codels(g: &Genom3Info, s: &Service) -> Vec<FsmCodel> {
    let mut out: Vec<FsmCodel> = Vec::new();
    for info in s
        .codels
        .iter()
        .filter_map(|&k| g.codels.iter().find(|i| i.codel == k))
    {
        let seen = out.iter().any(|f| f.span == info.fsm.span);
        if !info.fsm.states.is_empty() && Some(info.codel) != s.control && !seen {
            out.push(info.fsm.clone());
        }
    }
    out
}

/// Builds a machine's nodes and edges.
struct MachineBuilder {
    prefix: String,
    nodes: Vec<G3Node>,
    edges: Vec<G3Edge>,
    /// How many event edges lead the list.
    leading: usize,
}

impl MachineBuilder {
    fn new(prefix: String) -> Self {
        MachineBuilder {
            prefix,
            nodes: Vec::new(),
            edges: Vec::new(),
            leading: 0,
        }
    }

    fn node(&mut self, id: String, kind: G3NodeKind, name: &str, details: Vec<String>) -> usize {
        self.nodes.push(G3Node {
            id,
            kind,
            name: name.to_owned(),
            details,
            is_async: false,
        });
        self.nodes.len() - 1
    }

    fn event(&mut self, what: &str) -> usize {
        let id = format!("event.{}.{what}", self.prefix);
        self.node(id, G3NodeKind::Event, what, Vec::new())
    }

    fn edge(&mut self, from: usize, to: usize, kind: G3EdgeKind, label: &str) {
        let e = G3Edge {
            from,
            to,
            kind,
            label: label.to_owned(),
        };
        if !self.edges.contains(&e) {
            if kind == G3EdgeKind::Event {
                self.edges.insert(self.leading, e);
                self.leading += 1;
            } else {
                self.edges.push(e);
            }
        }
    }

    /// One node per state of `codels`, WCETs from `wcet_of` (state name),
    /// then `ether` if yielded to; the yields. Returns the state nodes by
    /// name and `ether`.
    fn states(
        &mut self,
        codels: &[FsmCodel],
        wcet_of: &dyn Fn(&str, &FsmCodel) -> Option<u64>,
    ) -> (Vec<(String, usize)>, Option<usize>) {
        let mut by_name: Vec<(String, usize)> = Vec::new();
        for f in codels {
            for st in &f.states {
                if by_name.iter().any(|(n, _)| *n == st.name) {
                    continue;
                }
                let kind = match st.name.as_str() {
                    "start" => G3NodeKind::Start,
                    "stop" => G3NodeKind::Stop,
                    _ => G3NodeKind::State,
                };
                let details = codel_lines(f, wcet_of(&st.name, f));
                let id = format!("state.{}.{}", self.prefix, st.name);
                let k = self.node(id, kind, &st.name, details);
                if let Some(n) = self.nodes.get_mut(k) {
                    n.is_async = f.is_async;
                }
                by_name.push((st.name.clone(), k));
            }
        }
        let ends = codels
            .iter()
            .flat_map(|f| &f.yields)
            .any(|y| y.state.name == "ether");
        let ether = ends.then(|| {
            let id = format!("ether.{}", self.prefix);
            self.node(id, G3NodeKind::Ether, "ether", Vec::new())
        });
        let find = |name: &str| by_name.iter().find(|(n, _)| n == name).map(|e| e.1);
        for f in codels {
            for st in &f.states {
                let Some(from) = find(&st.name) else { continue };
                for y in &f.yields {
                    let to = if y.state.name == "ether" {
                        ether
                    } else {
                        find(&y.state.name)
                    };
                    let Some(to) = to else { continue };
                    if y.pause {
                        self.edge(from, to, G3EdgeKind::Pause, "pause");
                    } else {
                        self.edge(from, to, G3EdgeKind::Yield, "");
                    }
                }
            }
        }
        (by_name, ether)
    }
}

/// The lines under a state: its codel, `async`, its WCET when known.
fn codel_lines(f: &FsmCodel, wcet: Option<u64>) -> Vec<String> {
    let mut out = vec![if f.is_async {
        format!("async codel {}", f.function.name)
    } else {
        format!("codel {}", f.function.name)
    }];
    if let Some(ns) = wcet {
        out.push(format!("WCET {}", duration(ns)));
    }
    out
}

fn permanent(task: &str, detail: &str, codels: &[FsmCodel], group: usize) -> G3Machine {
    let mut b = MachineBuilder::new(format!("task-{task}"));
    let spawn = b.event("spawn");
    let (by_name, _) = b.states(codels, &|_, f| f.wcet.map(|w| w.ns));
    let find = |name: &str| by_name.iter().find(|(n, _)| n == name).map(|e| e.1);
    if let Some(start) = find("start") {
        b.edge(spawn, start, G3EdgeKind::Event, "component start");
    }
    if let Some(stop) = find("stop") {
        let kill = b.event("kill");
        b.edge(kill, stop, G3EdgeKind::Interrupt, "kill");
        move_to(&mut b, kill, 1);
    }
    finish(
        b,
        format!("machine.task-{task}"),
        format!("task {task}: permanent codels"),
        detail.to_owned(),
        group,
    )
}

fn activity(c: &Component, g: &Genom3Info, sid: ServiceId, group: usize) -> G3Machine {
    let s = &c.services[sid];
    let name = &s.name.name;
    let mut b = MachineBuilder::new(name.clone());
    let request = b.event("request");
    let mut at = request;
    let validate = s
        .control
        .and_then(|k| g.codels.iter().find(|i| i.codel == k));
    if let Some(v) = validate {
        let wcet = s.control.and_then(|k| c.codels.get(k)).and_then(|k| k.wcet);
        let details = codel_lines(&v.fsm, wcet.map(|w| w.ns));
        let v = b.node(
            format!("validate.{name}"),
            G3NodeKind::Validate,
            "validate",
            details,
        );
        b.edge(request, v, G3EdgeKind::Event, "request");
        at = v;
    }
    let fsm = activity_codels(g, s);
    let wcet_of = |state: &str, _: &FsmCodel| {
        s.codels
            .iter()
            .filter(|&&k| Some(k) != s.control)
            .filter_map(|&k| c.codels.get(k))
            .find(|k| k.name.name == state)
            .and_then(|k| k.wcet)
            .map(|w| w.ns)
    };
    let (by_name, ether) = b.states(&fsm, &wcet_of);
    let find = |name: &str| by_name.iter().find(|(n, _)| n == name).map(|e| e.1);
    let label = if at == request { "request" } else { "valid" };
    match (find("start"), ether) {
        (Some(start), _) => b.edge(at, start, G3EdgeKind::Event, label),
        (None, Some(e)) => b.edge(at, e, G3EdgeKind::Event, label),
        (None, None) => {
            let e = b.node(
                format!("ether.{name}"),
                G3NodeKind::Ether,
                "ether",
                Vec::new(),
            );
            b.edge(at, e, G3EdgeKind::Event, "no codel");
        }
    }
    if let Some(stop) = find("stop") {
        let interrupt = b.event("interrupt");
        b.edge(interrupt, stop, G3EdgeKind::Interrupt, "interrupt");
        move_to(&mut b, interrupt, 1);
    }
    let mut detail = match thread_of(s) {
        Some(t) => format!("task {}", c.threads[t].name.name),
        None => "no task".to_owned(),
    };
    if !s.reports.is_empty() {
        let _ = write!(detail, ", throw {}", thrown(c, s));
    }
    finish(
        b,
        format!("machine.{name}"),
        format!("activity {name}"),
        detail,
        group,
    )
}

/// Moves node `from` to position `to`, renumbering the edges.
fn move_to(b: &mut MachineBuilder, from: usize, to: usize) {
    if from >= b.nodes.len() || to > from {
        return;
    }
    let node = b.nodes.remove(from);
    b.nodes.insert(to, node);
    let map = |k: usize| {
        if k == from {
            to
        } else if k >= to && k < from {
            k + 1
        } else {
            k
        }
    };
    for e in &mut b.edges {
        e.from = map(e.from);
        e.to = map(e.to);
    }
}

fn finish(b: MachineBuilder, id: String, title: String, detail: String, group: usize) -> G3Machine {
    G3Machine {
        id,
        title,
        detail,
        group,
        nodes: b.nodes,
        edges: b.edges,
    }
}
