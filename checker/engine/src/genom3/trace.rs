//! Traces of the GenoM3 engine: each transition as a [`TraceStep`] that
//! names the service, the task, the state whose codel ran and the yield it
//! took, so that a trace reads as GenoM3 users think of their component
//! and can be replayed independently (`genom_oracles::replay::genom3`, a
//! test oracle).
//!
//! Step vocabulary (the replay reads `event`, `service`, `thread`, `codel`
//! and `outcome`):
//!
//! | event | service | codel | outcome |
//! |---|---|---|---|
//! | `reject` (thread `control`) | the service | | `genom::disallowed` |
//! | `accept` (thread `control`) | the activity, function or attribute | | `pending` when it waits for instances it interrupted |
//! | `interrupt` (thread `control`) | the instance's activity | its state, or none if not started | `abort_activity` |
//! | `start` | the activity | the start state | |
//! | `codel-end` | the activity (none for a permanent codel) | the state | the yield: `s`, `pause::s`, `ether`, or `exception` (any exception the codel may throw; the text names them) |
//! | `violation` | | | |

use genom_model::trace::{Event, Trace, TraceStep};

use super::machine::{ControlKind, Owner, Target};
use super::state::{G3State, Inst, Phase, Status};
use super::steps::{Engine, G3Action};

/// The trace of `path` from the initial state.
pub fn render(engine: &Engine<'_>, path: &[G3Action]) -> Trace {
    let states = engine.states_along(path);
    let text = if engine.m.tasks.iter().any(|t| t.perm.is_some()) {
        "the component starts: task by task, each permanent activity runs its first codel before any request is handled"
    } else {
        "the component starts (no task has permanent codels): requests are handled at once"
    };
    let mut steps = vec![TraceStep::new(Event::ComponentStart, text)];
    for (k, &a) in path.iter().enumerate() {
        steps.push(step(engine, &states[k], &states[k + 1], a));
        if let G3Action::Start(x, _, o) = a {
            let owner = Owner::Activity(usize::from(x));
            if let Some(st) = engine.m.activities[usize::from(x)].fsm.start {
                steps.push(codel_text(engine, owner, st, o, &states[k], &states[k + 1]));
            }
        }
    }
    Trace {
        steps,
        loop_start: None,
    }
}

/// The trace of a request for `service` refused with `genom::disallowed`
/// once the component runs (after the `boot` steps); `why` says which
/// `after`/`before` refuses it.
pub fn refusal(
    engine: &Engine<'_>,
    boot: &[G3Action],
    service: genom_model::component::ServiceId,
    why: &str,
) -> Trace {
    let mut trace = render(engine, boot);
    let name = engine.m.service_name(service);
    let mut s = control_step(Event::Reject, name);
    s.outcome = Some("genom::disallowed".to_owned());
    s.span = Some(engine.m.c.services[service].name.span);
    s.text = format!(
        "the control thread refuses a request for `{name}` with `genom::disallowed`: {why}"
    );
    trace.steps.push(s);
    trace
}

/// A `codel-end` step: `owner` runs the codel of `state` and yields `to`.
pub fn codel_step(engine: &Engine<'_>, owner: Owner, state: u8, to: &str) -> TraceStep {
    let fsm = engine.m.fsm(owner);
    let st = &fsm.states[usize::from(state)];
    let mut s = TraceStep::new(Event::CodelEnd, String::new());
    s.thread = Some(engine.m.tasks[engine.m.task_of(owner)].name.clone());
    if let Owner::Activity(a) = owner {
        s.service = Some(engine.m.activity_name(a).to_owned());
    }
    s.codel = Some(st.name.clone());
    s.outcome = Some(to.to_owned());
    s.span = Some(st.span);
    s
}

pub(crate) fn step(
    engine: &Engine<'_>,
    before: &G3State,
    after: &G3State,
    a: G3Action,
) -> TraceStep {
    let m = &engine.m;
    match a {
        G3Action::Accept(x) => {
            let x = usize::from(x);
            let name = m.activity_name(x);
            let pending = after.inst[x].iter().any(|i| i.status == Status::Delayed);
            let mut s = control_step(Event::Accept, name);
            s.text = if pending {
                s.outcome = Some("pending".to_owned());
                format!(
                    "the control thread accepts a request for activity `{name}`; it interrupts the instances it names and waits for them to end"
                )
            } else {
                format!(
                    "the control thread accepts a request for activity `{name}` (validate succeeded)"
                )
            };
            s.span = Some(m.c.services[m.activities[x].service].name.span);
            s
        }
        G3Action::Call(k) => {
            let ctl = &m.controls[usize::from(k)];
            let name = m.service_name(ctl.service);
            let mut s = control_step(Event::Accept, name);
            s.text = match ctl.kind {
                ControlKind::Kill => {
                    "`kill` succeeds: every activity is interrupted, then the component shuts down"
                        .to_owned()
                }
                _ => format!("`{name}` runs on the control thread and succeeds"),
            };
            s.span = Some(m.c.services[ctl.service].name.span);
            s
        }
        G3Action::Abort(x, v) => {
            let x = usize::from(x);
            let name = m.activity_name(x);
            let mut s = control_step(Event::Interrupt, name);
            s.outcome = Some("abort_activity".to_owned());
            let i = Inst::unpack(v);
            s.codel = i.filter(|i| i.running()).map(|i| {
                m.fsm(Owner::Activity(x)).states[usize::from(i.state)]
                    .name
                    .clone()
            });
            s.text = format!("`abort_activity` interrupts an instance of `{name}`");
            s
        }
        G3Action::Start(x, _, _) => {
            let x = usize::from(x);
            let name = m.activity_name(x);
            let mut s = TraceStep::new(
                Event::Start,
                format!(
                    "an instance of `{name}` starts at its task's next sweep, which runs its first codel at once"
                ),
            );
            s.thread = Some(m.tasks[m.activities[x].task].name.clone());
            s.service = Some(name.to_owned());
            s.codel = m.activities[x]
                .fsm
                .start
                .map(|st| m.activities[x].fsm.states[usize::from(st)].name.clone());
            s
        }
        G3Action::Codel(x, v, o) => {
            let owner = Owner::Activity(usize::from(x));
            let state = Inst::unpack(v).map_or(0, |i| i.state);
            codel_text(engine, owner, state, o, before, after)
        }
        G3Action::Perm(t, o) => {
            let owner = Owner::Task(usize::from(t));
            let state = before.perm[usize::from(t)].map_or(0, |i| i.state);
            codel_text(engine, owner, state, o, before, after)
        }
    }
}

