//! The behavioural stage of a GenoM3 check: the GenoM3 engine
//! ([`crate::genom3`]) explores the component under GenoM3's own execution
//! semantics, and its findings become diagnostics: `dead-service` (never
//! accepted or started), `unreachable-codel` (a codel of an activity or of
//! a task's permanent machine that no execution runs), `livelock` and
//! `unpaused-loop`, and `incomplete` when a limit stopped it. With WCETs
//! (`--wcet`), the timed GenoM3 engine ([`crate::genom3::timed`]) adds
//! `thread-overrun` (schedulability of every periodic task).

use std::collections::BTreeSet;
use std::time::Instant;

use genom_model::component::{Component, ServiceId};
use genom_model::stats::{Decision, Method as Decider};
use genom_model::{Assumption, Diagnostic, ResponseTime, Span, Statistics, Trace};

use crate::checks::{
    codel_overrun, dead_service, incomplete, livelock, response_time, thread_overrun,
    unreachable_codel,
};
use crate::genom3::steps::Engine;
use crate::genom3::timed::analysis::{Cause, TimingAnalysis, analyse_timing};
use crate::genom3::timed::response::analyse_responses;
use crate::genom3::trace::refusal;
use crate::genom3::{G3Analysis, Machine, Owner, analyse_machine_by, machine::Fsm};
use crate::verify::CheckOptions;

/// What the GenoM3 engines found about a component.
#[derive(Debug, Clone)]
pub struct Genom3Verdicts {
    /// The behavioural diagnostics.
    pub diagnostics: Vec<Diagnostic>,
    /// The explorations' figures.
    pub statistics: Statistics,
    /// Worst-case response times (with `--response-times` or a
    /// `--deadline`, and WCETs).
    pub response_times: Vec<ResponseTime>,
    /// The traces of codels longer than their period (by FSM codel span),
    /// for the static `codel-overrun` diagnostics.
    pub long_codels: Vec<(Span, Trace)>,
}

impl Genom3Verdicts {
    /// Gives each `codel-overrun` among `diagnostics` (the static stage's)
    /// the trace the timed engine found for its codel.
    pub fn attach_codel_overrun_traces(&self, diagnostics: &mut [Diagnostic]) {
        codel_overrun::attach_traces(&self.long_codels, diagnostics);
    }
}

