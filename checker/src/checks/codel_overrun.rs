//! `codel-overrun`: a codel whose WCET is longer than the period of the
//! thread that runs it (a static check on the WCETs).

use std::collections::BTreeSet;

use genom_model::component::genom3::{FsmCodel, Genom3Info};
use genom_model::component::{Component, ThreadId};
use genom_model::duration::format_ns;
use genom_model::kinds::CodelKind;
use genom_model::{Code, Diagnostic, Span, Trace};

use super::registry::{Applies, StaticCheck};
use crate::genom3::Machine;
use crate::genom3::timed::analysis::{Cause, TimingAnalysis};

/// `genom-check explain codel-overrun`.
pub const EXPLANATION: &str = r#"A codel whose worst-case execution time (its `max-time`) is longer than the
period of the thread that runs it.

Why it matters: a periodic thread runs one codel of each active service per
period; a codel that may take longer than the period makes the thread
overrun (its next wake-up finds the codel still running) whatever else
happens.

Example:

```
thread servo { period: 10ms; }
service servo {
  thread: servo;
  start codel { exec: step(); max-time: 12ms; next: start; }   // codel-overrun
}
```

Split the codel into shorter steps (codels chained with `next`), or run it
on a slower or aperiodic thread.

GenoM3 components (WCETs from `--wcet FILE`): a codel of an activity, or of
a task's permanent activity, whose WCET is longer than the period of its
task. GenoM3 never preempts a codel, so when it takes that long the task's
next tick finds it still running, whatever else the task does. It is
reported at the codel, with the timed trace of a tick that finds it
running, and it hides no other cause of overrun of the same task (those
are `thread-overrun`s of their own).

```
task t { period 50 ms; };
activity calibrate() {
  task t;
  codel<start> cal_run(out a) yield ether;     // WCET file: calibrate.start 70ms
};
```

Split the work into codels joined by `yield pause::…` (one per wake-up),
or move the activity to a task with a longer period."#;

/// The registry's entry ([`super::STATIC_CHECKS`]).
pub const CHECK: StaticCheck = StaticCheck {
    name: "codel overruns",
    applies: Applies::Always,
    run: check,
    codes: &[(Code::CodelOverrun, EXPLANATION)],
};

/// Codels whose WCET exceeds their thread's period.
pub fn check(c: &Component) -> Vec<Diagnostic> {
    if let Some(g) = c.genom3.as_deref() {
        return check_genom3(c, g);
    }
    let mut out = Vec::new();
    // Control codels run on the control thread, not the service's thread.
    for codel in c.codels.values().filter(|k| k.kind != CodelKind::Control) {
        let svc = &c.services[codel.service];
        let Some(t) = svc.thread.map(|t| &c.threads[t.id]) else {
            continue;
        };
        let (Some(wcet), Some(period)) = (codel.wcet, t.period) else {
            continue;
        };
        if wcet.ns > period.ns {
            out.push(
                Diagnostic::new(
                    Code::CodelOverrun,
                    format!(
                        "codel `{}::{}` may take {} but thread `{}` wakes up every {}",
                        svc.name.name,
                        codel.name.name,
                        format_ns(wcet.ns),
                        t.name.name,
                        format_ns(period.ns)
                    ),
                    wcet.span,
                    "WCET longer than the period",
                )
                .with_label(period.span, format!("period of `{}`", t.name.name))
                .with_help("split the codel into shorter codels chained with `next`, or run it on a slower thread"),
            );
        }
    }
    out
}

/// GenoM3: every codel (of an activity or of a task's permanent
/// activity) whose WCET, from the WCET file, exceeds its task's period.
/// One diagnostic per codel, however many states it runs in; the primary
/// label is the codel in the `.gen`, where it is fixed. The timed GenoM3
/// engine gives it a trace ([`attach_traces`]).
fn check_genom3(c: &Component, g: &Genom3Info) -> Vec<Diagnostic> {
    let mut seen = BTreeSet::new();
    let mut out = Vec::new();
    for task in &g.tasks {
        let whose = format!(
            "the permanent activity of task `{}`",
            c.threads[task.thread].name.name
        );
        for k in &task.codels {
            out.extend(genom3_overrun(c, task.thread, &whose, k));
        }
    }
    for info in &g.codels {
        let codel = &c.codels[info.codel];
        let svc = &c.services[codel.service];
        let Some(t) = svc.thread.filter(|_| codel.kind != CodelKind::Control) else {
            continue;
        };
        if seen.insert(info.fsm.span) {
            let whose = format!("activity `{}`", svc.name.name);
            out.extend(genom3_overrun(c, t.id, &whose, &info.fsm));
        }
    }
    out
}

