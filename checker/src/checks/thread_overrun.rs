//! `thread-overrun`: a reachable period whose codels (with lock waits) are
//! not finished when the thread wakes up again; found by the timed engine,
//! with a timed trace.

use genom_model::component::{Component, Thread};
use genom_model::duration::format_ns;
use genom_model::{Code, Diagnostic, Trace};

use super::registry::Explained;
use crate::genom3::Machine;
use crate::genom3::timed::analysis::{Cause, TimingAnalysis};
use crate::timed::TimedFacts;

/// `genom-check explain thread-overrun`.
pub const EXPLANATION: &str = r#"A periodic thread can wake up while codels of its previous period are
still unfinished: the codels of all the services it runs in one period
(one codel per active service, in acknowledgment order), plus the time
they wait for locks held by other threads, can take longer than the period.

Why it matters: a real-time thread that overruns misses its deadline; the
servo loops it runs are late. The timed trace shows the requests that make
these services active together, every wake-up and codel with its instant,
and the wake-up that finds work unfinished.

Example:

```
thread servo { period: 10ms; }
service a { thread: servo; start codel { exec: fa(); max-time: 6ms; next: start; } }
service b { thread: servo; start codel { exec: fb(); max-time: 6ms; next: start; } }
// a and b active together: 12ms of codels in a 10ms period.
```

Make the services exclusive (`stops`, `forbids`), shorten the codels, or
run one of them on another thread. A codel without `max-time` counts as
taking no time (see `missing-wcet`).

GenoM3 components (`--wcet FILE` gives the WCETs): a task's wake-up runs
every instance that is not paused, one codel each per sweep, and sweeps
again at once while a codel yielded without `pause::`; so a chain of
unpaused transitions, several instances of one activity, the task's
permanent codels and the time spent waiting for GenoM3's locks (other
tasks' and the control thread's codels that access the same ids members
or ports) all count against the period.

```
task t { period 10 ms; };
activity chain() {
  task t;
  codel<start> s() yield exec;          // 6 ms
  codel<exec> e() yield pause::wait;    // 6 ms: same wake-up as `start`
  codel<wait> w() yield pause::wait, ether;
};
```

Add `pause::` so that a chain spreads over wake-ups, declare `interrupts`
so that instances do not pile up, shorten the codels, or move an activity
to another task.

Each cause is its own diagnostic with its own trace, the message saying
which: `a codel waits for a lock` (the trace's `lock-wait` steps show the
tickets it queued behind, GenoM3 serving them in order), `a chain of
codels without pause::`, or `its instances' codels together`. A codel
longer than the period is a `codel-overrun` instead.

The verdict rests on the WCET file and on how many requests of each
activity clients send at once (`--max-instances N`, default 1, plus one
request restarting an activity that interrupts itself): the summary's
`assuming …` line says both; a clean result holds under them only."#;

/// The codes of this verdict, for the registry ([`super::VERDICTS`]).
pub const CODES: &[Explained] = &[(Code::ThreadOverrun, EXPLANATION)];

/// One diagnostic per thread that can overrun.
pub fn check(c: &Component, facts: &TimedFacts) -> Vec<Diagnostic> {
    let over_codel: Vec<_> = c
        .codels
        .values()
        .filter_map(|k| {
            let t = c.services[k.service].thread?.id;
            let p = c.threads[t].period?;
            (k.wcet?.ns > p.ns).then_some(t)
        })
        .collect();
    facts
        .overruns
        .iter()
        .filter(|o| !over_codel.contains(&o.thread))
        .map(|o| {
            overrun(
                &c.threads[o.thread],
                "thread",
                "its codels of one period can take longer than the period",
                "make the services it runs together exclusive, shorten their codels, or move one to another thread",
                &o.trace,
            )
        })
        .collect()
}

/// One diagnostic per GenoM3 task and cause of overrun (the timed GenoM3
/// engine's findings), each with its own trace. A codel longer than the
/// period is a `codel-overrun` ([`super::codel_overrun::check_genom3`]),
/// which carries that cause's trace; it hides no other cause.
pub fn check_genom3(m: &Machine<'_>, timing: &TimingAnalysis) -> Vec<Diagnostic> {
    timing
        .overruns
        .iter()
        .filter_map(|o| {
            let (why, label, help) = match o.cause {
                Cause::LongCodel(..) => return None,
                Cause::LockWait => (
                    ": a codel waits for a lock",
                    "a codel of its wake-up waits for a lock (GenoM3's resource queue) and ends after the next tick",
                    "shorten the codels that hold the lock, make them touch fewer ids members or ports, or move one of them to another task",
                ),
                Cause::Chain => (
                    ": a chain of codels without `pause::`",
                    "codels joined without `pause::` run in one wake-up and end after the next tick",
                    "yield `pause::` between codels of the chain so that it spreads over periods, or shorten the codels",
                ),
                Cause::Shared => (
                    ": its instances' codels together",
                    "the codels of its instances (one each per sweep, its permanent codels included) end after the next tick",
                    "make instances interrupt each other (`interrupts`), shorten the codels, or move an activity to another task",
                ),
            };
            Some(overrun_because(
                &m.c.threads[m.tasks[o.task].thread],
                "task",
                why,
                label,
                help,
                &o.trace,
            ))
        })
        .collect()
}

/// The diagnostic of thread `t` (a `thread` or a GenoM3 `task`) overrunning,
/// with its trace.
fn overrun(t: &Thread, what: &str, label: &str, help: &str, trace: &Trace) -> Diagnostic {
    overrun_because(t, what, "", label, help, trace)
}

/// [`overrun`] whose message ends with `why` (empty, or `: …`).
fn overrun_because(
    t: &Thread,
    what: &str,
    why: &str,
    label: &str,
    help: &str,
    trace: &Trace,
) -> Diagnostic {
    let period = t.period.map_or(0, |p| p.ns);
    let mut d = Diagnostic::new(
        Code::ThreadOverrun,
        format!(
            "{what} `{}` can overrun its {} period{why}",
            t.name.name,
            format_ns(period)
        ),
        t.name.span,
        label,
    )
    .with_help(help);
    if let Some(p) = t.period {
        d = d.with_label(p.span, "the period");
    }
    d.with_trace(trace.clone())
}
