//! The Petri net of a GenoM3 component in GenoM3's untimed semantics
//! (docs/genom3-semantics.md section 14, as the Promela export encodes it:
//! docs/exports/promela.md), built from the component read by
//! [`crate::genom3_reading`], independently of the GenoM3 engine.
//!
//! A safe P/T net with read and inhibitor arcs and priorities, one
//! instance per activity (exact for the untimed verdicts, 14.3). Places:
//! the phase (`phase.boot.I`: booting task `I`, `phase.run`,
//! `phase.drain`, `phase.pstop.J`: the `J`-th stop path of the shutdown,
//! `phase.stopped`, `phase.failed`, and `phase.live` beside run, drain and
//! the stop paths); per task `task.T.off` and `task.T.at.S`; per activity
//! `act.A.idle`, `.delayed`, `.ready`, `.run.S`, `.stop.S`; per service an
//! `after`/`before` reads, `done.S` and `undone.S`; `ended` and `calm`;
//! and the stages of the atomic sequences (`stage.N`).
//!
//! Each step of 14.2 is one transition of priority
//! [`G3_PRIORITY_STEP`] whose effect that needs a case analysis (the
//! interruption of an activity in whatever state it is, a completion
//! marked once, the choice between pending and ready) continues as a
//! sequence of micro-steps ([`G3_PRIORITY_MICRO`], so nothing else fires
//! in between). What follows every step at once comes after: pending
//! interrupters re-examine while an instance ended
//! ([`G3_PRIORITY_REEXAMINE`]), then the boot order and the shutdown
//! sequence ([`G3_PRIORITY_SETTLE`]). The stable markings (no transition
//! above the steps' priority enabled) are the states of the Promela model
//! after each step.
//!
//! Each step transition's label says what it shows, in the words of the
//! Promela model's markers: `service `S` is accepted`, `service `A`
//! starts`, `codel `f` of activity `A` (state `s`) runs`, `codel `f` of
//! task `T` (state `s`) runs`, so a token game tells dead services and
//! unreachable codels from the transitions that never fire.

mod sequences;
mod steps;

use genom_model::component::{Component, Idx};
use genom_model::petri::{
    G3_PRIORITY_SETTLE, G3Place, G3Step, PetriNet, Place, PlaceId, PlaceKind, Transition,
    TransitionKind,
};
use genom_model::span::Span;

use crate::genom3_reading::Reading;
use crate::petri::Arcs;

pub use genom_model::petri::{G3_PRIORITY_MICRO, G3_PRIORITY_REEXAMINE, G3_PRIORITY_STEP};

/// The construction of a GenoM3 component's [`PetriNet`], as an associated
/// function of the net (bring the trait into scope and call
/// `PetriNet::build_genom3(c)`).
pub trait BuildGenom3PetriNet: Sized {
    /// Builds the net of a GenoM3 component (`None` for a LANGUAGE.md one).
    fn build_genom3(c: &Component) -> Option<Self>;
}

impl BuildGenom3PetriNet for PetriNet {
    fn build_genom3(c: &Component) -> Option<PetriNet> {
        let r = Reading::new(c)?;
        let mut b = Builder::new(c, r);
        b.steps();
        b.settle();
        Some(b.net)
    }
}

/// The places of one task's permanent activity.
#[derive(Debug, Clone)]
struct TaskPlaces {
    off: PlaceId,
    at: Vec<PlaceId>,
}

/// The places of one activity's instance.
#[derive(Debug, Clone)]
struct ActPlaces {
    idle: PlaceId,
    delayed: PlaceId,
    ready: PlaceId,
    run: Vec<PlaceId>,
    stop: Vec<PlaceId>,
}

/// The phase places.
#[derive(Debug, Clone)]
struct Phase {
    /// Booting task `I` (tasks before it booted).
    boot: Vec<PlaceId>,
    run: PlaceId,
    drain: PlaceId,
    /// Running the `J`-th stop path of the shutdown order.
    pstop: Vec<PlaceId>,
    stopped: PlaceId,
    failed: PlaceId,
    /// Run, drain or a stop path.
    live: PlaceId,
}

/// The net under construction.
struct Builder<'c> {
    c: &'c Component,
    r: Reading,
    net: PetriNet,
    phase: Phase,
    tasks: Vec<TaskPlaces>,
    acts: Vec<ActPlaces>,
    /// Per service (by index): its `done` and `undone` places, when some
    /// `after`/`before` reads its completion.
    done: Vec<Option<(PlaceId, PlaceId)>>,
    ended: PlaceId,
    calm: PlaceId,
    /// The shutdown order: (task, its `stop` state), last task first.
    order: Vec<(usize, usize)>,
}

impl<'c> Builder<'c> {
    fn new(c: &'c Component, r: Reading) -> Self {
        let net = PetriNet::empty();
        let order = r
            .tasks
            .iter()
            .enumerate()
            .rev()
            .filter_map(|(t, task)| task.fsm.stop.map(|s| (t, s)))
            .collect();
        let mut b = Builder {
            c,
            r,
            net,
            phase: Phase {
                boot: Vec::new(),
                run: PlaceId(0),
                drain: PlaceId(0),
                pstop: Vec::new(),
                stopped: PlaceId(0),
                failed: PlaceId(0),
                live: PlaceId(0),
            },
            tasks: Vec::new(),
            acts: Vec::new(),
            done: Vec::new(),
            ended: PlaceId(0),
            calm: PlaceId(0),
            order,
        };
        b.places();
        b
    }

