//! Concrete timed traces of the timed GenoM3 model. A symbolic path is
//! fired again without extrapolation, with extra clocks: `T` (absolute
//! time, never reset) and one snapshot clock per step, reset at that step.
//! Any point of the final zone then gives consistent instants for the
//! whole path: step `i` happens at `T − sᵢ` (the technique of
//! `crate::timed::trace`).
//!
//! Step vocabulary, besides the untimed engine's ([`crate::genom3::trace`]):
//!
//! | event | thread | service | codel | outcome |
//! |---|---|---|---|---|
//! | `wake-up` | the task | | | `tick` (periodic) or `activation` (aperiodic) |
//! | `codel-start` | the task | the activity (none for a permanent codel) | the state | |
//!
//! Every step carries its instant.

use genom_model::duration::format_ns;
use genom_model::trace::{Event, Trace, TraceStep};

use super::{TG3Action, TG3State, TimedEngine, Who};
use crate::genom3::state::Inst;
use crate::genom3::trace::{codel_text, step};
use crate::zones::dbm::{le, lt};

/// The concrete trace of `path`, with `last` at the final instant.
pub fn timed_trace(te: &TimedEngine<'_>, path: &[TG3Action], last: TraceStep) -> Trace {
    timed_trace_beyond(te, path, last, None)
}

/// [`timed_trace`], its final instant chosen where clock `x` is beyond `c`
/// units (`(x, c, true)`: `x > c`; `(x, c, false)`: `x ≥ c + 1`). When the
/// path cannot get there, the final step has no instant.
pub fn timed_trace_beyond(
    te: &TimedEngine<'_>,
    path: &[TG3Action],
    last: TraceStep,
    beyond: Option<(usize, i64, bool)>,
) -> Trace {
    timed_trace_seeing(te, path, last, beyond, |_, _| {})
}

/// [`timed_trace_beyond`], calling `see` with the states before and after
/// each step of the path as it is fired (for what a trace reads off them,
/// [`super::aside`]).
pub fn timed_trace_seeing(
    te: &TimedEngine<'_>,
    path: &[TG3Action],
    last: TraceStep,
    beyond: Option<(usize, i64, bool)>,
    mut see: impl FnMut(&TG3State, &TG3State),
) -> Trace {
    let base = te.clock_count();
    let mut steps = vec![TraceStep::new(
        Event::ComponentStart,
        "the component starts; periodic tasks wake at their ticks, the first at their `delay`",
    )];
    // Per step, the action it belongs to (its instant); 0: the start.
    let mut marks = vec![0usize];
    let mut st = walk(te, path, |k, before, after, a| {
        see(before, after);
        for step in render(te, before, after, a) {
            marks.push(k + 1);
            steps.push(step);
        }
    });
    let mut trace = Trace {
        steps,
        loop_start: None,
    };
    if let Some((x, c, strict)) = beyond {
        let b = if strict { lt(-c) } else { le(-(c + 1)) };
        if !st.zone.constrain(0, x, b) {
            trace.steps.push(last);
            return trace;
        }
    }
    let Some((values, scale)) = st.zone.pick() else {
        trace.steps.push(last);
        return trace;
    };
    let now = values[base];
    let to_ns = |v: i64| {
        let ns = i128::from(v) * i128::from(te.unit) / i128::from(scale.max(1));
        u64::try_from(ns.max(0)).unwrap_or(u64::MAX)
    };
    trace.steps[0].time_ns = Some(0);
    for (step, &k) in trace.steps.iter_mut().zip(&marks).skip(1) {
        step.time_ns = Some(to_ns(now - values[base + k]));
    }
    let mut last = last;
    last.time_ns = Some(to_ns(now));
    trace.steps.push(last);
    trace
}

/// Fires `path` again without extrapolation, with the absolute clock and
/// one snapshot clock per step (see the module doc), calling `visit` with
/// each step's index, the states before and after it, and its action;
/// returns the last state reached.
fn walk(
    te: &TimedEngine<'_>,
    path: &[TG3Action],
    mut visit: impl FnMut(usize, &TG3State, &TG3State, TG3Action),
) -> TG3State {
    let base = te.clock_count();
    let mut st = te.start(1 + path.len());
    for (k, &a) in path.iter().enumerate() {
        let Some(mut next) = te.fire(&st, a) else {
            break;
        };
        te.follow_responses(&st, &mut next);
        next.zone.reset(base + 2 + k);
        let next = te.let_time_pass(next);
        visit(k, &st, &next, a);
        st = next;
    }
    st
}