/// Explores a GenoM3 component (`None` for a LANGUAGE.md component).
pub fn verify_genom3(
    c: &Component,
    options: &CheckOptions,
    started: Instant,
) -> Option<Genom3Verdicts> {
    let m = Machine::new(c, options.instance_bound())?;
    let analysis = analyse_machine_by(&m, options.limits(started), true, options.kernel_method());
    let mut out = Vec::new();
    if analysis.stopped.is_none() {
        out.extend(dead_services(c, &m, &analysis));
        out.extend(unreached_codels(&m, &analysis));
    }
    out.extend(livelock::check(&m, &analysis));
    let names = |tasks: &[usize], services: &[ServiceId]| -> Vec<String> {
        let tasks = tasks.iter().map(|&t| format!("task {}", m.tasks[t].name));
        let services = services.iter().map(|&s| m.service_name(s).to_owned());
        tasks.chain(services).collect()
    };
    if let Some(stop) = analysis.stopped {
        let (done, open): (Vec<_>, Vec<_>) = analysis
            .parts
            .iter()
            .filter(|p| !p.superseded)
            .partition(|p| p.complete);
        let listed = |parts: &[&crate::genom3::analysis::PartRecord]| -> String {
            let tasks = parts.iter().flat_map(|p| &p.tasks);
            let services = parts.iter().flat_map(|p| &p.services);
            let all: Vec<String> = tasks
                .map(|&t| format!("task `{}`", m.tasks[t].name))
                .chain(services.map(|&s| format!("`{}`", m.service_name(s))))
                .collect();
            all.join(", ")
        };
        let what = if open.is_empty() {
            "dead services, codel reachability and livelocks (GenoM3 semantics)".to_owned()
        } else {
            format!(
                "dead services, codel reachability and livelocks of {} (GenoM3 semantics)",
                listed(&open)
            )
        };
        let proven: Vec<String> = if done.is_empty() {
            Vec::new()
        } else {
            vec![format!(
                "the untimed verdicts of {} (their parts were explored to the end)",
                listed(&done)
            )]
        };
        let spent = format!(
            "{} states in {:.1} s",
            genom_model::limits::grouped(analysis.states),
            started.elapsed().as_secs_f64()
        );
        out.push(incomplete::incomplete_partly(
            c, stop, &what, &proven, &spent,
        ));
    }
    let (mut states, mut transitions) = (analysis.states, analysis.transitions);
    let mut footprint = analysis.footprint;
    let mut decided_by: Vec<Decision> = analysis
        .parts
        .iter()
        .map(|p| {
            let who = names(&p.tasks, &p.services);
            let how = if p.symbolic {
                Decider::Symbolic
            } else {
                Decider::Exhaustive
            };
            Decision::new(who, how, p.states, p.complete)
        })
        .collect();
    let mut long_codels = Vec::new();
    let timed = gives_timing(&m);
    if timed {
        match analyse_timing(&m, options.limits(started)) {
            Some(timing) => {
                decided_by.extend(timing.records.iter().map(|g| {
                    let who = names(&g.tasks, &g.services);
                    let how = if g.by_bound {
                        Decider::Bound
                    } else if g.witnessed {
                        Decider::Witnesses
                    } else {
                        Decider::Zones
                    };
                    Decision::new(who, how, g.states, g.complete)
                }));
                // Tasks of explored groups that the bound alone decides.
                let explored = |t: &usize| {
                    timing
                        .records
                        .iter()
                        .any(|g| !g.by_bound && g.tasks.contains(t))
                };
                decided_by.extend(
                    timing
                        .bounded
                        .iter()
                        .filter(|t| explored(t))
                        .map(|&t| Decision::new(names(&[t], &[]), Decider::Bound, 0, true)),
                );
                out.extend(thread_overrun::check_genom3(&m, &timing));
                long_codels = codel_overrun::genom3_traces(&m, &timing);
                if let Some(stop) = timing.stopped {
                    let mut proven = proven_timing(&m, &timing);
                    if analysis.stopped.is_none() {
                        proven.push(
                            "the untimed verdicts (dead services, codel reachability, livelocks)"
                                .to_owned(),
                        );
                    }
                    let spent = format!(
                        "{} timed states in {:.1} s",
                        genom_model::limits::grouped(timing.states),
                        started.elapsed().as_secs_f64()
                    );
                    out.push(incomplete::incomplete_partly(
                        c,
                        stop,
                        &unproven_timing(&m, &timing),
                        &proven,
                        &spent,
                    ));
                }
                states += timing.states;
                transitions += timing.transitions;
                footprint.join(timing.footprint);
            }
            None => out.push(incomplete::timing_not_modelled(
                c,
                "a component with more than 32 tasks",
            )),
        }
    }
    let mut response_times = Vec::new();
    if !timed {
        out.extend(
            options
                .deadline_ids(c)
                .into_iter()
                .map(|(s, ns)| incomplete::deadline_without_wcet(c, s, ns)),
        );
    } else if options.wants_response_times() {
        let deadlines = options.deadline_ids(c);
        if let Some(r) = analyse_responses(&m, options.limits(started), &deadlines) {
            response_times = response_time::response_times(c, &r.found);
            let checked = response_time::check(c, &r.found, &response_times, &deadlines);
            // A deadline left undecided already says it is incomplete.
            let said = checked
                .iter()
                .any(|d| d.code == genom_model::Code::Incomplete);
            out.extend(checked);
            if let (Some(stop), false) = (r.stopped, said) {
                out.push(response_time::unfinished(c, stop, &response_times, started));
            }
            states += r.states;
            transitions += r.transitions;
        }
    }
    let stats = Statistics {
        states,
        transitions,
        time_ms: started.elapsed().as_secs_f64() * 1000.0,
        complete: out.iter().all(|d| d.code != genom_model::Code::Incomplete),
        bytes_per_state: Some(footprint.bytes_per_state),
        decided_by,
        // Timing depends on how many requests run at once (F4); the
        // untimed verdicts do not (section 14.3 of docs/genom3-semantics.md).
        assumptions: if timed {
            vec![Assumption::instances(
                m.max_instances,
                m.has_self_interrupts(),
            )]
        } else {
            Vec::new()
        },
    };
    Some(Genom3Verdicts {
        diagnostics: out,
        statistics: stats,
        response_times,
        long_codels,
    })
}

