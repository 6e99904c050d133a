//! `livelock` and `unpaused-loop` (GenoM3): a reachable cycle of codel
//! transitions without `pause::`. GenoM3 runs a transition without
//! `pause::` in the same wake-up of the task (another sweep at once), so a
//! task inside such a cycle never waits: in a periodic task its paused
//! instances never resume and no new request of it starts; in a task
//! without a period it busy-spins between events. An `async` codel blocks,
//! so it exempts the cycles through it; the cycles that avoid every async
//! codel are reported, enough of them to go through every state that can
//! spin. With no yield out of the spinning states it is a `livelock`
//! (error); with one (`yield step, ether`, the idiom of running several
//! states in one period) an `unpaused-loop` warning, since how often it
//! goes round depends on data the model does not see.

use crate::genom3::{G3Analysis, Livelock, Machine, Owner};
use genom_model::{Code, Diagnostic};

use super::registry::Explained;

/// `genom-check explain livelock`.
pub const EXPLANATION_LIVELOCK: &str = r#"A GenoM3 state machine can enter a cycle of transitions that have no
`pause::` and that no yield leaves. GenoM3 runs a transition without
`pause::` at once, in the same wake-up of the task (it sweeps again
without waiting), so once inside, the task never waits again. In a
periodic task it never waits for its next tick: its paused activities
never resume and no new request for it starts. In a task without a
period it busy-spins between events and never handles the next one. In
any task the loop eats the CPU.

The trace reaches the cycle, then goes round it once (the repeating part).
An `async` codel blocks on its external event, so a cycle through one is
not reported; a cycle that avoids every async codel is, even if other
cycles of the same states go through one. When several cycles share
states, enough of them are reported to go through every state that can
spin, each with its own trace.

Example:

```
activity spin() {
  task t;
  codel<start> s_start(out n) yield step, ether;
  codel<step> s_step(inout n) yield step;     // livelock: no pause::, no way out
};
```

Fix, on a periodic task: `yield pause::step, ether` (one round per
period), or give the loop a way out. On a task without a period,
`pause::` waits for the next event, which may be long to come, and can
stall the activity: make the codel that waits for something (a device, a
message) `async`, or move the activity to a periodic task."#;

/// `genom-check explain unpaused-loop`.
pub const EXPLANATION_UNPAUSED_LOOP: &str = r#"A GenoM3 state machine can go round a cycle of transitions that have no
`pause::` and go through no `async` codel, though some yield leaves the
cycle. GenoM3 runs those transitions in the same wake-up of the task, so
how many rounds run depends on the codels' data, which the model does not
see: if the way out is never taken, the task spins as in a `livelock`.

- In a periodic task this is the idiom for running several states in one
  period: the rounds of one period count against it. Check that the loop
  always ends, or add a `pause::` to the transition that closes it.
- In a task without a period there is no period to share: the loop is a
  busy spin until it ends, between two events. If a codel of the loop
  waits for something (a device, a message), make it `async`, or move the
  activity to a periodic task: `pause::` on a task without a period waits
  for the next event, which may be long to come, and can stall the
  activity.

Every state that can spin is on some reported cycle: when several cycles
share states, enough of them are reported, each with its own trace."#;

/// The codes of this verdict, for the registry ([`super::VERDICTS`]).
pub const CODES: &[Explained] = &[
    (Code::Livelock, EXPLANATION_LIVELOCK),
    (Code::UnpausedLoop, EXPLANATION_UNPAUSED_LOOP),
];

