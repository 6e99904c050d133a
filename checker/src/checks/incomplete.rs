//! `incomplete`: a resource limit (states, time, memory) stopped
//! verification before it finished; the diagnostic names the properties
//! left unproven. Verdicts found before the limit (with their traces) stand;
//! nothing is claimed about what was not explored.

use genom_model::component::{Component, ServiceId};
use genom_model::{Code, Diagnostic};

use crate::dialect::{Analysis, Stop};

/// `genom-check explain incomplete`.
pub const EXPLANATION: &str = r#"A limit stopped verification before it explored every reachable state:
`--max-states`, `--timeout` or `--max-memory`. The message says which limit
and which properties are left unproven.

Why it matters: a verifier must never say "verified" when it did not finish.
Violations found before the limit are real (they come with traces), but the
absence of a violation is not proven, so the exit status is 1.

For a limit: raise it, or simplify the component: services that share no `stops`,
`delays` or `forbids` are verified separately, so cutting such links between
groups of services reduces the state space.

GenoM3 components: the message says which exploration stopped. The untimed
one (dead services, unreachable codels, livelocks) explores activities that
are linked by `interrupts`, `after` or `before` together; the timed one
(`--wcet FILE`: which tasks can overrun) explores together the tasks whose
codels wait for each other's locks (ids members, ports) or whose activities
are linked. An overrun found before the limit is real, with its trace; a
task without one is not proven schedulable. Raise `--timeout` or
`--max-states`, lower `--max-instances` if you raised it (each more
concurrent request of an activity multiplies the states), or cut links: an
activity on its own task that touches no ids member another task's codels
use is explored alone."#;

use super::registry::Explained;

/// The codes of this verdict, for the registry ([`super::VERDICTS`]).
pub const CODES: &[Explained] = &[(Code::Incomplete, EXPLANATION)];

/// Verification stopped by `stop`; `what` names the unproven properties.
pub fn incomplete(c: &Component, stop: Stop, what: &str) -> Diagnostic {
    let limit = match stop {
        Stop::States => "the state limit (--max-states) was reached",
        Stop::Time => "the time limit (--timeout) was reached",
        Stop::Memory => "the memory limit (--max-memory) was reached",
    };
    Diagnostic::new(
        Code::Incomplete,
        format!("verification is incomplete: {limit}"),
        c.name.span,
        "not fully verified",
    )
    .with_help(format!("left unproven: {what}; raise the limit to finish"))
}

/// [`incomplete`], also saying what the run did prove (`proven`, when
/// anything) and what it spent (`spent`: `2,447,164 states in 10.0 s`).
pub fn incomplete_partly(
    c: &Component,
    stop: Stop,
    what: &str,
    proven: &[String],
    spent: &str,
) -> Diagnostic {
    let d = incomplete(c, stop, what);
    let mut help = d.help.clone().unwrap_or_default();
    if !proven.is_empty() {
        help.push_str(&format!(". Proven: {}", proven.join("; ")));
    }
    help.push_str(&format!(". Stopped after {spent}"));
    d.with_help(help)
}

/// A component with WCETs whose timing the timed engine cannot model
/// (`what` says why): its untimed verdicts stand, its timing is unproven.
pub fn timing_not_modelled(c: &Component, what: &str) -> Diagnostic {
    Diagnostic::new(
        Code::Incomplete,
        format!("verification is incomplete: the timed engine does not model the timing of {what}"),
        c.name.span,
        "timing not verified",
    )
    .with_help(
        "the untimed verdicts (dead services, codel reachability, livelocks) stand; schedulability (`thread-overrun`) is left unproven",
    )
}

/// A `--deadline` on a GenoM3 component without WCETs: without durations
/// there is no response time to compare it with.
pub fn deadline_without_wcet(c: &Component, s: ServiceId, ns: u64) -> Diagnostic {
    let svc = &c.services[s];
    Diagnostic::new(
        Code::Incomplete,
        format!(
            "verification is incomplete: the deadline of `{}` ({}) is not decided: no codel has a WCET",
            svc.name.name,
            genom_model::duration::format_ns(ns)
        ),
        svc.name.span,
        "deadline not decided",
    )
    .with_help("give the codels' WCETs in a `--wcet` file: response times are computed in time")
}

/// The `incomplete` diagnostic, if exploration stopped early: what is left
/// unproven (the services of the clusters whose exploration stopped), what
/// was decided (the other services' verdicts, and with durations the
/// threads all of whose services were explored to the end), and what the
/// explorations spent.
pub fn check(c: &Component, analysis: &Analysis) -> Vec<Diagnostic> {
    let Some(stop) = analysis.stopped else {
        return Vec::new();
    };
    let quoted = |s: &ServiceId| format!("`{}`", c.services[*s].name.name);
    let names: Vec<String> = analysis.unproven.iter().map(quoted).collect();
    let scope = if names.is_empty() {
        "the component".to_owned()
    } else {
        format!("{} {}", plural("service", names.len()), names.join(", "))
    };
    let mut what = format!(
        "deadlock and starvation freedom, unbounded interrupts, dead services and codel reachability for {scope}"
    );
    let timed = c.gives_timing();
    let (open_threads, done_threads) = threads_by_decision(c, analysis);
    if timed && !open_threads.is_empty() {
        what.push_str(&format!(
            "; whether {} {} can overrun and {} services end within their `max-time`",
            plural("thread", open_threads.len()),
            open_threads.join(", "),
            if open_threads.len() == 1 {
                "its"
            } else {
                "their"
            }
        ));
    }
    let done: Vec<String> = c
        .services
        .ids()
        .filter(|s| !analysis.unproven.contains(s))
        .map(|s| quoted(&s))
        .collect();
    let mut proven = Vec::new();
    if !done.is_empty() {
        proven.push(format!(
            "the verdicts of {} {} (explored to the end)",
            plural("service", done.len()),
            done.join(", ")
        ));
    }
    if timed && !done_threads.is_empty() {
        proven.push(format!(
            "the timing of {} {} (`thread-overrun`, `max-time`)",
            plural("thread", done_threads.len()),
            done_threads.join(", ")
        ));
    }
    let spent = format!(
        "{} states in {:.1} s",
        genom_model::limits::grouped(analysis.states),
        analysis.elapsed.as_secs_f64()
    );
    vec![incomplete_partly(c, stop, &what, &proven, &spent)]
}

/// `word`, with an `s` when `n` is not 1.
fn plural(word: &str, n: usize) -> String {
    if n == 1 {
        word.to_owned()
    } else {
        format!("{word}s")
    }
}

/// The threads that run some service, quoted, split into those with a
/// service left unproven and those all of whose services were decided (a
/// thread's services are in one timed cluster: `Component::timed_clusters`).
fn threads_by_decision(c: &Component, analysis: &Analysis) -> (Vec<String>, Vec<String>) {
    let (mut open, mut done) = (Vec::new(), Vec::new());
    for (t, thread) in c.threads.iter() {
        let mut services = c
            .services
            .iter()
            .filter(|(_, s)| s.thread.map(|r| r.id) == Some(t))
            .map(|(id, _)| id)
            .peekable();
        if services.peek().is_none() {
            continue;
        }
        let name = format!("`{}`", thread.name.name);
        if services.any(|s| analysis.unproven.contains(&s)) {
            open.push(name);
        } else {
            done.push(name);
        }
    }
    (open, done)
}