/// The steps of action `a` from `before` to `after`: one, or for a request
/// taken, the request and then its first codel beginning or its ticket.
fn render(
    te: &TimedEngine<'_>,
    before: &TG3State,
    after: &TG3State,
    a: TG3Action,
) -> Vec<TraceStep> {
    let TG3Action::CtlBegin(job) = a else {
        return vec![render_one(te, before, after, a)];
    };
    let mut taken = before.clone();
    taken.ctl = Some(super::Ctl {
        job,
        phase: 0,
        running: false,
    });
    let first = match after.ctl {
        Some(c) if c.running => Some(TG3Action::CtlPhase),
        Some(_) if after.queue.contains(&super::CTL) => Some(TG3Action::CtlTicket),
        _ => None,
    };
    let mut out = vec![render_one(te, before, &taken, a)];
    out.extend(first.map(|f| render_one(te, &taken, after, f)));
    out
}

/// The step of action `a` from `before` to `after`.
fn render_one(
    te: &TimedEngine<'_>,
    before: &TG3State,
    after: &TG3State,
    a: TG3Action,
) -> TraceStep {
    let m = te.m();
    let task = |t: u8| m.tasks[usize::from(t)].name.clone();
    match a {
        TG3Action::Control(c) => step(&te.e, &before.g, &after.g, c),
        TG3Action::Tick(t) => {
            let p = format_ns(m.tasks[usize::from(t)].period_ns.unwrap_or(0));
            let text = if after.late >> t & 1 == 1 {
                format!(
                    "task `{}` reaches its tick (period {p}) still busy: the tick is coalesced, the task wakes again as soon as its work ends",
                    task(t)
                )
            } else if after.violation.is_some() {
                format!(
                    "task `{}` reaches its tick (period {p}) still busy",
                    task(t)
                )
            } else {
                format!(
                    "task `{}` wakes up at its tick (period {p}): accepted instances start, paused ones resume",
                    task(t)
                )
            };
            let mut s = TraceStep::new(Event::WakeUp, text);
            s.thread = Some(task(t));
            s.outcome = Some("tick".to_owned());
            s
        }
        TG3Action::Wake(t) => {
            let mut s = TraceStep::new(
                Event::WakeUp,
                format!(
                    "aperiodic task `{}` is activated: accepted instances start, paused ones resume",
                    task(t)
                ),
            );
            s.thread = Some(task(t));
            s.outcome = Some("activation".to_owned());
            s
        }
        TG3Action::CtlBegin(job) => {
            let name = te.job_service(job).map_or("", |s| m.service_name(s));
            let mut s = TraceStep::new(
                Event::Request,
                format!("the control thread takes a request for `{name}`"),
            );
            s.thread = Some("control".to_owned());
            s.service = Some(name.to_owned());
            s
        }
        TG3Action::CtlPhase | TG3Action::CtlEnd(_) => {
            let mut s = ctl_step(te, before, a);
            if let (TG3Action::CtlEnd(true), Some(c), None) = (a, before.ctl, after.ctl) {
                let effect = step(&te.e, &before.g, &after.g, c.job);
                s.text = format!("{}; {}", s.text, effect.text);
            }
            s
        }
        TG3Action::Begin(who, v) => task_codel_step(te, who, v, Event::CodelStart, |st| {
            let wcet = st
                .wcet_ns
                .map_or("no WCET".to_owned(), |w| format!("WCET {}", format_ns(w)));
            format!(
                "begins codel `{}` in state `{}` ({wcet})",
                st.function, st.name
            )
        }),
        TG3Action::End(who, v, o) => {
            let state = Inst::unpack(v).map_or(0, |i| i.state);
            codel_text(&te.e, who.owner(), state, o, &before.g, &after.g)
        }
        TG3Action::Ticket(who, v) => task_codel_step(te, who, v, Event::LockWait, |st| {
            let owner = who.owner();
            let k = te.locks.key(owner, Inst::unpack(v).map_or(0, |i| i.state));
            format!(
                "takes a ticket for codel `{}` in state `{}` and waits: {}",
                st.function,
                st.name,
                why_waiting(te, before, Some(m.task_of(owner)), k)
            )
        }),
        TG3Action::CtlTicket => ctl_step(te, before, a),
    }
}

