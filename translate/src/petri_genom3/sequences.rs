//! The atomic sequences of micro-steps that finish a step of the GenoM3
//! net: each operation is a stage place and one micro-step per case of
//! what it reads (an interruption per state of the interrupted instance,
//! a completion marked whether or not it already was), all of priority
//! [`G3_PRIORITY_MICRO`](genom_model::petri::G3_PRIORITY_MICRO), so that
//! no other transition fires until the sequence ends.

use genom_model::component::{Idx, ServiceId};
use genom_model::petri::PlaceId;

use super::{Builder, micro};
use crate::petri::Arcs;

/// One operation of a sequence.
#[derive(Debug, Clone, Copy)]
pub(super) enum Op {
    /// Interrupt activity `A`'s instance (5.1, 5.2, 5.4, 5.5 at once): a
    /// delayed or ready one ends, a running one goes to its `stop` state
    /// (or ends without one), an idle or stopping one is left alone.
    Flag(usize),
    /// The service completed (when some `after`/`before` reads it).
    Done(ServiceId),
    /// An instance ended: pending interrupters will re-examine.
    Ended,
    /// `kill` succeeded: the component drains.
    Drain,
}

/// How a sequence ends.
#[derive(Debug, Clone)]
pub(super) enum Finish {
    /// These places are marked.
    Places(Vec<PlaceId>),
    /// Activity `A` was accepted: ready when none of the activities it
    /// interrupts is stopping, else delayed (5.1, 5.3).
    Decide(usize),
    /// Activity `A`'s delayed instance becomes ready when none of the
    /// activities it interrupts is stopping (5.3); then these places are
    /// marked.
    Promote(usize, Vec<PlaceId>),
}

impl Builder<'_> {
    /// The places a step marks to run `ops` then `finish` (the finish's
    /// places at once when there is nothing to do in between).
    pub(super) fn sequence(&mut self, what: &str, ops: &[Op], finish: Finish) -> Vec<PlaceId> {
        let ops: Vec<Op> = ops
            .iter()
            .copied()
            .filter(|op| !matches!(op, Op::Done(s) if self.done_places(*s).is_none()))
            .collect();
        if let (true, Finish::Places(places)) = (ops.is_empty(), &finish) {
            return places.clone();
        }
        let entry = self.stage(format!("{what}: begins"));
        let mut at = entry;
        for (k, op) in ops.iter().enumerate() {
            let next = self.stage(format!("{what}: after step {}", k + 1));
            self.operation(&format!("{what}.{k}"), *op, at, next);
            at = next;
        }
        self.finish(what, at, finish);
        vec![entry]
    }

    fn done_places(&self, s: ServiceId) -> Option<(PlaceId, PlaceId)> {
        self.done.get(s.index()).copied().flatten()
    }

    /// The micro-steps of `op` from stage `at` to stage `next`.
    fn operation(&mut self, name: &str, op: Op, at: PlaceId, next: PlaceId) {
        match op {
            Op::Flag(a) => self.flag(name, a, at, next),
            Op::Done(s) => {
                if let Some((done, undone)) = self.done_places(s) {
                    self.mark_once(name, (done, undone), at, next);
                }
            }
            Op::Ended => self.mark_once(name, (self.ended, self.calm), at, next),
            Op::Drain => {
                let t = micro(format!("{name}.drain"), "`kill`: drain".into())
                    .pre(at)
                    .pre(self.phase.run)
                    .post(self.phase.drain)
                    .post(next);
                self.add(t);
            }
        }
    }

    /// Marks `on` (unmarking `off`) unless already marked.
    fn mark_once(&mut self, name: &str, (on, off): (PlaceId, PlaceId), at: PlaceId, next: PlaceId) {
        let t = micro(format!("{name}.set"), "mark".into())
            .pre(at)
            .pre(off)
            .post(on)
            .post(next);
        self.add(t);
        let t = micro(format!("{name}.kept"), "already marked".into())
            .pre(at)
            .read(on)
            .post(next);
        self.add(t);
    }

    /// The interruption of activity `a`, one micro-step per state of its
    /// instance.
    fn flag(&mut self, name: &str, a: usize, at: PlaceId, next: PlaceId) {
        let p = self.acts[a].clone();
        let act = self.r.activities[a].name.clone();
        let ended = self.stage(format!("`{act}` interrupted: it ended"));
        self.mark_once(
            &format!("{name}.ended"),
            (self.ended, self.calm),
            ended,
            next,
        );
        let mut left_alone = vec![p.idle];
        left_alone.extend(p.stop.iter().copied());
        for (k, q) in left_alone.into_iter().enumerate() {
            let t = micro(format!("{name}.alone.{k}"), format!("`{act}` left alone"))
                .pre(at)
                .read(q)
                .post(next);
            self.add(t);
        }
        for (k, q) in [p.delayed, p.ready].into_iter().enumerate() {
            let t = micro(
                format!("{name}.drop.{k}"),
                format!("`{act}` ends, interrupted"),
            )
            .pre(at)
            .pre(q)
            .post(p.idle)
            .post(ended);
            self.add(t);
        }
        let stop = self.r.activities[a].fsm.stop;
        for (s, &q) in p.run.iter().enumerate() {
            let t = micro(format!("{name}.run.{s}"), format!("`{act}` interrupted"))
                .pre(at)
                .pre(q);
            let t = match stop {
                Some(stop) => t.post(p.stop[stop]).post(next),
                None => t.post(p.idle).post(ended),
            };
            self.add(t);
        }
    }

    /// The places of the activities `a` interrupts that mean "stopping".
    fn stopping(&self, a: usize) -> Vec<PlaceId> {
        self.r.activities[a]
            .targets
            .iter()
            .flat_map(|&x| self.acts[x].stop.iter().copied())
            .collect()
    }

    /// The micro-steps that end a sequence at stage `at`.
    fn finish(&mut self, what: &str, at: PlaceId, finish: Finish) {
        let (a, promote, then) = match finish {
            Finish::Places(places) => {
                let t = micro(format!("{what}.end"), format!("{what}: ends"))
                    .pre(at)
                    .posts(places);
                self.add(t);
                return;
            }
            Finish::Decide(a) => (a, false, Vec::new()),
            Finish::Promote(a, then) => (a, true, then),
        };
        let stopping = self.stopping(a);
        let p = self.acts[a].clone();
        let ready = micro(format!("{what}.ready"), format!("{what}: ready"))
            .pre(at)
            .inhibit(stopping.iter().copied())
            .posts(then.iter().copied())
            .post(p.ready);
        let ready = if promote { ready.pre(p.delayed) } else { ready };
        self.add(ready);
        for (k, &q) in stopping.iter().enumerate() {
            let t = micro(format!("{what}.waits.{k}"), format!("{what}: waits"))
                .pre(at)
                .read(q)
                .posts(then.iter().copied());
            let t = if promote { t } else { t.post(p.delayed) };
            self.add(t);
        }
    }
}