/// The diagnostic of one reachable unpaused cycle.
pub fn diagnostic(m: &Machine<'_>, l: &Livelock) -> Diagnostic {
    let fsm = m.fsm(l.cycle.owner);
    let entry = &fsm.states[usize::from(l.cycle.states[0])];
    let whose = match l.cycle.owner {
        Owner::Activity(a) => format!("activity `{}`", m.activity_name(a)),
        Owner::Task(t) => format!("the permanent codels of task `{}`", m.tasks[t].name),
    };
    let round = round_names(m, l);
    // "activity `a` loops", "the permanent codels of task `t` loop".
    let loops = match l.cycle.owner {
        Owner::Activity(_) => "loops",
        Owner::Task(_) => "loop",
    };
    let task = &m.tasks[m.task_of(l.cycle.owner)];
    let (code, message, help) = match (l.cycle.has_exit, task.period_ns.is_some()) {
        (true, true) => (
            Code::UnpausedLoop,
            format!("{whose} may loop through {round} without `pause::`"),
            "each round runs in the same period; make sure the loop ends, or yield `pause::` on the transition that closes it".to_owned(),
        ),
        (false, true) => (
            Code::Livelock,
            format!("{whose} {loops} through {round} forever without `pause::`"),
            "no yield leads out of the states this cycle can reach without `pause::`, so the task never waits for its next wake-up: yield `pause::` on one transition, or give the loop a way out".to_owned(),
        ),
        (true, false) => (
            Code::UnpausedLoop,
            format!(
                "{whose} may loop through {round} without `pause::`: task `{}` has no period, so it busy-spins until the loop ends",
                task.name
            ),
            format!(
                "each round runs at once, without waiting for an event; make sure the loop ends quickly, or, if a codel of it waits for something, make it `async` or {}",
                aperiodic_fix(m, l.cycle.owner)
            ),
        ),
        (false, false) => (
            Code::Livelock,
            format!(
                "{whose} {loops} through {round} forever without `pause::`: task `{}` has no period and busy-spins",
                task.name
            ),
            format!(
                "no yield leads out of the states this cycle can reach without `pause::`, so the task never waits for an event again: make the codel that waits for something `async`, or {}",
                aperiodic_fix(m, l.cycle.owner)
            ),
        ),
    };
    let mut d =
        Diagnostic::new(code, message, entry.span, "the cycle is entered here").with_help(help);
    for &s in l.cycle.states.iter().skip(1) {
        let st = &fsm.states[usize::from(s)];
        if st.span != entry.span {
            d = d.with_label(st.span, format!("then `{}`", st.name));
        }
    }
    d.with_trace(l.trace.clone())
}

