//! The transitions of the timed GenoM3 model: ticks and activations that
//! open a sweep, codels beginning and ending, the control thread's steps
//! (the untimed engine's), and after each of them the sweeps that follow
//! at once ([`TimedEngine::finish`]).

use super::{CTL, Ctl, TG3Action, TG3State, TimedEngine, Who, idle_running, service_index};
use crate::genom3::machine::Target;
use crate::genom3::state::{G3State, Inst, Phase, Status, mark};
use crate::genom3::steps::{G3Action, insert, remove, total};
use crate::kernel::explore::Model;
use crate::zones::dbm::{Dbm, lt};

impl TimedEngine<'_> {
    /// The transitions enabled in `st` (their zone guards are checked when
    /// they fire).
    pub fn enabled(&self, st: &TG3State, out: &mut Vec<TG3Action>) {
        if st.violation.is_some() || matches!(st.g.phase, Phase::Stopped | Phase::Failed) {
            return;
        }
        if st.g.phase == Phase::Run && st.ctl.is_none() {
            let mut v = Vec::new();
            self.e.requests(&st.g, &mut v);
            // Interchangeable calls: one stands for all.
            v.retain(|u| match *u {
                G3Action::Call(k) => {
                    self.canon[usize::from(k)] == k && !self.changes_nothing(st, usize::from(k))
                }
                _ => true,
            });
            out.extend(v.into_iter().map(|u| {
                if self.job_codels(u) > 0 {
                    TG3Action::CtlBegin(u)
                } else {
                    TG3Action::Control(u)
                }
            }));
        }
        if let Some(c) = st.ctl.filter(|c| c.running) {
            out.push(TG3Action::CtlEnd(true));
            // An attribute's ids copy throws nothing.
            let copy = self
                .job_service(c.job)
                .zip(self.job_codel(c))
                .is_some_and(|(s, i)| super::ctl_copy(&self.e.m, s, i));
            if !copy {
                out.push(TG3Action::CtlEnd(false));
            }
        }
        for t in (0..self.e.m.tasks.len()).filter(|&t| self.in_group[t]) {
            if self.period[t].is_some() {
                out.push(TG3Action::Tick(t as u8));
            } else if self.activatable(st, t) {
                out.push(TG3Action::Wake(t as u8));
            }
        }
        self.begins(st, out);
        for t in 0..self.e.m.tasks.len() {
            if let Some((who, i)) = self.running(&st.g, t) {
                let n = self.e.outcomes(who.owner(), i.state);
                out.extend((0..n).map(|o| TG3Action::End(who, i.pack(), o)));
            }
        }
    }

    /// Whether a request for control service `k` changes nothing a task
    /// sees in `st`: its one control codel takes no time, throws nothing,
    /// and could begin at once (its locks free, no ticket waiting), so it
    /// would run and end at this instant. A task's codel due at the same
    /// instant and ordered between them would take a ticket and begin at
    /// that same instant: no delay, no other order of codels than the
    /// explored ones (docs/genom3-semantics.md 15.5, "Quiet requests").
    /// Not applied while response times are measured (the request's own
    /// response is read).
    pub(crate) fn changes_nothing(&self, st: &TG3State, k: usize) -> bool {
        let Some(key) = self.quiet[k] else {
            return false;
        };
        self.ctl_resp.is_none()
            && self.resp.is_empty()
            && st.queue.is_empty()
            && self.locks_free(st, None, key)
    }

    /// An aperiodic task asleep with something to start or resume.
    fn activatable(&self, st: &TG3State, t: usize) -> bool {
        self.spawned(&st.g, t)
            && !self.unfinished(st, t)
            && self
                .instances(&st.g, t)
                .any(|(_, i)| i.status == Status::Ready || idle_running(i))
    }

    /// Fires `a` from `st` (no delay after it); `None` when its guard
    /// fails.
    pub fn fire(&self, st: &TG3State, a: TG3Action) -> Option<TG3State> {
        let mut n = st.clone();
        match a {
            TG3Action::Control(c) => n.g = self.e.next_state(&st.g, c)?,
            TG3Action::Tick(t) => return self.tick(n, usize::from(t)),
            TG3Action::Wake(t) => self.sweep(&mut n.g, usize::from(t), true),
            TG3Action::CtlBegin(job) => {
                n.ctl = Some(Ctl {
                    job,
                    phase: 0,
                    running: false,
                });
                // Its first codel begins, or it takes a ticket, at once.
                match self.ctl_turn(&n) {
                    Some(true) => self.ctl_phase(&mut n)?,
                    Some(false) => n.queue.push(CTL),
                    None => {}
                }
            }
            TG3Action::CtlPhase => self.ctl_phase(&mut n)?,
            TG3Action::CtlTicket => n.queue.push(CTL),
            TG3Action::CtlEnd(ok) => {
                let c = n.ctl?;
                let next = usize::from(c.phase) + 1;
                n.ctl = None;
                if ok && next < self.job_codels(c.job) {
                    n.ctl = Some(Ctl {
                        job: c.job,
                        phase: c.phase + 1,
                        running: false,
                    });
                } else if ok {
                    if let Some(g) = self.e.next_state(&n.g, c.job) {
                        n.g = g;
                    }
                }
            }
            TG3Action::Begin(who, v) => {
                let i = Inst::unpack(v)?;
                let t = self.e.m.task_of(who.owner());
                let busy = Inst {
                    mark: (i.mark & !(mark::DUE | mark::TICKET)) | mark::BUSY,
                    ..i
                };
                replace(&mut n.g, who, v, Some(busy));
                n.zone.reset(self.exec_clock[t]);
                n.queue.retain(|&u| usize::from(u) != t);
            }
            TG3Action::Ticket(who, v) => {
                let i = Inst::unpack(v)?;
                let t = self.e.m.task_of(who.owner());
                let held = Inst {
                    mark: i.mark | mark::TICKET,
                    ..i
                };
                replace(&mut n.g, who, v, Some(held));
                n.queue.push(t as u8);
            }
            TG3Action::End(who, v, o) => {
                let i = Inst::unpack(v)?;
                let t = self.e.m.task_of(who.owner());
                if !n
                    .zone
                    .lower(self.exec_clock[t], self.locks.lower(who.owner(), i.state))
                {
                    return None;
                }
                self.end(&mut n, who, i, o);
            }
        }
        Some(self.finish(n))
    }

    /// The control thread begins its next control codel.
    fn ctl_phase(&self, n: &mut TG3State) -> Option<()> {
        let c = n.ctl?;
        n.ctl = Some(Ctl { running: true, ..c });
        n.queue.retain(|&u| u != CTL);
        n.zone.reset(self.ctl_clock);
        Some(())
    }

    /// Task `t`'s tick: an overrun when its work is unfinished (and not
    /// about to finish at this instant), else a new wake-up.
    fn tick(&self, mut n: TG3State, t: usize) -> Option<TG3State> {
        let x = self.period_clock[t]?;
        let first = n.ticked >> t & 1 == 0;
        let at = if first {
            self.delay[t]
        } else {
            self.period[t]?
        };
        if !n.zone.lower(x, at) {
            return None;
        }
        if self.unfinished(&n, t) && self.coalesce {
            n.late |= 1 << t;
            n.ticked |= 1 << t;
            n.zone.reset(x);
            return Some(self.finish(n));
        }
        if self.unfinished(&n, t) {
            n.zone = self.overrun_zone(&n, t)?;
            n.violation = Some(t as u8);
            return Some(n);
        }
        n.ticked |= 1 << t;
        n.zone.reset(x);
        if self.spawned(&n.g, t) {
            self.sweep(&mut n.g, t, true);
        }
        Some(self.finish(n))
    }

    /// Where the unfinished work of task `t` at its tick is an overrun:
    /// its running codel has not reached its WCET (at its WCET it ends
    /// first, at the same instant); or, idle, a due codel waits for a lock
    /// whose holder has not reached its WCET. `None` when the work may
    /// still end at this instant (zero-time steps come first).
    fn overrun_zone(&self, st: &TG3State, t: usize) -> Option<Dbm> {
        let below = |clock: usize, w: Option<i64>| {
            let mut z = st.zone.clone();
            match w {
                Some(w) => z.constrain(clock, 0, lt(w)).then_some(z),
                None => Some(z),
            }
        };
        if let Some((who, i)) = self.running(&st.g, t) {
            return below(self.exec_clock[t], self.locks.wcet(who.owner(), i.state));
        }
        if self.urgent(st) {
            return None;
        }
        // The locks that keep the queue up to `t`'s ticket waiting.
        let queued = self.queued_codels(st, t as u8);
        let holders: Vec<_> = self
            .holders(st, Some(t))
            .filter(|&(j, _, _)| {
                queued.is_empty() || queued.iter().any(|&k| self.locks.excludes(k, j))
            })
            .collect();
        if holders.is_empty() {
            // Due work that nothing running delays and that cannot begin:
            // it stays unfinished at the tick.
            return Some(st.zone.clone());
        }
        holders
            .into_iter()
            .find_map(|(_, clock, w)| below(clock, w))
    }

    /// Opens a sweep of task `t`: instances due to run a codel; when
    /// `runnable` (a tick, an activation, or an aperiodic task's
    /// continuation), accepted instances start and paused ones resume.
    pub(super) fn sweep(&self, g: &mut G3State, t: usize, runnable: bool) {
        let before = total(g);
        if let Some(i) = g.perm[t] {
            g.perm[t] = Some(due(i, runnable));
        }
        for &a in &self.acts_of[t] {
            let start = self.e.m.activities[a].fsm.start;
            let old = std::mem::take(&mut g.inst[a]);
            let mut new = Vec::with_capacity(old.len());
            for i in old {
                match i.status {
                    Status::Ready if runnable => match start {
                        Some(s) => new.push(Inst {
                            status: Status::Run,
                            state: s,
                            mark: mark::DUE,
                        }),
                        None => g.set_done(service_index(&self.e.m, a)),
                    },
                    Status::Run | Status::Stop => new.push(due(i, runnable)),
                    _ => new.push(i),
                }
            }
            new.sort_unstable();
            g.inst[a] = new;
        }
        if total(g) < before {
            self.e.settle(g, true);
        }
    }

    /// The steps that follow at once: an idle task with nothing due whose
    /// last sweep made an unpaused transition sweeps again.
    pub(super) fn finish(&self, mut n: TG3State) -> TG3State {
        self.drop_stale_tickets(&mut n);
        for t in 0..self.e.m.tasks.len() {
            if n.cont >> t & 1 == 1
                && !self
                    .instances(&n.g, t)
                    .any(|(_, i)| i.has(mark::BUSY | mark::DUE))
            {
                n.cont &= !(1 << t);
                self.sweep(&mut n.g, t, self.period[t].is_none());
            }
            // A coalesced tick: the task wakes as soon as its work ended.
            if n.late >> t & 1 == 1 && !self.unfinished(&n, t) && self.spawned(&n.g, t) {
                n.late &= !(1 << t);
                self.sweep(&mut n.g, t, true);
            }
        }
        n
    }

    /// Drops the tickets whose codel is gone (its instance was removed, or
    /// the control thread's request ended).
    fn drop_stale_tickets(&self, n: &mut TG3State) {
        if n.queue.is_empty() {
            return;
        }
        let holds = |u: u8| {
            if u == CTL {
                n.ctl.is_some_and(|c| !c.running)
            } else {
                self.ticket_of(&n.g, usize::from(u)).is_some()
            }
        };
        let kept: Vec<u8> = n.queue.iter().copied().filter(|&u| holds(u)).collect();
        n.queue = kept;
    }

    /// Ends the running codel of instance `i` with outcome `o`: the untimed
    /// rule, then the marks (`pause::`, continuation) and a pending
    /// interruption.
    fn end(&self, n: &mut TG3State, who: Who, i: Inst, o: u8) {
        let owner = who.owner();
        let t = self.e.m.task_of(owner);
        let clean = Inst::new(i.status, i.state);
        replace(&mut n.g, who, i.pack(), Some(clean));
        let before = total(&n.g);
        let target = self.e.m.fsm(owner).states[usize::from(i.state)]
            .yields
            .get(usize::from(o))
            .copied();
        match who {
            Who::Act(a) => self.e.codel(&mut n.g, usize::from(a), clean.pack(), o),
            Who::Perm(p) => self.e.perm(&mut n.g, usize::from(p), o),
        }
        if let Some(Target::State { state, pause }) = target {
            let landed = Inst::new(i.status, state);
            if !pause {
                n.cont |= 1 << t;
            }
            // Interrupted during this codel: its stop path (or its end).
            let kept = if i.has(mark::FLAGGED) && i.status == Status::Run {
                self.e.m.fsm(owner).stop.map(|s| Inst::new(Status::Stop, s))
            } else {
                Some(Inst {
                    mark: if pause { mark::PAUSED } else { 0 },
                    ..landed
                })
            };
            replace(&mut n.g, who, landed.pack(), kept);
        }
        let ended = total(&n.g) < before;
        self.e.settle(&mut n.g, ended);
    }
}

/// Instance `i` at the opening of a sweep: due unless paused and the sweep
/// resumes nothing.
fn due(i: Inst, runnable: bool) -> Inst {
    if !matches!(i.status, Status::Run | Status::Stop) || i.has(mark::BUSY) {
        return i;
    }
    if i.has(mark::PAUSED) && !runnable {
        return i;
    }
    Inst {
        mark: (i.mark & !mark::PAUSED) | mark::DUE,
        ..i
    }
}

/// Replaces one instance (packed `v`) of `who` by `new` (or removes it).
fn replace(g: &mut G3State, who: Who, v: u16, new: Option<Inst>) {
    match who {
        Who::Act(a) => {
            let list = &mut g.inst[usize::from(a)];
            remove(list, v);
            if let Some(i) = new {
                insert(list, i);
            }
        }
        Who::Perm(t) => {
            let slot = &mut g.perm[usize::from(t)];
            if slot.is_some_and(|i| i.pack() == v) {
                *slot = new;
            }
        }
    }
}