fn control_step(event: Event, service: &str) -> TraceStep {
    let mut s = TraceStep::new(event, String::new());
    s.thread = Some("control".to_owned());
    s.service = Some(service.to_owned());
    s
}

pub(crate) fn codel_text(
    engine: &Engine<'_>,
    owner: Owner,
    state: u8,
    o: u8,
    before: &G3State,
    after: &G3State,
) -> TraceStep {
    let fsm = engine.m.fsm(owner);
    let to = outcome_name(engine, owner, state, o);
    let mut s = codel_step(engine, owner, state, &to);
    let who = describe(engine, owner);
    let st = &fsm.states[usize::from(state)];
    let yields = match fsm.states[usize::from(state)].yields.get(usize::from(o)) {
        Some(Target::State { pause: true, .. }) => {
            format!("yields `{to}` (it waits for its task's next wake-up)")
        }
        Some(Target::State { .. }) => format!("yields `{to}` (run in the same sweep loop)"),
        Some(Target::Ether) => format!("yields `{to}`: the instance ends, success"),
        None => format!(
            "yields an exception ({}): the instance ends with it",
            exceptions(engine, owner)
        ),
    };
    s.text = format!(
        "{who} runs codel `{}` in state `{}`, which {yields}",
        st.function, st.name
    );
    if before.phase != after.phase {
        s.text.push_str(match after.phase {
            Phase::Run => "; every task has started: requests are handled from now on",
            Phase::Stopped => "; the component has stopped",
            Phase::Failed => "; the component fails to start",
            _ => "",
        });
    }
    s
}

/// The exceptions the `exception` outcome of `owner`'s codels stands
/// for: those its service (or task) declares with `throw`, or a built-in
/// `genom::` one (the engine does not tell them apart).
pub fn exceptions(engine: &Engine<'_>, owner: Owner) -> String {
    let c = engine.m.c;
    let declared: Vec<&str> = match owner {
        Owner::Activity(a) => c.services[engine.m.activities[a].service]
            .reports
            .iter()
            .map(|r| r.name.as_str())
            .collect(),
        Owner::Task(t) => c
            .genom3
            .as_ref()
            .and_then(|g| {
                g.tasks
                    .iter()
                    .find(|x| x.thread == engine.m.tasks[t].thread)
            })
            .map(|x| x.throws.iter().map(|r| r.name.as_str()).collect())
            .unwrap_or_default(),
    };
    exception_list(&declared)
}

/// The exceptions a codel of a service or task that declares `declared`
/// (its `throw`s) may end with: those, or a built-in `genom::` one.
pub fn exception_list(declared: &[&str]) -> String {
    let mut names: Vec<String> = declared
        .iter()
        .map(|n| format!("`{}`", n.trim_start_matches("::")))
        .collect();
    names.sort();
    names.dedup();
    match names.as_slice() {
        [] => "a built-in `genom::…` one, since no `throw` is declared".to_owned(),
        [one] => format!("{one} or a built-in `genom::…` one"),
        [init @ .., last] => format!("{}, {last} or a built-in `genom::…` one", init.join(", ")),
    }
}

/// The name of outcome `o` of `state`'s codel.
pub fn outcome_name(engine: &Engine<'_>, owner: Owner, state: u8, o: u8) -> String {
    let fsm = engine.m.fsm(owner);
    match fsm.states[usize::from(state)].yields.get(usize::from(o)) {
        Some(Target::State { state, pause }) => {
            let n = &fsm.states[usize::from(*state)].name;
            if *pause {
                format!("pause::{n}")
            } else {
                n.clone()
            }
        }
        Some(Target::Ether) => "ether".to_owned(),
        None => "exception".to_owned(),
    }
}

/// `activity `a`` or `the permanent activity of task `t``.
pub fn describe(engine: &Engine<'_>, owner: Owner) -> String {
    match owner {
        Owner::Activity(a) => format!("activity `{}`", engine.m.activity_name(a)),
        Owner::Task(t) => format!(
            "the permanent activity of task `{}`",
            engine.m.tasks[t].name
        ),
    }
}
