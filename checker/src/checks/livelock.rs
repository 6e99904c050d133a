//! `livelock` and `unpaused-loop` (GenoM3): a reachable cycle of codel
//! transitions without `pause::`. GenoM3 runs a transition without
//! `pause::` in the same wake-up of the task (another sweep at once), so a
//! task inside such a cycle never waits for its next tick: in a periodic
//! task its paused instances never resume and no new request of it starts.
//! A cycle through an `async` codel is not one (the codel blocks). With no
//! yield out of the cycle it is a `livelock` (error); with one (`yield
//! step, ether`, the idiom of running several states in one period) an
//! `unpaused-loop` warning, since how often it goes round depends on data
//! the model does not see.

use crate::genom3::{G3Analysis, Livelock, Machine, Owner};
use genom_model::{Code, Diagnostic};

/// `genom-check explain livelock`.
pub const EXPLANATION_LIVELOCK: &str = r#"A GenoM3 state machine can enter a cycle of transitions that have no
`pause::` and that no yield leaves. GenoM3 runs a transition without
`pause::` at once, in the same wake-up of the task (it sweeps again
without waiting), so once inside, the task never waits for its next
tick again: in a periodic task its paused activities never resume and
no new request for it starts; in any task the loop eats the CPU.

The trace reaches the cycle, then goes round it once (the repeating part).
A cycle through an `async` codel is not reported: the async codel blocks
on its external event.

Example:

```
activity spin() {
  task t;
  codel<start> s_start(out n) yield step, ether;
  codel<step> s_step(inout n) yield step;     // livelock: no pause::, no way out
};
```

Fix: `yield pause::step, ether` (one round per period), or give the loop
a way out."#;

/// `genom-check explain unpaused-loop`.
pub const EXPLANATION_UNPAUSED_LOOP: &str = r#"A GenoM3 state machine can go round a cycle of transitions that have no
`pause::`, though some yield leaves the cycle. GenoM3 runs those
transitions in the same wake-up of the task, so how many rounds one period
holds depends on the codels' data, which the model does not see: if the
way out is never taken, the task spins as in a `livelock`, and the rounds
of one period count against its period.

This is the idiom for running several states in one period; check that the
loop always ends, or add a `pause::` to the transition that closes it."#;

/// The diagnostic of one reachable unpaused cycle.
pub fn diagnostic(m: &Machine<'_>, l: &Livelock) -> Diagnostic {
    let fsm = m.fsm(l.cycle.owner);
    let entry = &fsm.states[usize::from(l.cycle.states[0])];
    let whose = match l.cycle.owner {
        Owner::Activity(a) => format!("activity `{}`", m.activity_name(a)),
        Owner::Task(t) => format!("the permanent codels of task `{}`", m.tasks[t].name),
    };
    let round = round_names(m, l);
    let (code, message, help) = if l.cycle.has_exit {
        (
            Code::UnpausedLoop,
            format!("{whose} may loop through {round} without `pause::`"),
            "each round runs in the same period; make sure the loop ends, or yield `pause::` on the transition that closes it",
        )
    } else {
        (
            Code::Livelock,
            format!("{whose} loops through {round} forever without `pause::`"),
            "no yield leaves this cycle, so the task never waits for its next wake-up: yield `pause::` on one transition, or give the loop a way out",
        )
    };
    let mut d = Diagnostic::new(code, message, entry.span, "the cycle is entered here")
        .with_help(help.to_owned());
    for &s in l.cycle.states.iter().skip(1) {
        let st = &fsm.states[usize::from(s)];
        if st.span != entry.span {
            d = d.with_label(st.span, format!("then `{}`", st.name));
        }
    }
    d.with_trace(l.trace.clone())
}

fn round_names(m: &Machine<'_>, l: &Livelock) -> String {
    crate::genom3::analysis::names(m.fsm(l.cycle.owner), &l.cycle.states)
}

/// One diagnostic per reachable unpaused cycle of `m`'s component.
pub fn check(m: &Machine<'_>, analysis: &G3Analysis) -> Vec<Diagnostic> {
    analysis
        .livelocks
        .iter()
        .map(|l| diagnostic(m, l))
        .collect()
}