/// The `codel-overrun` of FSM codel `k` of `whose` on `task`, if its WCET
/// exceeds the period.
fn genom3_overrun(c: &Component, task: ThreadId, whose: &str, k: &FsmCodel) -> Option<Diagnostic> {
    let t = &c.threads[task];
    let (wcet, period) = (k.wcet?, t.period?);
    (wcet.ns > period.ns).then(|| {
        Diagnostic::new(
            Code::CodelOverrun,
            format!(
                "codel `{}` of {whose} may take {} but task `{}` wakes up every {}",
                k.function.name,
                format_ns(wcet.ns),
                t.name.name,
                format_ns(period.ns)
            ),
            k.function.span,
            format!("its WCET, {}, is longer than the period", format_ns(wcet.ns)),
        )
        .with_label(period.span, format!("the period of `{}`", t.name.name))
        .with_help("split its work into codels joined by `yield pause::…` (one per wake-up), or run it on a task with a longer period")
    })
}

/// The codels longer than their period that the timed GenoM3 engine saw
/// still running at a tick: each FSM codel's span with that trace.
pub fn genom3_traces(m: &Machine<'_>, timing: &TimingAnalysis) -> Vec<(Span, Trace)> {
    timing
        .overruns
        .iter()
        .filter_map(|o| match o.cause {
            Cause::LongCodel(owner, state) => Some((
                m.fsm(owner).states[usize::from(state)].span,
                o.trace.clone(),
            )),
            _ => None,
        })
        .collect()
}

/// Gives each `codel-overrun` without a trace the trace whose span holds
/// its primary label (the codel's WCET in LANGUAGE.md, the FSM codel in
/// GenoM3, [`genom3_traces`]); a codel that no execution runs keeps none.
pub fn attach_traces(traces: &[(Span, Trace)], diagnostics: &mut [Diagnostic]) {
    for d in diagnostics
        .iter_mut()
        .filter(|d| d.code == Code::CodelOverrun && d.trace.is_none())
    {
        let at = d.span();
        let found = traces
            .iter()
            .find(|(span, _)| span.start <= at.start && at.end <= span.end);
        if let Some((_, trace)) = found {
            d.trace = Some(trace.clone());
        }
    }
}

#[cfg(test)]
mod tests {
    use genom_model::Code;

    use crate::testing::{self, HEADER};

    /// A service on `main` (period 10ms) with these codels.
    fn service(codels: &str) -> String {
        format!("{HEADER}service s {{\n  thread: main;\n{codels}}}\n")
    }

    #[test]
    fn a_wcet_longer_than_the_period_is_reported() {
        let src = service("  start codel { exec: f(); max-time: 10000001ns; next: end; }\n");
        let d = testing::check(&src).diagnostics;
        let overruns: Vec<_> = d.iter().filter(|d| d.code == Code::CodelOverrun).collect();
        assert_eq!(overruns.len(), 1);
        assert_eq!(
            overruns[0].message,
            "codel `s::start` may take 10000001ns but thread `main` wakes up every 10ms"
        );
    }

    #[test]
    fn a_wcet_equal_to_the_period_is_clean() {
        let src = service("  start codel { exec: f(); max-time: 10ms; next: end; }\n");
        assert_eq!(testing::count(&src, Code::CodelOverrun), 0);
    }

    #[test]
    fn a_control_codel_runs_on_the_control_thread() {
        let src = service(
            "  control codel { exec: c(); max-time: 50ms; }\n  start codel { exec: f(); max-time: 1ms; next: end; }\n",
        );
        assert_eq!(testing::count(&src, Code::CodelOverrun), 0);
    }
}