/// Whether some codel has a WCET (from a WCET file).
fn gives_timing(m: &Machine<'_>) -> bool {
    let fsm_states = m
        .activities
        .iter()
        .map(|a| &a.fsm)
        .chain(m.tasks.iter().filter_map(|t| t.perm.as_ref()))
        .flat_map(|f| f.states.iter());
    fsm_states
        .chain(m.control_codels.values().flatten())
        .any(|s| s.wcet_ns.is_some())
}

/// Services no execution accepts (an activity: starts), with the reason.
fn dead_services(c: &Component, m: &Machine<'_>, a: &G3Analysis) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let engine = Engine::new(m.clone());
    for (sid, _) in c.services.iter() {
        if a.started.contains(&sid) || m.is_builtin(sid) {
            continue;
        }
        let (reason, why) = dead_reason(m, a, sid);
        let trace = match why {
            Some(why) => refusal(&engine, &a.boot, sid, &why),
            None => Trace::default(),
        };
        out.push(dead_service::dead_service(c, sid, &reason, trace));
    }
    out
}

/// Why `sid` is dead, and, when `after` refuses it, the refusal the trace
/// shows.
fn dead_reason(m: &Machine<'_>, a: &G3Analysis, sid: ServiceId) -> (String, Option<String>) {
    let names = |v: Vec<ServiceId>| -> String {
        v.iter()
            .map(|s| format!("`{}`", m.service_name(*s)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let never: Vec<ServiceId> = m
        .after
        .get(&sid)
        .into_iter()
        .flatten()
        .copied()
        .filter(|x| !a.completed.contains(x))
        .collect();
    if !never.is_empty() {
        let list = names(never);
        return (
            format!(
                "it is declared `after` {list}, which no execution completes successfully: every request is refused with `genom::disallowed`"
            ),
            Some(format!("it is `after` {list}, which has not completed")),
        );
    }
    (
        "no execution lets a request for it be accepted and started".to_owned(),
        None,
    )
}

/// Codels that the state machine leads to (from `start`, or from `stop`
/// after an interruption) but no execution runs; dead services are left to
/// `dead-service`.
fn unreached_codels(m: &Machine<'_>, a: &G3Analysis) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let owners = (0..m.activities.len())
        .map(Owner::Activity)
        .chain((0..m.tasks.len()).map(Owner::Task));
    for owner in owners {
        if let Owner::Activity(x) = owner {
            if !a.started.contains(&m.activities[x].service) {
                continue;
            }
        }
        let fsm = m.fsm(owner);
        let mut seen_spans = BTreeSet::new();
        for s in statically_reachable(fsm) {
            if a.reached.contains(&(owner, s)) {
                continue;
            }
            let st = &fsm.states[usize::from(s)];
            if !seen_spans.insert((st.span, st.name.clone())) {
                continue;
            }
            let who = match owner {
                Owner::Activity(x) => format!("activity `{}`", m.activity_name(x)),
                Owner::Task(t) => format!("task `{}`", m.tasks[t].name),
            };
            out.push(unreachable_codel::never_run_genom3(
                &who,
                &st.name,
                &st.function,
                st.span,
            ));
        }
    }
    out
}

/// States some path of yields reaches from `start` or from `stop`.
fn statically_reachable(fsm: &Fsm) -> BTreeSet<u8> {
    let mut seen = BTreeSet::new();
    let mut todo: Vec<u8> = fsm.start.into_iter().chain(fsm.stop).collect();
    while let Some(s) = todo.pop() {
        if !seen.insert(s) {
            continue;
        }
        for t in &fsm.states[usize::from(s)].yields {
            if let crate::genom3::machine::Target::State { state, .. } = *t {
                todo.push(state);
            }
        }
    }
    seen
}

/// The tasks whose schedulability is decided: those of a group explored
/// to the end, and those the static bound clears (semantics 15.12), even
/// in a group whose exploration stopped.
fn decided_tasks(timing: &TimingAnalysis) -> BTreeSet<usize> {
    timing
        .records
        .iter()
        .filter(|g| g.complete)
        .flat_map(|g| g.tasks.iter().copied())
        .chain(timing.bounded.iter().copied())
        .chain(every_cause_shown(timing))
        .collect()
}

/// The tasks of unfinished groups that have shown an overrun for every
/// cause the static bound leaves possible (docs/genom3-semantics.md 15.14).
fn every_cause_shown(timing: &TimingAnalysis) -> impl Iterator<Item = usize> + '_ {
    let found: BTreeSet<usize> = timing.overruns.iter().map(|o| o.task).collect();
    timing
        .open_causes
        .iter()
        .filter(move |(t, open)| open.is_empty() && found.contains(t))
        .map(|(&t, _)| t)
}

/// The tasks a stopped timed exploration proved never overrun: decided,
/// periodic, and not found overrunning.
fn proven_timing(m: &Machine<'_>, timing: &TimingAnalysis) -> Vec<String> {
    let found: BTreeSet<usize> = timing.overruns.iter().map(|o| o.task).collect();
    let never = decided_tasks(timing)
        .into_iter()
        .filter(|t| !found.contains(t) && m.tasks[*t].period_ns.is_some())
        .map(|t| format!("task `{}` never overruns", m.tasks[t].name));
    let shown = every_cause_shown(timing).map(|t| {
        format!(
            "every cause of overrun of task `{}` is shown",
            m.tasks[t].name
        )
    });
    never.chain(shown).collect()
}

/// A cause of overrun, as a noun phrase.
fn cause_phrase(m: &Machine<'_>, cause: Cause) -> String {
    match cause {
        Cause::LongCodel(owner, state) => {
            let codel = &m.fsm(owner).states[usize::from(state)];
            format!("codel `{}` longer than the period", codel.function)
        }
        Cause::LockWait => "a lock wait".to_owned(),
        Cause::Chain => "a chain of codels without `pause::`".to_owned(),
        Cause::Shared => "its instances' codels together".to_owned(),
    }
}

/// What an unfinished timed exploration leaves unproven, task by task: a
/// decided task ([`decided_tasks`]) is not listed; of the others, one
/// found overrunning has its traces (other causes may be missing), and one
/// not found may or may not overrun.
fn unproven_timing(m: &Machine<'_>, timing: &TimingAnalysis) -> String {
    let decided = decided_tasks(timing);
    let found: BTreeSet<usize> = timing.overruns.iter().map(|o| o.task).collect();
    let name = |t: &usize| format!("`{}`", m.tasks[*t].name);
    let open: Vec<usize> = (0..m.tasks.len())
        .filter(|t| !decided.contains(t))
        .collect();
    let (overrun, unknown): (Vec<usize>, Vec<usize>) =
        open.into_iter().partition(|t| found.contains(t));
    let mut parts = Vec::new();
    if !unknown.is_empty() {
        let names: Vec<String> = unknown.iter().map(name).collect();
        parts.push(format!("whether task {} can overrun", names.join(", ")));
    }
    for t in &overrun {
        let open = timing.open_causes.get(t).into_iter().flatten();
        let open: Vec<String> = open.map(|&c| cause_phrase(m, c)).collect();
        let still = if open.is_empty() {
            String::new()
        } else {
            format!("; still possible: {}", open.join(", "))
        };
        parts.push(format!(
            "other causes of overrun of task {} (an overrun was found{still})",
            name(t)
        ));
    }
    if parts.is_empty() {
        return "schedulability of the tasks (GenoM3 timed semantics)".to_owned();
    }
    format!("{} (GenoM3 timed semantics)", parts.join("; "))
}