/// The other way out of a spin on a task without a period: a periodic
/// task, where `pause::` waits for a tick rather than for an event.
fn aperiodic_fix(m: &Machine<'_>, owner: Owner) -> String {
    match owner {
        Owner::Activity(_) => "move the activity to a periodic task and yield `pause::` there (on a task without a period, `pause::` waits for the next event and can stall the activity)".to_owned(),
        Owner::Task(t) => format!(
            "give task `{}` a `period` and yield `pause::` in the loop (without a period, `pause::` waits for the next event and can stall the task)",
            m.tasks[t].name
        ),
    }
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

#[cfg(test)]
mod tests {
    use genom_model::component::Component;
    use genom_model::trace::Event;
    use genom_model::{Code, Diagnostic};

    use crate::dialect::Limits;
    use crate::genom3::{Machine, analyse_machine};
    use crate::testing::load_genom3;

    /// `drain` (task `io`, no period) spins `recv → recv`: the async
    /// `wait` exempts only the cycles through it.
    const DRAIN: &str = "component spin {
  task io;
  activity drain() {
    task io;
    codel<start> drain_open() yield recv;
    codel<recv> drain_recv() yield RECV, wait;
    async codel<wait> drain_wait() yield recv, ether;
  };
};";

    /// Two rounds share `b`: `a → b → a` and `b → c → b`.
    const WALK: &str = "component loops {
  ids { long n; };
  task t { period 10 ms; };
  activity walk() {
    task t;
    codel<start> w_start(out n) yield a;
    codel<a> w_a(inout n) yield b, pause::a, ether;
    codel<b> w_b(inout n) yield A, c;
    codel<c> w_c(inout n) yield B;
  };
};";

    /// `check` runs `check` forever, with no way out.
    const BUSY: &str = "component busy {
  ids { long n; };
  task poller TASK;
  activity poll() {
    task poller;
    codel<start> p_start(out n) yield check, ether;
    codel<check> p_check(inout n) yield check;
  };
};";

    /// The livelock diagnostics of `text`, each trace replayed against
    /// GenoM3's rules and checked to be a lasso ending in its violation.
    fn loops(text: &str) -> Vec<Diagnostic> {
        let c: Component = load_genom3(text);
        let m = Machine::new(&c, 1).unwrap();
        let analysis = analyse_machine(&m, Limits::default());
        assert!(analysis.stopped.is_none());
        let out = super::check(&m, &analysis);
        for d in &out {
            let t = d.trace.as_ref().unwrap();
            genom_oracles::replay::genom3::replay_genom3(&c, t)
                .unwrap_or_else(|e| panic!("{}: {e}\n{t:#?}", d.message));
            assert!(t.loop_start.is_some(), "{}", d.message);
            assert_eq!(t.steps.last().map(|s| s.event), Some(Event::Violation));
        }
        out
    }

    /// The `(codel, outcome)` of each step of a diagnostic's round.
    fn round(d: &Diagnostic) -> Vec<(String, String)> {
        let t = d.trace.as_ref().unwrap();
        let start = t.loop_start.unwrap();
        t.steps[start..t.steps.len() - 1]
            .iter()
            .map(|s| (s.codel.clone().unwrap(), s.outcome.clone().unwrap()))
            .collect()
    }

    fn pair(a: &str, b: &str) -> (String, String) {
        (a.to_owned(), b.to_owned())
    }

    #[test]
    fn an_async_codel_exempts_only_the_cycles_through_it() {
        let d = loops(&DRAIN.replace("RECV", "recv"));
        assert_eq!(d.len(), 1, "{d:#?}");
        assert_eq!(d[0].code, Code::UnpausedLoop);
        assert_eq!(
            d[0].message,
            "activity `drain` may loop through `recv` → `recv` without `pause::`: task `io` has no period, so it busy-spins until the loop ends"
        );
        let help = d[0].help.as_deref().unwrap();
        assert!(help.contains("make it `async`"), "{help}");
        assert!(
            help.contains("move the activity to a periodic task"),
            "{help}"
        );
        assert_eq!(round(&d[0]), [pair("recv", "recv")]);
        let t = d[0].trace.as_ref().unwrap();
        let last = &t.steps[t.steps.len() - 1].text;
        assert!(last.contains("busy-spins between events"), "{last}");
    }

    #[test]
    fn the_paused_twin_of_the_drain_loop_is_clean() {
        assert_eq!(loops(&DRAIN.replace("RECV", "pause::recv")), []);
    }

    #[test]
    fn every_state_that_can_spin_is_on_a_reported_cycle() {
        let d = loops(&WALK.replace('A', "a").replace('B', "b"));
        let messages: Vec<(Code, &str)> = d.iter().map(|d| (d.code, d.message.as_str())).collect();
        assert_eq!(
            messages,
            [
                (
                    Code::UnpausedLoop,
                    "activity `walk` may loop through `a` → `b` → `a` without `pause::`"
                ),
                (
                    Code::UnpausedLoop,
                    "activity `walk` may loop through `b` → `c` → `b` without `pause::`"
                ),
            ]
        );
        assert_eq!(round(&d[0]), [pair("a", "b"), pair("b", "a")]);
        assert_eq!(round(&d[1]), [pair("b", "c"), pair("c", "b")]);
        // Periodic task: the advice of the same period.
        assert!(d[0].help.as_deref().unwrap().contains("same period"));
    }

    #[test]
    fn a_cycle_whose_states_are_covered_is_not_reported_again() {
        // `c` yields back to `a` too: `a → b → c → a` adds no state.
        let d = loops(&WALK.replace('A', "a").replace('B', "b, a"));
        let rounds: Vec<_> = d.iter().map(round).collect();
        assert_eq!(
            rounds,
            [
                vec![pair("a", "b"), pair("b", "a")],
                vec![pair("b", "c"), pair("c", "b")],
            ]
        );
    }

    #[test]
    fn the_walk_with_its_back_yields_paused_is_clean() {
        let d = loops(&WALK.replace('A', "pause::a").replace('B', "pause::b"));
        assert_eq!(d, []);
    }

    #[test]
    fn a_loop_with_no_way_out_is_a_livelock_worded_for_its_task() {
        let periodic = loops(&BUSY.replace("TASK", "{ period 10 ms; }"));
        assert_eq!(periodic.len(), 1);
        assert_eq!(periodic[0].code, Code::Livelock);
        assert_eq!(
            periodic[0].message,
            "activity `poll` loops through `check` → `check` forever without `pause::`"
        );
        assert!(
            periodic[0]
                .help
                .as_deref()
                .unwrap()
                .contains("never waits for its next wake-up")
        );
        let aperiodic = loops(&BUSY.replace("TASK", ""));
        assert_eq!(aperiodic.len(), 1);
        assert_eq!(aperiodic[0].code, Code::Livelock);
        assert_eq!(
            aperiodic[0].message,
            "activity `poll` loops through `check` → `check` forever without `pause::`: task `poller` has no period and busy-spins"
        );
        let help = aperiodic[0].help.as_deref().unwrap();
        assert!(
            help.contains("`async`") && help.contains("periodic task"),
            "{help}"
        );
        assert_eq!(round(&aperiodic[0]), [pair("check", "check")]);
    }

    #[test]
    fn the_busy_loop_with_a_pause_is_clean() {
        let text = BUSY
            .replace("TASK", "{ period 10 ms; }")
            .replace("yield check;", "yield pause::check, ether;");
        assert_eq!(loops(&text), []);
    }
}
