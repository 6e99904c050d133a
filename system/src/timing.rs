//! Each component's timing, as the chains use it: which periodic tasks
//! the timed engine proves never to overrun (every wake-up's work ends
//! before the next tick), from the component's WCET file, in the steady
//! state the system file states (services it does not list are taken as
//! never requested: their codels run in no time, which admits every run
//! where they are not requested). A chain crosses only such tasks; for
//! any other it says why it has no number.

use std::collections::BTreeSet;

use genom_engine::genom3::Machine;
use genom_engine::genom3::timed::analysis::analyse_timing;
use genom_engine::kernel::explore::Limits;
use genom_model::component::{Component, Duration, ServiceId, ThreadId};
use serde::Serialize;

/// One task's timing.
#[derive(Debug, Clone, Serialize)]
pub struct TaskTiming {
    /// Its thread (not serialised).
    #[serde(skip)]
    pub thread: ThreadId,
    /// Its name.
    pub name: String,
    /// Its period, when periodic.
    pub period_ns: Option<u64>,
    /// How long after its tick a wake-up's codels may still run: the
    /// period for a task proven never to overrun.
    pub window_ns: Option<u64>,
    /// Why the task gives chains no bound (`None`: it does).
    pub unbounded: Option<String>,
}

/// A component's tasks' timing.
#[derive(Debug, Clone, Serialize)]
pub struct ComponentTiming {
    /// The component's name in the system file.
    pub name: String,
    /// Its tasks, in declaration order.
    pub tasks: Vec<TaskTiming>,
    /// Timed states the engine explored for it.
    pub states: u64,
}

impl ComponentTiming {
    /// The timing of the task on `thread`.
    pub fn task(&self, thread: ThreadId) -> Option<&TaskTiming> {
        self.tasks.iter().find(|t| t.thread == thread)
    }
}

/// `c` with every codel of a service outside `steady` taking no time.
fn steady_copy(c: &Component, steady: &BTreeSet<ServiceId>) -> Component {
    let mut copy = c.clone();
    let zero = |d: &mut Option<Duration>| {
        let span = d.map(|x| x.span).unwrap_or_default();
        *d = Some(Duration { ns: 0, span });
    };
    let ids: Vec<_> = copy.codels.ids().collect();
    for k in ids {
        let Some(codel) = copy.codels.get_mut(k) else {
            continue;
        };
        if !steady.contains(&codel.service) {
            zero(&mut codel.wcet);
        }
    }
    if let Some(g) = copy.genom3.as_mut() {
        for info in &mut g.codels {
            if !steady.contains(&c.codels[info.codel].service) {
                zero(&mut info.fsm.wcet);
            }
        }
    }
    copy
}

/// The timing of `c`'s tasks (named `name` in the system file), in the
/// steady state where clients call only `steady` (all services when
/// `None`).
pub fn component_timing(
    name: &str,
    c: &Component,
    steady: Option<&BTreeSet<ServiceId>>,
    limits: Limits,
) -> ComponentTiming {
    let copy = steady.map(|s| steady_copy(c, s));
    let model = copy.as_ref().unwrap_or(c);
    let mut out = ComponentTiming {
        name: name.to_owned(),
        tasks: Vec::new(),
        states: 0,
    };
    let Some(m) = Machine::new(model, 1) else {
        return out;
    };
    let analysis = analyse_timing(&m, limits);
    out.states = analysis.as_ref().map_or(0, |a| a.states);
    for (t, task) in m.tasks.iter().enumerate() {
        let period_ns = task.period_ns;
        let missing = missing_wcet(&m, t);
        let unbounded = if period_ns.is_none() {
            Some(format!(
                "task `{}` of `{name}` has no period: nothing bounds when it runs",
                task.name
            ))
        } else if let Some(codel) = missing {
            Some(format!(
                "codel `{codel}` on task `{}` of `{name}` has no WCET in its WCET file",
                task.name
            ))
        } else {
            match &analysis {
                None => Some(format!(
                    "the timed engine does not model `{name}` (too many tasks)"
                )),
                Some(a) if a.overruns.iter().any(|o| o.task == t) => Some(format!(
                    "task `{}` of `{name}` can overrun its period (`genom-check check` on the component shows how)",
                    task.name
                )),
                Some(a) => {
                    let decided = a.bounded.contains(&t)
                        || a
                            .records
                            .iter()
                            .any(|g| g.complete && g.tasks.contains(&t));
                    (!decided).then(|| {
                        format!(
                            "the timed exploration of `{name}` stopped before deciding task `{}`",
                            task.name
                        )
                    })
                }
            }
        };
        out.tasks.push(TaskTiming {
            thread: task.thread,
            name: task.name.clone(),
            period_ns,
            window_ns: if unbounded.is_none() { period_ns } else { None },
            unbounded,
        });
    }
    out
}

/// The first codel of task `t` (its permanent codels, its activities'
/// codels, the control codels that can lock against them) without a
/// WCET, by function name.
fn missing_wcet(m: &Machine<'_>, t: usize) -> Option<String> {
    let perm = m.tasks[t].perm.iter().flat_map(|f| f.states.iter());
    let acts = m
        .activities
        .iter()
        .filter(|a| a.task == t)
        .flat_map(|a| a.fsm.states.iter());
    let ctls = m.control_codels.values().flatten();
    perm.chain(acts)
        .chain(ctls)
        .find(|s| s.wcet_ns.is_none())
        .map(|s| s.function.clone())
}

/// The services named `names` in `c`, or the names that name none.
pub fn services_named<'a>(
    c: &Component,
    names: impl IntoIterator<Item = &'a str>,
) -> Result<BTreeSet<ServiceId>, Vec<&'a str>> {
    let mut found = BTreeSet::new();
    let mut unknown = Vec::new();
    for n in names {
        match c.service_named(n) {
            Some(s) => {
                found.insert(s);
            }
            None => unknown.push(n),
        }
    }
    // Built-in services (genom's) stay: they are requested by tools.
    if let Some(g) = c.genom3.as_deref() {
        for i in &g.services {
            if i.interface.as_deref() == Some("genom") {
                found.insert(i.service);
            }
        }
    }
    if unknown.is_empty() {
        Ok(found)
    } else {
        Err(unknown)
    }
}
