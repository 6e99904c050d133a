//! The steps of the GenoM3 net (docs/genom3-semantics.md 14.2), one
//! transition per step and outcome: a permanent codel, an activity
//! request accepted, a function or attribute that succeeds
//! (`abort_activity` once per state of the instance it aborts), an
//! instance starting with its first codel, an instance's codel; and the
//! re-examination of pending interrupters after an end (5.3).

use genom_model::component::{Idx, ServiceId};
use genom_model::petri::{G3_PRIORITY_REEXAMINE, G3Step, PlaceId, Transition};

use super::sequences::{Finish, Op};
use super::{Builder, G3_PRIORITY_STEP, micro, transition};
use crate::genom3_reading::{ControlKind, Next};
use crate::petri::Arcs;

/// One outcome of a codel: a yield to a state, `ether`, or an exception.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Outcome {
    State(usize),
    Ether,
    Exception,
}

fn outcomes(yields: &[Next]) -> Vec<Outcome> {
    let mut out: Vec<Outcome> = yields
        .iter()
        .map(|y| match *y {
            Next::State(n) => Outcome::State(n),
            Next::Ether => Outcome::Ether,
        })
        .collect();
    out.push(Outcome::Exception);
    out
}

fn outcome_name(o: Outcome) -> String {
    match o {
        Outcome::State(n) => format!("y{n}"),
        Outcome::Ether => "ether".into(),
        Outcome::Exception => "exception".into(),
    }
}

fn step(name: String, label: String, kind: G3Step) -> Transition {
    transition(name, label, G3_PRIORITY_STEP, kind)
}

