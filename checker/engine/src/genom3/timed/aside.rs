//! The threads an overrun trace shows that play no part in the overrun
//! ([`genom_model::trace::TraceStep::aside`]). A thread plays a part when it
//! is the overrunning task or the control thread (which takes the
//! requests), or when a thread that plays a part took a ticket while it
//! ran a codel or held a ticket ahead: from a ticket on, only those codels
//! begin before the waiting one (docs/genom3-semantics.md 15.12), so no
//! other thread's codel can delay it. The others' steps stay in the trace
//! (the replay needs their ticks) and are folded in human output.

use std::collections::BTreeSet;

use genom_model::trace::Trace;

use super::{CTL, TG3State, TimedEngine};

/// A thread: a task, or `None` for the control thread.
type Thread = Option<usize>;

/// The tickets taken along a path, each with the threads that may delay
/// it, gathered step by step as the trace is built
/// ([`super::trace::timed_trace_seeing`]).
#[derive(Debug, Default)]
pub struct Waits(Vec<(Thread, Vec<Thread>)>);

impl Waits {
    /// Reads the tickets the step from `before` to `after` takes.
    pub fn see(&mut self, te: &TimedEngine<'_>, before: &TG3State, after: &TG3State) {
        for &u in after.queue.iter().filter(|u| !before.queue.contains(u)) {
            let who = thread_of(u);
            self.0.push((who, blockers(te, after, who)));
        }
    }

    /// Marks the steps of `trace` set aside for the overrun of task `task`.
    pub fn mark(&self, te: &TimedEngine<'_>, task: usize, trace: &mut Trace) {
        set_aside(te, &self.0, task, trace);
    }
}

/// Marks the steps of `trace` set aside for the overrun of task `task`,
/// given the tickets taken on its way (`waits`).
fn set_aside(
    te: &TimedEngine<'_>,
    waits: &[(Thread, Vec<Thread>)],
    task: usize,
    trace: &mut Trace,
) {
    let mut part: BTreeSet<Thread> = [Some(task), None].into_iter().collect();
    let mut grown = true;
    while grown {
        grown = false;
        for (who, by) in waits {
            if part.contains(who) {
                for b in by {
                    grown |= part.insert(*b);
                }
            }
        }
    }
    let m = te.m();
    let aside: Vec<&str> = (0..m.tasks.len())
        .filter(|&t| te.in_group[t] && !part.contains(&Some(t)))
        .map(|t| m.tasks[t].name.as_str())
        .collect();
    for s in &mut trace.steps {
        s.aside = s.thread.as_deref().is_some_and(|t| aside.contains(&t));
    }
}

/// The thread of a queue entry.
fn thread_of(u: u8) -> Thread {
    (u != CTL).then_some(usize::from(u))
}

/// The threads that may delay `who`'s ticket in `st`: those running a
/// codel, and those queued ahead of it.
fn blockers(te: &TimedEngine<'_>, st: &TG3State, who: Thread) -> Vec<Thread> {
    let m = te.m();
    let mut out: Vec<Thread> = (0..m.tasks.len())
        .filter(|&t| Some(t) != who && te.running(&st.g, t).is_some())
        .map(Some)
        .collect();
    if who.is_some() && st.ctl.is_some_and(|c| c.running) {
        out.push(None);
    }
    out.extend(
        st.queue
            .iter()
            .map(|&u| thread_of(u))
            .take_while(|&u| u != who),
    );
    out
}
