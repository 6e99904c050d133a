//! Data flow inside one component: which codel of which task reads which
//! datum (an in port, an ids member, a service's local) and writes which
//! (an ids member, a local, an out port), read off the codels' parameters
//! (`genom_model::component::genom3::CodelParam`). A cause-effect chain
//! crosses a component from the codel that reads its in port, through
//! ids members, to the codel that writes its out port.
//!
//! Only codels that run on a task are followed: the permanent codels of
//! each task and the codels of the activities clients call in the steady
//! state (all of them unless the system file lists them). Functions and
//! attributes run on the control thread when a client calls them; the
//! steady state has no such call.

use std::collections::BTreeSet;

use genom_model::component::genom3::{CodelParam, FsmCodel, ParamSource};
use genom_model::component::{Component, Idx, ServiceId, ThreadId};

/// A datum codels read and write.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Datum {
    /// A port, by name.
    Port(String),
    /// An ids member, by its first member name (`""`: the whole ids).
    Ids(String),
    /// A local or parameter of one service.
    Local(usize, String),
}

impl Datum {
    /// Whether a write of `self` can change what a read of `other` sees.
    pub fn overlaps(&self, other: &Datum) -> bool {
        match (self, other) {
            (Datum::Ids(a), Datum::Ids(b)) => a == b || a.is_empty() || b.is_empty(),
            (a, b) => a == b,
        }
    }

    /// How the datum reads in a trace.
    pub fn describe(&self) -> String {
        match self {
            Datum::Port(p) => format!("port `{p}`"),
            Datum::Ids(m) if m.is_empty() => "the whole ids".to_owned(),
            Datum::Ids(m) => format!("ids `{m}`"),
            Datum::Local(_, n) => format!("local `{n}`"),
        }
    }
}

/// One FSM codel on a task.
#[derive(Debug, Clone)]
pub struct Site {
    /// The task's thread.
    pub thread: ThreadId,
    /// The task's name.
    pub task: String,
    /// The activity (`None`: the task's permanent codels).
    pub service: Option<ServiceId>,
    /// The owner's name (the task's for a permanent codel).
    pub owner: String,
    /// The codel function.
    pub function: String,
    /// The states it runs in.
    pub states: Vec<String>,
    /// What it reads.
    pub reads: Vec<Datum>,
    /// What it writes.
    pub writes: Vec<Datum>,
}

impl Site {
    /// `owner.state` (the first state) and the function, for traces.
    pub fn label(&self) -> String {
        let state = self.states.first().map_or("", String::as_str);
        format!("{}.{state} ({})", self.owner, self.function)
    }
}

/// Reads a parameter into the data it reads and writes.
fn datum(p: &CodelParam, service: Option<ServiceId>) -> Option<Datum> {
    let root = p
        .path
        .split(['.', '['])
        .next()
        .unwrap_or_default()
        .trim()
        .to_owned();
    match p.source {
        ParamSource::Port => Some(Datum::Port(root)),
        ParamSource::Ids if root.starts_with(':') => Some(Datum::Ids(String::new())),
        ParamSource::Ids => Some(Datum::Ids(root)),
        ParamSource::Local => service.map(|s| Datum::Local(s.index(), root)),
        ParamSource::Remote => None,
    }
}

fn site(c: &Component, thread: ThreadId, service: Option<ServiceId>, fsm: &FsmCodel) -> Site {
    let mut reads = Vec::new();
    let mut writes = Vec::new();
    for p in &fsm.params {
        let Some(d) = datum(p, service) else { continue };
        let dir = p.dir.as_str();
        if dir == "in" || dir == "inout" {
            reads.push(d.clone());
        }
        if dir == "out" || dir == "inout" {
            writes.push(d);
        }
    }
    let task = c.threads[thread].name.name.clone();
    Site {
        thread,
        owner: service.map_or(task.clone(), |s| c.services[s].name.name.clone()),
        task,
        service,
        function: fsm.function.name.clone(),
        states: fsm.states.iter().map(|s| s.name.clone()).collect(),
        reads,
        writes,
    }
}

/// The codels on tasks of `c`: permanent codels, then those of the
/// activities `steady` admits (all when `None`), each FSM codel once.
pub fn sites(c: &Component, steady: Option<&BTreeSet<ServiceId>>) -> Vec<Site> {
    let Some(g) = c.genom3.as_deref() else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for t in &g.tasks {
        for fsm in &t.codels {
            out.push(site(c, t.thread, None, fsm));
        }
    }
    let mut seen = BTreeSet::new();
    for info in &g.codels {
        let sid = c.codels[info.codel].service;
        let Some(thread) = c.services[sid].thread.map(|t| t.id) else {
            continue;
        };
        if steady.is_some_and(|s| !s.contains(&sid)) {
            continue;
        }
        if seen.insert((sid, info.fsm.span.start, info.fsm.function.name.clone())) {
            out.push(site(c, thread, Some(sid), &info.fsm));
        }
    }
    out
}
