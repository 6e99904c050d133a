//! What a check established about a component, as recorded in exports:
//! whether it is verified (no error, exploration complete), the codes of
//! the errors that prevent it, and the properties proven.
//!
//! A property is listed only when the check actually establishes it:
//!
//! - the behavioural ones (`deadlock-free`, `no-starvation`,
//!   `every-service-can-start`, `interrupts-terminate`) and
//!   `static-semantics` whenever the component is verified, since their
//!   violations are errors;
//! - the ones whose violations are warnings (`every-codel-reachable`,
//!   `every-service-can-end`, `auto-services-run-forever`,
//!   `no-privilege-escalation`) only without such a warning;
//! - the timing ones, `thread-never-overruns:T` and `meets-max-time:S`,
//!   only when the timed engine ran and every codel that can influence
//!   them has a WCET: the codels of the services of its *timed cluster*
//!   (services linked by `stops`, `delays`, `forbids`, a shared thread, or
//!   conflicting codels, the grouping the timed engine explores), control
//!   codels included. A codel without WCET counts as taking no time, so a
//!   bound that depends on it is not proven (`missing-wcet`). A service
//!   whose max-time is only enforced by the watchdog (`max-time-watchdog`)
//!   does not meet it.
//!
//! A property is written `kind` or `kind:subject` (a thread or service
//! name); [`describe`] gives its parts and a sentence.

use std::collections::BTreeSet;

use genom_model::component::genom3::Genom3Info;
use genom_model::component::{Component, ServiceId};
use genom_model::duration::format_ns;
use genom_model::kinds::ServiceKind;
use genom_model::{Code, Counts, Diagnostic, Severity, Statistics};

use crate::Verification;

/// Proven by every verified component.
const ALWAYS: [&str; 5] = [
    "static-semantics",
    "deadlock-free",
    "no-starvation",
    "every-service-can-start",
    "interrupts-terminate",
];

/// Properties whose violation is a warning: (property, code).
const UNLESS_WARNED: [(&str, Code); 4] = [
    ("every-codel-reachable", Code::UnreachableCodel),
    ("every-service-can-end", Code::NoTermination),
    ("auto-services-run-forever", Code::AutoTerminates),
    ("no-privilege-escalation", Code::PrivilegeEscalation),
];

impl Verification {
    /// The verification record of a check: `component` is the resolved
    /// component (none after parse errors), `diagnostics` all the check's
    /// diagnostics, `statistics` the exploration figures (none when the
    /// engines did not run).
    pub fn of(
        component: Option<&Component>,
        diagnostics: &[Diagnostic],
        statistics: Option<&Statistics>,
        tool_version: &str,
    ) -> Self {
        let counts = Counts::of(diagnostics);
        let complete = statistics.is_some_and(|s| s.complete);
        let verified = counts.errors == 0 && complete && component.is_some();
        let error_codes: BTreeSet<&str> = diagnostics
            .iter()
            .filter(|d| d.severity == Severity::Error)
            .map(|d| d.code.as_str())
            .collect();
        let properties = match component {
            Some(c) if verified => proven(c, diagnostics),
            _ => Vec::new(),
        };
        Verification {
            verified,
            counts,
            states: statistics.map_or(0, |s| s.states),
            transitions: statistics.map_or(0, |s| s.transitions),
            complete,
            properties,
            error_codes: error_codes.into_iter().map(str::to_owned).collect(),
            tool_version: tool_version.to_owned(),
            assumptions: statistics.map_or_else(Vec::new, |s| s.assumptions.clone()),
            response_times: Vec::new(),
        }
    }
}

/// Proven by every verified GenoM3 component (its engines report the
/// violations of these as errors).
const GENOM3_ALWAYS: [&str; 3] = ["static-semantics", "every-service-can-start", "no-livelock"];

/// GenoM3's properties whose violation is a warning: (property, code).
const GENOM3_UNLESS_WARNED: [(&str, Code); 2] = [
    ("every-codel-reachable", Code::UnreachableCodel),
    ("no-unpaused-loop", Code::UnpausedLoop),
];

/// The properties a verified component's check proves, in a fixed order:
/// the general ones, then threads and services in source order.
pub fn proven(c: &Component, diagnostics: &[Diagnostic]) -> Vec<String> {
    let warned = |code: Code| diagnostics.iter().any(|d| d.code == code);
    if let Some(g) = &c.genom3 {
        return proven_genom3(c, g, &warned);
    }
    let mut out: Vec<String> = ALWAYS.iter().map(|p| (*p).to_owned()).collect();
    for (property, code) in UNLESS_WARNED {
        let applies = property != "auto-services-run-forever"
            || c.services.values().any(|s| s.kind == ServiceKind::Auto);
        if applies && !warned(code) {
            out.push(property.to_owned());
        }
    }
    if !c.gives_timing() {
        return out;
    }
    let clusters = c.timed_cluster_roots();
    let timed = |members: &dyn Fn(ServiceId) -> bool| {
        let cluster: BTreeSet<usize> = c
            .services
            .ids()
            .filter(|&s| members(s))
            .map(|s| clusters[s.0 as usize])
            .collect();
        c.codels
            .values()
            .filter(|k| cluster.contains(&clusters[k.service.0 as usize]))
            .all(|k| k.wcet.is_some())
    };
    for (tid, t) in c.threads.iter() {
        let on_thread = |s: ServiceId| c.services[s].thread.is_some_and(|r| r.id == tid);
        if t.period.is_some() && timed(&on_thread) {
            out.push(format!("thread-never-overruns:{}", t.name.name));
        }
    }
    for (sid, s) in c.services.iter() {
        let watchdog = diagnostics
            .iter()
            .any(|d| d.code == Code::MaxTimeWatchdog && d.span() == s.name.span);
        if s.max_time.is_some() && !watchdog && timed(&|x| x == sid) {
            out.push(format!("meets-max-time:{}", s.name.name));
        }
    }
    out
}