impl Builder<'_> {
    /// Every step transition.
    pub(super) fn steps(&mut self) {
        for t in 0..self.r.tasks.len() {
            self.permanent(t);
        }
        for a in 0..self.r.activities.len() {
            self.accept(a);
        }
        for k in 0..self.r.controls.len() {
            self.call(k);
        }
        for a in 0..self.r.activities.len() {
            self.start(a);
            self.codels(a);
        }
    }

    /// The reads of `after` all done and `before` none done (4.1, 4.2),
    /// each place once.
    fn admissible(&self, sid: ServiceId, t: Transition) -> Transition {
        let places = |list: Option<&Vec<ServiceId>>, done: bool| -> Vec<PlaceId> {
            list.into_iter()
                .flatten()
                .filter_map(|x| self.done.get(x.index()).copied().flatten())
                .map(|(d, u)| if done { d } else { u })
                .collect()
        };
        let mut reads: Vec<PlaceId> = places(self.r.after.get(&sid), true);
        reads.extend(places(self.r.before.get(&sid), false));
        reads.sort_unstable();
        reads.dedup();
        t.reads(reads)
    }

    /// Task `t`'s permanent codels: while the component lives, and in the
    /// boot for tasks already booted and the one booting (whose first
    /// codel counts it booted, and whose exception fails the boot, 9.4).
    fn permanent(&mut self, t: usize) {
        let task = self.r.tasks[t].clone();
        let mut phases = vec![self.phase.live];
        phases.extend(self.phase.boot.iter().skip(t + 1).copied());
        for (s, state) in task.fsm.states.iter().enumerate() {
            let label = format!(
                "codel `{}` of task `{}` (state `{}`) runs",
                state.function, task.name, state.name
            );
            let at = self.tasks[t].at[s];
            for o in outcomes(&state.yields) {
                let to = match o {
                    Outcome::State(n) => self.tasks[t].at[n],
                    Outcome::Ether | Outcome::Exception => self.tasks[t].off,
                };
                let base = format!("task.{}.{}.{}", task.name, state.name, outcome_name(o));
                for (k, &phase) in phases.iter().enumerate() {
                    let tr = step(format!("{base}.p{k}"), label.clone(), G3Step::Permanent)
                        .at(state.span)
                        .pre(at)
                        .read(phase)
                        .post(to);
                    self.add(tr);
                }
                let Some(&booting) = self.phase.boot.get(t) else {
                    continue;
                };
                let tr = step(format!("{base}.boot"), label.clone(), G3Step::Permanent)
                    .at(state.span)
                    .pre(at)
                    .pre(booting);
                let tr = match o {
                    Outcome::Exception => tr.post(at).post(self.phase.failed),
                    _ => tr.post(to).posts(self.after_boot(t)),
                };
                self.add(tr);
            }
        }
    }

    /// A request of activity `a` accepted: it interrupts its targets,
    /// then pends while one of them is stopping (5.1, 5.3).
    fn accept(&mut self, a: usize) {
        let act = self.r.activities[a].clone();
        let name = format!("accept.{}", act.name);
        let ops: Vec<Op> = act.targets.iter().map(|&x| Op::Flag(x)).collect();
        let finish = if ops.is_empty() {
            Finish::Places(vec![self.acts[a].ready])
        } else {
            Finish::Decide(a)
        };
        let posts = self.sequence(&name, &ops, finish);
        let t = step(
            name,
            format!("request of `{}` accepted", act.name),
            G3Step::Accept,
        )
        .at(self.c.services[act.service].name.span)
        .pre(self.acts[a].idle)
        .read(self.phase.run)
        .posts(posts);
        let t = self.admissible(act.service, t);
        self.add(t);
    }

    /// A function or attribute that succeeds (6.1): completed, then its
    /// interruptions; `kill` then drains (10.2); `abort_activity`
    /// interrupts one instance (5.6).
    fn call(&mut self, k: usize) {
        let ctl = self.r.controls[k].clone();
        let label = format!("service `{}` is accepted", ctl.name);
        if ctl.kind == ControlKind::Abort {
            for a in 0..self.r.activities.len() {
                let p = self.acts[a].clone();
                let mut on = vec![p.delayed, p.ready];
                on.extend(p.run.iter().copied());
                for (j, place) in on.into_iter().enumerate() {
                    let name = format!("call.{}.{}.{j}", ctl.name, self.r.activities[a].name);
                    let ops = [Op::Done(ctl.service), Op::Flag(a)];
                    let posts = self.sequence(&name, &ops, Finish::Places(Vec::new()));
                    let t = step(name, label.clone(), G3Step::Call)
                        .at(self.c.services[ctl.service].name.span)
                        .read(self.phase.run)
                        .read(place)
                        .posts(posts);
                    let t = self.admissible(ctl.service, t);
                    self.add(t);
                }
            }
            return;
        }
        let mut ops = vec![Op::Done(ctl.service)];
        ops.extend(ctl.targets.iter().map(|&x| Op::Flag(x)));
        if ctl.kind == ControlKind::Kill {
            ops.push(Op::Drain);
        }
        let name = format!("call.{}", ctl.name);
        let posts = self.sequence(&name, &ops, Finish::Places(Vec::new()));
        let t = step(name, label, G3Step::Call)
            .at(self.c.services[ctl.service].name.span)
            .read(self.phase.run)
            .posts(posts);
        let t = self.admissible(ctl.service, t);
        self.add(t);
    }

    /// An accepted instance of `a` starts (1.4) and runs its `start` codel
    /// in the same step; without one it completes at once.
    fn start(&mut self, a: usize) {
        let act = self.r.activities[a].clone();
        let starts = format!("service `{}` starts", act.name);
        let ready = self.acts[a].ready;
        let Some(s) = act.fsm.start else {
            let name = format!("start.{}", act.name);
            let posts = self.instance_ends(&name, a, true);
            let t = step(name, starts, G3Step::Start)
                .at(self.c.services[act.service].name.span)
                .pre(ready)
                .posts(posts);
            self.add(t);
            return;
        };
        let state = &act.fsm.states[s];
        let label = format!(
            "{starts}; codel `{}` of activity `{}` (state `{}`) runs",
            state.function, act.name, state.name
        );
        for o in outcomes(&state.yields) {
            let name = format!("start.{}.{}", act.name, outcome_name(o));
            let posts = self.codel_outcome(&name, a, o, false);
            let t = step(name, label.clone(), G3Step::Start)
                .at(state.span)
                .pre(ready)
                .posts(posts);
            self.add(t);
        }
    }

    /// One codel of `a`'s instance, running or stopping, with each of its
    /// outcomes (9.1, 9.2); a stopping instance stays stopping.
    fn codels(&mut self, a: usize) {
        let act = self.r.activities[a].clone();
        for (s, state) in act.fsm.states.iter().enumerate() {
            let label = format!(
                "codel `{}` of activity `{}` (state `{}`) runs",
                state.function, act.name, state.name
            );
            for (stopping, place) in [(false, self.acts[a].run[s]), (true, self.acts[a].stop[s])] {
                for o in outcomes(&state.yields) {
                    let name = format!(
                        "codel.{}.{}.{}.{}",
                        act.name,
                        if stopping { "stop" } else { "run" },
                        state.name,
                        outcome_name(o)
                    );
                    let posts = self.codel_outcome(&name, a, o, stopping);
                    let t = step(name, label.clone(), G3Step::Codel)
                        .at(state.span)
                        .pre(place)
                        .posts(posts);
                    self.add(t);
                }
            }
        }
    }

    /// The places marked by an outcome of one of `a`'s codels.
    fn codel_outcome(&mut self, name: &str, a: usize, o: Outcome, stopping: bool) -> Vec<PlaceId> {
        match o {
            Outcome::State(n) if stopping => vec![self.acts[a].stop[n]],
            Outcome::State(n) => vec![self.acts[a].run[n]],
            Outcome::Ether => self.instance_ends(name, a, true),
            Outcome::Exception => self.instance_ends(name, a, false),
        }
    }

    /// `a`'s instance ends (completed when `success`): idle, and pending
    /// interrupters re-examine.
    fn instance_ends(&mut self, name: &str, a: usize, success: bool) -> Vec<PlaceId> {
        let mut ops = Vec::new();
        if success {
            ops.push(Op::Done(self.r.activities[a].service));
        }
        ops.push(Op::Ended);
        self.sequence(name, &ops, Finish::Places(vec![self.acts[a].idle]))
    }

    /// 5.3: after an end, every accepted instance not started re-examines
    /// its interruptions in activity order, until no further end.
    pub(super) fn reexamine(&mut self) {
        let pending: Vec<usize> = (0..self.r.activities.len())
            .filter(|&a| !self.r.activities[a].targets.is_empty())
            .collect();
        let mut stages: Vec<PlaceId> = Vec::new();
        for &a in &pending {
            let name = &self.r.activities[a].name;
            let label = format!("re-examine: `{name}`");
            stages.push(self.stage(label));
        }
        let t = transition(
            "reexamine".into(),
            "an instance ended: pending interrupters re-examine".into(),
            G3_PRIORITY_REEXAMINE,
            G3Step::Settle,
        )
        .pre(self.ended)
        .post(self.calm)
        .posts(stages.first().copied());
        self.add(t);
        for (j, &a) in pending.iter().enumerate() {
            let then: Vec<PlaceId> = stages.get(j + 1).copied().into_iter().collect();
            self.reexamine_one(a, stages[j], &then);
        }
    }

    /// The re-examination of activity `a` at stage `at`, then `then`.
    fn reexamine_one(&mut self, a: usize, at: PlaceId, then: &[PlaceId]) {
        let act = self.r.activities[a].clone();
        let p = self.acts[a].clone();
        let flags: Vec<Op> = act.targets.iter().map(|&x| Op::Flag(x)).collect();
        let name = format!("reexamine.{}", act.name);
        let delayed = self.sequence(
            &format!("{name}.delayed"),
            &flags,
            Finish::Promote(a, then.to_vec()),
        );
        let t = micro(format!("{name}.delayed"), format!("`{}` pending", act.name))
            .pre(at)
            .read(p.delayed)
            .posts(delayed);
        self.add(t);
        let ready = self.sequence(
            &format!("{name}.ready"),
            &flags,
            Finish::Places(then.to_vec()),
        );
        let t = micro(format!("{name}.ready"), format!("`{}` ready", act.name))
            .pre(at)
            .read(p.ready)
            .posts(ready);
        self.add(t);
        let mut other = vec![p.idle];
        other.extend(p.run.iter().copied());
        other.extend(p.stop.iter().copied());
        for (k, q) in other.into_iter().enumerate() {
            let t = micro(
                format!("{name}.other.{k}"),
                format!("`{}` not pending", act.name),
            )
            .pre(at)
            .read(q)
            .posts(then.iter().copied());
            self.add(t);
        }
    }
}