    fn place(&mut self, name: String, label: String, kind: G3Place, tokens: u32) -> PlaceId {
        self.place_at(self.c.name.span, name, label, kind, tokens)
    }

    /// A place standing for what is written at `span`.
    fn place_at(
        &mut self,
        span: Span,
        name: String,
        label: String,
        kind: G3Place,
        tokens: u32,
    ) -> PlaceId {
        let id = PlaceId::new(self.net.places.len());
        self.net.places.push(Place {
            name,
            label,
            span,
            kind: PlaceKind::Genom3(kind),
        });
        self.net.initial.push(tokens);
        id
    }

    /// Every place, with the initial marking: booting the first task (or
    /// running, without tasks), each permanent activity at its `start`
    /// (off without one), every activity idle, nothing done.
    fn places(&mut self) {
        let n = self.r.tasks.len();
        for i in 0..n {
            let name = self.r.tasks[i].name.clone();
            let p = self.place(
                format!("phase.boot.{i}"),
                format!("booting: task `{name}` is next"),
                G3Place::Phase,
                u32::from(i == 0),
            );
            self.phase.boot.push(p);
        }
        let phase = |b: &mut Self, name: &str, label: &str, on: bool| {
            b.place(
                format!("phase.{name}"),
                label.to_owned(),
                G3Place::Phase,
                u32::from(on),
            )
        };
        self.phase.run = phase(self, "run", "requests are handled", n == 0);
        self.phase.drain = phase(self, "drain", "`kill` succeeded: draining", false);
        for j in 0..self.order.len() {
            let task = self.r.tasks[self.order[j].0].name.clone();
            let p = self.place(
                format!("phase.pstop.{j}"),
                format!("shutdown: task `{task}` runs its stop path"),
                G3Place::Phase,
                0,
            );
            self.phase.pstop.push(p);
        }
        self.phase.stopped = phase(self, "stopped", "the component stopped", false);
        self.phase.failed = phase(self, "failed", "the boot failed (an exception)", false);
        self.phase.live = phase(self, "live", "running, draining or stopping", n == 0);
        for t in 0..n {
            let task = self.r.tasks[t].clone();
            let start = task.fsm.start;
            let off = self.place_at(
                task.span,
                format!("task.{}.off", task.name),
                format!("task `{}`: no permanent activity", task.name),
                G3Place::Task,
                u32::from(start.is_none()),
            );
            let at = (0..task.fsm.states.len())
                .map(|s| {
                    self.place_at(
                        task.fsm.states[s].span,
                        format!("task.{}.at.{}", task.name, task.fsm.states[s].name),
                        format!("task `{}` at `{}`", task.name, task.fsm.states[s].name),
                        G3Place::Task,
                        u32::from(start == Some(s)),
                    )
                })
                .collect();
            self.tasks.push(TaskPlaces { off, at });
        }
        for a in 0..self.r.activities.len() {
            let places = self.activity_places(a);
            self.acts.push(places);
        }
        let watched = self.r.watched();
        for sid in self.c.services.ids() {
            let entry = watched.contains(&sid).then(|| {
                let name = self.c.services[sid].name.name.clone();
                let span = self.c.services[sid].name.span;
                let done = self.place_at(
                    span,
                    format!("done.{name}"),
                    format!("`{name}` has completed"),
                    G3Place::Done,
                    0,
                );
                let undone = self.place_at(
                    span,
                    format!("undone.{name}"),
                    format!("`{name}` has not completed"),
                    G3Place::Done,
                    1,
                );
                (done, undone)
            });
            self.done.push(entry);
        }
        self.ended = self.place(
            "ended".into(),
            "an instance ended".into(),
            G3Place::Ended,
            0,
        );
        self.calm = self.place(
            "calm".into(),
            "no instance ended since the last re-examination".into(),
            G3Place::Ended,
            1,
        );
    }

    fn activity_places(&mut self, a: usize) -> ActPlaces {
        let act = self.r.activities[a].clone();
        let span = self.c.services[act.service].name.span;
        let one = |b: &mut Self, what: &str, label: String, on: bool| {
            b.place_at(
                span,
                format!("act.{}.{what}", act.name),
                label,
                G3Place::Activity,
                u32::from(on),
            )
        };
        let idle = one(
            self,
            "idle",
            format!("`{}` has no instance", act.name),
            true,
        );
        let delayed = one(
            self,
            "delayed",
            format!("`{}` accepted, waits for interrupted instances", act.name),
            false,
        );
        let ready = one(
            self,
            "ready",
            format!("`{}` accepted, starts next", act.name),
            false,
        );
        let mut run = Vec::new();
        let mut stop = Vec::new();
        for st in &act.fsm.states {
            run.push(one(
                self,
                &format!("run.{}", st.name),
                format!("`{}` runs `{}`", act.name, st.name),
                false,
            ));
            stop.push(one(
                self,
                &format!("stop.{}", st.name),
                format!("`{}` stopping, at `{}`", act.name, st.name),
                false,
            ));
        }
        ActPlaces {
            idle,
            delayed,
            ready,
            run,
            stop,
        }
    }

