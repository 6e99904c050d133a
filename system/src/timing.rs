//! Each component's timing, as the chains use it: which periodic tasks
//! the timed engine proves never to overrun (every wake-up's work ends
//! before the next tick), from the component's WCET file, in the steady
//! state the system file states (services it does not list are never
//! requested: the engine explores only the others' requests). A chain crosses only such tasks; for
//! any other it says why it has no number.

use std::collections::BTreeSet;

use genom_engine::genom3::Machine;
use genom_engine::genom3::machine::{Owner, Role};
use genom_engine::genom3::timed::analysis::analyse_timing;
use genom_engine::genom3::timed::windows::codel_windows;
use genom_engine::kernel::explore::Limits;
use genom_model::component::{Component, ServiceId, ThreadId};
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

/// The latest end of one codel after its wake-up's tick, as the timed
/// engine explored it.
#[derive(Debug, Clone, Serialize)]
pub struct CodelWindow {
    /// Its task's thread (not serialised).
    #[serde(skip)]
    pub thread: ThreadId,
    /// Its activity (`None`: the task's permanent codels; not serialised).
    #[serde(skip)]
    pub service: Option<ServiceId>,
    /// `owner.state`.
    pub codel: String,
    /// Its latest end after the tick.
    pub end_ns: u64,
}

/// A component's tasks' timing.
#[derive(Debug, Clone, Serialize)]
pub struct ComponentTiming {
    /// The component's name in the system file.
    pub name: String,
    /// Its tasks, in declaration order.
    pub tasks: Vec<TaskTiming>,
    /// Per codel of its periodic tasks, its latest end after the tick
    /// (empty when the exploration could not give them: then windows are
    /// whole periods).
    pub windows: Vec<CodelWindow>,
    /// Timed states the engine explored for it.
    pub states: u64,
}

impl ComponentTiming {
    /// The timing of the task on `thread`.
    pub fn task(&self, thread: ThreadId) -> Option<&TaskTiming> {
        self.tasks.iter().find(|t| t.thread == thread)
    }

    /// The latest end after the tick of the codel of `service` (`None`:
    /// permanent) on `thread` running in `state`, when explored.
    pub fn window(&self, thread: ThreadId, service: Option<ServiceId>, state: &str) -> Option<u64> {
        self.windows
            .iter()
            .find(|w| {
                w.thread == thread
                    && w.service == service
                    && w.codel.rsplit_once('.').is_some_and(|(_, s)| s == state)
            })
            .map(|w| w.end_ns)
    }
}

/// `m` without the activities and control services outside `steady`
/// (kept: GenoM3's built-in services): the timed engine then explores
/// only requests of the steady services.
fn restrict(m: &mut Machine<'_>, steady: &BTreeSet<ServiceId>) {
    let keep_act: Vec<bool> = m
        .activities
        .iter()
        .map(|a| steady.contains(&a.service))
        .collect();
    let keep_ctl: Vec<bool> = m
        .controls
        .iter()
        .map(|k| k.builtin || steady.contains(&k.service))
        .collect();
    let mut new_index = Vec::with_capacity(keep_act.len());
    let mut n = 0;
    for &k in &keep_act {
        new_index.push(k.then_some(n));
        n += usize::from(k);
    }
    let remap = |v: &mut Vec<usize>| {
        *v = v
            .iter()
            .filter_map(|&i| new_index.get(i).copied().flatten())
            .collect();
    };
    let mut kept = keep_act.iter();
    m.activities
        .retain(|_| kept.next().copied().unwrap_or(false));
    let mut kept = keep_ctl.iter();
    m.controls.retain(|_| kept.next().copied().unwrap_or(false));
    for a in &mut m.activities {
        remap(&mut a.interrupts);
    }
    for k in &mut m.controls {
        remap(&mut k.interrupts);
    }
    m.role.clear();
    for (i, a) in m.activities.iter().enumerate() {
        m.role.insert(a.service, Role::Activity(i));
    }
    for (i, k) in m.controls.iter().enumerate() {
        m.role.insert(k.service, Role::Control(i));
    }
    let roles: BTreeSet<ServiceId> = m.role.keys().copied().collect();
    m.control_codels.retain(|s, _| roles.contains(s));
    for map in [&mut m.after, &mut m.before] {
        map.retain(|s, _| roles.contains(s));
        for v in map.values_mut() {
            v.retain(|s| roles.contains(s));
        }
    }
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
    let mut out = ComponentTiming {
        name: name.to_owned(),
        tasks: Vec::new(),
        windows: Vec::new(),
        states: 0,
    };
    let Some(mut m) = Machine::new(c, 1) else {
        return out;
    };
    if let Some(s) = steady {
        restrict(&mut m, s);
    }
    let analysis = analyse_timing(&m, limits);
    let overruns = analysis.as_ref().is_none_or(|a| !a.overruns.is_empty());
    if !overruns && let Some(found) = codel_windows(&m, limits) {
        for ((owner, state), end_ns) in found {
            let (thread, service, name) = match owner {
                Owner::Task(t) => (m.tasks[t].thread, None, m.tasks[t].name.clone()),
                Owner::Activity(a) => {
                    let sid = m.activities[a].service;
                    (
                        m.tasks[m.activities[a].task].thread,
                        Some(sid),
                        c.services[sid].name.name.clone(),
                    )
                }
            };
            let Some(st) = m.fsm(owner).states.get(usize::from(state)) else {
                continue;
            };
            out.windows.push(CodelWindow {
                thread,
                service,
                codel: format!("{name}.{}", st.name),
                end_ns,
            });
        }
    }
    out.states = analysis.as_ref().map_or(0, |a| a.states);
    for (t, task) in m.tasks.iter().enumerate() {
        let period_ns = task.period_ns;
        let missing = missing_wcet(&m, t, steady);
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
                Some(a) if a.overruns.iter().any(|o| o.task == t) => {
                    let o = a.overruns.iter().find(|o| o.task == t);
                    let last = o
                        .and_then(|o| o.trace.steps.last())
                        .map(|s| s.text.clone())
                        .unwrap_or_default();
                    Some(format!(
                        "task `{}` of `{name}` can overrun its period in the steady state ({last})",
                        task.name
                    ))
                }
                Some(a) => {
                    let decided = a.bounded.contains(&t)
                        || a.records.iter().any(|g| g.complete && g.tasks.contains(&t));
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
/// codels, the control codels of the steady services) without a WCET, by
/// function name. GenoM3's own copies of an attribute's data (`ids copy`)
/// have none to give.
fn missing_wcet(m: &Machine<'_>, t: usize, steady: Option<&BTreeSet<ServiceId>>) -> Option<String> {
    let perm = m.tasks[t].perm.iter().flat_map(|f| f.states.iter());
    let acts = m
        .activities
        .iter()
        .filter(|a| a.task == t)
        .flat_map(|a| a.fsm.states.iter());
    let ctls = m
        .control_codels
        .iter()
        .filter(|(s, _)| steady.is_none_or(|set| set.contains(s)))
        .flat_map(|(_, v)| v)
        .filter(|s| s.codel.is_some());
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