/// The properties a verified GenoM3 component's check proves. Task
/// overruns are proven only when every codel of the component, the
/// permanent ones and the control task's included, has a WCET: a codel
/// without one counts as taking no time, and with GenoM3's locks and the
/// control task's queue any codel can delay any task.
fn proven_genom3(c: &Component, g: &Genom3Info, warned: &dyn Fn(Code) -> bool) -> Vec<String> {
    let mut out: Vec<String> = GENOM3_ALWAYS.iter().map(|p| (*p).to_owned()).collect();
    for (property, code) in GENOM3_UNLESS_WARNED {
        if !warned(code) {
            out.push(property.to_owned());
        }
    }
    let task_codels = || g.tasks.iter().flat_map(|t| t.codels.iter());
    let every =
        c.codels.values().all(|k| k.wcet.is_some()) && task_codels().all(|k| k.wcet.is_some());
    let any =
        c.codels.values().any(|k| k.wcet.is_some()) || task_codels().any(|k| k.wcet.is_some());
    if any && every {
        for t in c.threads.values().filter(|t| t.period.is_some()) {
            out.push(format!("thread-never-overruns:{}", t.name.name));
        }
    }
    out
}

/// A property's kind, subject (a thread or service name) and a sentence
/// saying what it means for this component.
pub fn describe(c: &Component, property: &str) -> (String, Option<String>, String) {
    let (kind, subject) = match property.split_once(':') {
        Some((k, s)) => (k, Some(s.to_owned())),
        None => (property, None),
    };
    let statement = statement(c, kind, subject.as_deref().unwrap_or_default());
    (kind.to_owned(), subject, statement)
}

fn statement(c: &Component, kind: &str, subject: &str) -> String {
    match kind {
        "static-semantics" => "the description satisfies every static rule of the language".into(),
        "deadlock-free" => "no reachable state has pending instances waiting on each other".into(),
        "no-starvation" => {
            "no pending instance can wait forever on an instance that may never end".into()
        }
        "every-service-can-start" => "every service can be started (or, without start codel, accepted)".into(),
        "no-livelock" => "no task can sweep a cycle of codel transitions forever without `pause::` or `async`".into(),
        "no-unpaused-loop" => "no reachable cycle of codel transitions lacks a `pause::` or an `async` codel".into(),
        "interrupts-terminate" => "every interrupted service ends: its inter codels cannot loop forever".into(),
        "every-codel-reachable" => "every codel runs in some execution".into(),
        "every-service-can-end" => "every non-auto service can end by itself from every codel it reaches".into(),
        "auto-services-run-forever" => "no auto service can end by itself".into(),
        "no-privilege-escalation" => "no service requestable with a weaker credential stops, delays, forbids or feeds one that needs a stronger credential".into(),
        "thread-never-overruns" => {
            let period = c
                .thread_named(subject)
                .and_then(|t| c.threads[t].period)
                .map_or_else(String::new, |p| format!(" {}", format_ns(p.ns)));
            let word = c.dialect().thread_word();
            format!("{word} `{subject}` always finishes the codels of a period before its next{period} wake-up")
        }
        "meets-max-time" => {
            let limit = c
                .service_named(subject)
                .and_then(|s| c.services[s].max_time)
                .map_or_else(String::new, |m| format!(" of {}", format_ns(m.ns)));
            format!("every instance of `{subject}` sends its final reply within its max-time{limit} of its acknowledgment, without the watchdog")
        }
        _ => kind.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use genom_model::Span;

    use super::*;

    #[test]
    fn errors_make_a_check_unverified_and_are_listed_once_sorted() {
        let d = |code| Diagnostic::new(code, "m", Span::default(), "l");
        let diagnostics = [
            d(Code::Starvation),
            d(Code::Deadlock),
            d(Code::Starvation),
            d(Code::MissingWcet),
        ];
        let stats = Statistics {
            states: 7,
            transitions: 9,
            time_ms: 1.0,
            complete: true,
            bytes_per_state: None,
            decided_by: Vec::new(),
            assumptions: Vec::new(),
        };
        let v = Verification::of(None, &diagnostics, Some(&stats), "1.2.3");
        assert!(!v.verified);
        assert_eq!(v.error_codes, ["deadlock", "starvation"]);
        assert_eq!((v.states, v.transitions, v.complete), (7, 9, true));
        assert_eq!(v.counts.errors, 3);
        assert!(v.properties.is_empty());
        assert_eq!(v.tool_version, "1.2.3");
    }

    #[test]
    fn without_statistics_nothing_is_verified() {
        let v = Verification::of(None, &[], None, "1");
        assert!(!v.verified && !v.complete);
        assert!(v.error_codes.is_empty());
    }
}