/// A step of instance `v` of `who` about the codel of its state: `what`
/// says what happens to it, after the instance's description.
fn task_codel_step(
    te: &TimedEngine<'_>,
    who: Who,
    v: u16,
    event: Event,
    what: impl Fn(&crate::genom3::machine::FsmState) -> String,
) -> TraceStep {
    let m = te.m();
    let owner = who.owner();
    let state = Inst::unpack(v).map_or(0, |i| i.state);
    let st = &m.fsm(owner).states[usize::from(state)];
    let text = format!(
        "{} {}",
        crate::genom3::trace::describe(&te.e, owner),
        what(st)
    );
    let mut s = TraceStep::new(event, text);
    s.thread = Some(m.tasks[m.task_of(owner)].name.clone());
    if let Who::Act(x) = who {
        s.service = Some(m.activity_name(usize::from(x)).to_owned());
    }
    s.codel = Some(st.name.clone());
    s.span = Some(st.span);
    s
}

/// Why a codel (key `k`) of thread `t` (`None`: control) cannot begin in
/// `st`: a thread runs a codel it waits for, or older tickets are queued.
fn why_waiting(te: &TimedEngine<'_>, st: &TG3State, t: Option<usize>, k: usize) -> String {
    let m = te.m();
    let thread = |u: Option<usize>| {
        u.map_or("the control thread".to_owned(), |u| {
            format!("task `{}`", m.tasks[u].name)
        })
    };
    for u in (0..m.tasks.len()).filter(|&u| Some(u) != t) {
        if let Some((w, i)) = te.running(&st.g, u) {
            if te.locks.excludes(k, te.locks.key(w.owner(), i.state)) {
                let name = &m.fsm(w.owner()).states[usize::from(i.state)].name;
                return format!(
                    "{} runs `{name}`, which holds a lock it needs",
                    thread(Some(u))
                );
            }
        }
    }
    let ctl_holds = t.is_some()
        && st.ctl.is_some_and(|c| c.running)
        && te.ctl_codel(st).is_some_and(|j| te.locks.excludes(k, j));
    if ctl_holds {
        return "the control thread runs a codel that holds a lock it needs".to_owned();
    }
    let ahead: Vec<String> = st
        .queue
        .iter()
        .map(|&u| thread((u != super::CTL).then_some(usize::from(u))))
        .collect();
    format!(
        "older tickets are queued ahead of it ({}), GenoM3's resource queue serves them first",
        ahead.join(", ")
    )
}

/// The exceptions service `sid`'s control codel may throw, named.
fn thrown(te: &TimedEngine<'_>, sid: Option<genom_model::component::ServiceId>) -> String {
    let c = te.m().c;
    let declared: Vec<&str> = sid.map_or_else(Vec::new, |s| {
        c.services[s]
            .reports
            .iter()
            .map(|r| r.name.as_str())
            .collect()
    });
    crate::genom3::trace::exception_list(&declared)
}

/// A control codel beginning or ending.
fn ctl_step(te: &TimedEngine<'_>, before: &TG3State, a: TG3Action) -> TraceStep {
    let m = te.m();
    let sid = before.ctl.and_then(|c| te.job_service(c.job));
    let name = sid.map_or("", |s| m.service_name(s));
    // The phase counts the codels that take time; `job_codel` says which.
    let st = sid
        .zip(before.ctl.and_then(|c| te.job_codel(c)))
        .and_then(|(s, i)| m.control_codels.get(&s)?.get(i));
    let codel = st.map_or(String::new(), |x| x.name.clone());
    let function = st.map_or(String::new(), |x| x.function.clone());
    let (event, text, outcome) = match a {
        TG3Action::CtlEnd(true) => (
            Event::CodelEnd,
            format!("`{name}`'s control codel `{function}` ({codel}) succeeds"),
            Some("ok".to_owned()),
        ),
        TG3Action::CtlEnd(false) => (
            Event::CodelEnd,
            format!(
                "`{name}`'s control codel `{function}` ({codel}) throws an exception ({}): the request ends with it",
                thrown(te, sid)
            ),
            Some("exception".to_owned()),
        ),
        TG3Action::CtlTicket => (
            Event::LockWait,
            format!(
                "the control thread takes a ticket for `{name}`'s control codel `{function}` ({codel}) and waits: {}",
                te.ctl_codel(before)
                    .map_or(String::new(), |k| why_waiting(te, before, None, k))
            ),
            None,
        ),
        _ => (
            Event::CodelStart,
            format!("the control thread begins `{name}`'s control codel `{function}` ({codel})"),
            None,
        ),
    };
    let mut s = TraceStep::new(event, text);
    s.thread = Some("control".to_owned());
    s.service = Some(name.to_owned());
    s.codel = Some(codel);
    s.outcome = outcome;
    s.span = st.map(|x| x.span);
    s
}