    /// Adds a transition.
    fn add(&mut self, t: Transition) {
        self.net.transitions.push(t);
    }

    /// The phase place after task `i` booted: the next task's, or run
    /// (with `live`) after the last.
    fn after_boot(&self, i: usize) -> Vec<PlaceId> {
        match self.phase.boot.get(i + 1) {
            Some(&p) => vec![p],
            None => vec![self.phase.run, self.phase.live],
        }
    }

    /// What follows every step: the boot order (a task without a living
    /// permanent activity is passed), the shutdown once `kill` drained
    /// every instance, and each stop path after the previous one ended.
    fn settle(&mut self) {
        for i in 0..self.phase.boot.len() {
            let post = self.after_boot(i);
            let task = self.r.tasks[i].name.clone();
            let t = settle_step(
                format!("boot.pass.{i}"),
                format!("boot: task `{task}` is passed"),
            )
            .pre(self.phase.boot[i])
            .read(self.tasks[i].off)
            .posts(post);
            self.add(t);
        }
        self.shutdown();
        self.reexamine();
    }

    /// 10.2: once `kill` drained every instance, every permanent activity
    /// is discarded and the stop paths run one by one, last task first.
    fn shutdown(&mut self) {
        let idle: Vec<PlaceId> = self.acts.iter().map(|a| a.idle).collect();
        let stage = self.stage("shutdown: discard the permanent activities".into());
        let t = settle_step("shutdown".into(), "shutdown: every instance ended".into())
            .pre(self.phase.drain)
            .reads(idle)
            .post(stage);
        self.add(t);
        let mut at = stage;
        for task in 0..self.tasks.len() {
            let next = self.stage(format!("shutdown: task {task} discarded"));
            self.discard_task(task, at, next);
            at = next;
        }
        let first = self.begin_stop_path(0);
        let t = micro(
            "shutdown.begin".into(),
            "shutdown: the first stop path".into(),
        )
        .pre(at)
        .pres(first.0)
        .posts(first.1);
        self.add(t);
        for j in 0..self.order.len() {
            let (task, _) = self.order[j];
            let next = self.begin_stop_path(j + 1);
            let t = settle_step(
                format!("shutdown.next.{j}"),
                format!(
                    "shutdown: the stop path of task `{}` ended",
                    self.r.tasks[task].name
                ),
            )
            .pre(self.phase.pstop[j])
            .read(self.tasks[task].off)
            .pres(next.0)
            .posts(next.1);
            self.add(t);
        }
    }

    /// The arcs that begin the `j`-th stop path (consumed, produced), or
    /// stop the component after the last.
    fn begin_stop_path(&self, j: usize) -> (Vec<PlaceId>, Vec<PlaceId>) {
        match self.order.get(j) {
            Some(&(task, stop)) => (
                vec![self.tasks[task].off],
                vec![self.phase.pstop[j], self.tasks[task].at[stop]],
            ),
            None => (vec![self.phase.live], vec![self.phase.stopped]),
        }
    }

    /// Micro-steps from `at` to `next` turning task `task`'s permanent
    /// activity off, whatever its state.
    fn discard_task(&mut self, task: usize, at: PlaceId, next: PlaceId) {
        let name = self.r.tasks[task].name.clone();
        let off = self.tasks[task].off;
        let t = micro(
            format!("discard.{name}.off"),
            format!("task `{name}` already off"),
        )
        .pre(at)
        .read(off)
        .post(next);
        self.add(t);
        for (s, &p) in self.tasks[task].at.clone().iter().enumerate() {
            let state = self.r.tasks[task].fsm.states[s].name.clone();
            let t = micro(
                format!("discard.{name}.{state}"),
                format!("task `{name}` discarded at `{state}`"),
            )
            .pre(at)
            .pre(p)
            .post(off)
            .post(next);
            self.add(t);
        }
    }

    /// A new stage place of an atomic sequence.
    fn stage(&mut self, label: String) -> PlaceId {
        let n = self.net.places.len();
        self.place(format!("stage.{n}"), label, G3Place::Stage, 0)
    }
}

/// A transition without arcs.
fn transition(name: String, label: String, priority: u8, kind: G3Step) -> Transition {
    Transition::new(
        name,
        label,
        Span::default(),
        priority,
        TransitionKind::Genom3(kind),
    )
}

/// A micro-step of an atomic sequence.
fn micro(name: String, label: String) -> Transition {
    transition(name, label, G3_PRIORITY_MICRO, G3Step::Micro)
}

/// A transition of what follows every step (boot order, shutdown).
fn settle_step(name: String, label: String) -> Transition {
    transition(name, label, G3_PRIORITY_SETTLE, G3Step::Settle)
}
