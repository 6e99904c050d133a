//! The steps of the timed GenoM3 replay: wake-ups and sweeps, codels
//! beginning and ending, the control thread's requests, and what follows
//! each at once (continuation sweeps, pending interrupters re-examined,
//! boot and shutdown).

use genom_model::component::ServiceId;
use genom_model::trace::{Event, TraceStep};

use super::reading::{Builtin, Owner};
use super::{Codel, Inst, Interval, Phase, Request, Sim, Status, Yield, parse_yield};

impl Sim<'_, '_> {
    /// Applies step `k`; `last`: the violating tick.
    pub(super) fn step(&mut self, s: &TraceStep, k: usize, last: bool) -> Result<(), String> {
        let control = s.thread.as_deref() == Some("control");
        match s.event {
            Event::WakeUp => self.wake(s, last),
            Event::CodelStart if control => self.ctl_start(s, k),
            Event::CodelEnd if control => self.ctl_end(s, k),
            Event::CodelStart => self.codel_start(s, k),
            Event::CodelEnd => self.codel_end(s, k),
            Event::LockWait if control => self.ctl_ticket(),
            Event::LockWait => self.ticket(s),
            Event::Request | Event::Accept | Event::Interrupt if !control => {
                Err("requests are handled by the `control` thread".into())
            }
            Event::Request => self.request(s),
            Event::Accept => self.accept(s),
            Event::Interrupt => self.abort(s),
            e => Err(format!("`{}` is no step of the timed engine", e.as_str())),
        }
    }

    /// A tick or an activation.
    fn wake(&mut self, s: &TraceStep, last: bool) -> Result<(), String> {
        let t = self.task_named(s.thread.as_deref())?;
        let name = &self.m.tasks[t].name;
        match (s.outcome.as_deref(), self.m.tasks[t].period_ns) {
            (Some("tick"), Some(p)) => {
                if self.next_tick[t] != Some(self.now) {
                    let at = self.next_tick[t].unwrap_or_default();
                    return Err(format!("task `{name}`'s tick is at {at} ns"));
                }
                if last {
                    return self.overrun(t);
                }
                if self.unfinished(t) && self.coalesce {
                    self.late[t] = true;
                    self.next_tick[t] = Some(self.now + p);
                    return Ok(());
                }
                if self.unfinished(t) {
                    return Err(format!(
                        "task `{name}` reaches its tick with its work unfinished: that is the overrun"
                    ));
                }
                self.next_tick[t] = Some(self.now + p);
                if self.spawned(t) {
                    self.sweep(t, true);
                }
                Ok(())
            }
            (Some("activation"), None) => {
                let idle = |i: &Inst| {
                    self.task_of(i.owner) == t
                        && (i.status == Status::Ready || (i.started() && i.busy.is_none()))
                };
                if !self.spawned(t) || self.unfinished(t) || !self.insts.iter().any(idle) {
                    return Err(format!(
                        "task `{name}` is not asleep with an instance to start or resume"
                    ));
                }
                self.sweep(t, true);
                Ok(())
            }
            _ => Err(format!(
                "task `{name}` wakes by `tick` if periodic, else by `activation`"
            )),
        }
    }

    /// The violating tick finds task `t`'s work really unfinished.
    fn overrun(&self, t: usize) -> Result<(), String> {
        let name = &self.m.tasks[t].name;
        let before_wcet = |(c, since): (Codel, u64)| {
            let def = match c {
                Codel::Fsm(o, s) => Some(self.fsm_state(o, s)),
                Codel::Ctl(sid, i) => self.m.control_codels.get(&sid).and_then(|v| v.get(i)),
            };
            def.is_some_and(|d| d.is_async || self.now - since < d.wcet_ns.unwrap_or(0))
        };
        if let Some(p) = self.running(t) {
            let i = &self.insts[p];
            let since = i.busy.unwrap_or(self.now);
            if before_wcet((Codel::Fsm(i.owner, i.state), since)) {
                return Ok(());
            }
            return Err(format!(
                "task `{name}`'s running codel has reached its WCET: it ends at this instant"
            ));
        }
        let holders = self.holders(Some(t));
        let queued = self.queued_up_to(Some(t));
        let blocked = holders
            .iter()
            .any(|&(j, since)| queued.iter().any(|&k| self.waits(k, j)) && before_wcet((j, since)));
        if blocked {
            return Ok(());
        }
        Err(format!(
            "task `{name}` has no codel running before its WCET nor waiting for a busy lock: no overrun"
        ))
    }

    /// Opens a sweep of task `t`: due instances; `runnable`: accepted ones
    /// start, paused ones resume.
    pub(super) fn sweep(&mut self, t: usize, runnable: bool) {
        let before = self.insts.len();
        let mut done = Vec::new();
        let m = self.m;
        let task_of = |o: Owner| m.task_of(o);
        self.insts.retain_mut(|i| {
            if task_of(i.owner) != t {
                return true;
            }
            match i.status {
                Status::Ready if runnable => {
                    let Owner::Activity(a) = i.owner else {
                        return true;
                    };
                    match m.activities[a].fsm.start {
                        Some(s) => {
                            *i = Inst::new(i.owner, Status::Run, s);
                            i.due = true;
                        }
                        None => {
                            done.push(m.activities[a].service);
                            return false;
                        }
                    }
                }
                Status::Run | Status::Stop if i.busy.is_none() && (runnable || !i.paused) => {
                    i.due = true;
                    i.paused = false;
                }
                _ => {}
            }
            true
        });
        self.done.extend(done);
        let ended = self.insts.len() < before;
        if ended {
            self.settle(true);
        }
    }

    /// Continuation sweeps of tasks with nothing left due.
    pub(super) fn finish(&mut self) {
        self.drop_stale_tickets();
        for t in 0..self.m.tasks.len() {
            let busy = self
                .insts
                .iter()
                .any(|i| self.task_of(i.owner) == t && (i.due || i.busy.is_some()));
            if self.cont[t] && !busy {
                self.cont[t] = false;
                self.sweep(t, self.m.tasks[t].period_ns.is_none());
            }
            if self.late[t] && !self.unfinished(t) && self.spawned(t) {
                self.late[t] = false;
                self.sweep(t, true);
            }
        }
    }

    /// The instance (position) a task-thread codel step names: the
    /// step's service (none: the task's permanent activity) at state
    /// `codel`, passing `fits`.
    fn find(&self, s: &TraceStep, fits: impl Fn(&Inst) -> bool) -> Result<usize, String> {
        let t = self.task_named(s.thread.as_deref())?;
        let owner = match s.service.as_deref() {
            None => Owner::Task(t),
            name => {
                let sid = self.service_named(name)?;
                let a = self.activity_of(sid).ok_or("that service is no activity")?;
                if self.m.activities[a].task != t {
                    return Err("that activity runs on another task".into());
                }
                Owner::Activity(a)
            }
        };
        let codel = s.codel.as_deref().ok_or("the step names no state")?;
        let at = |i: &Inst| {
            i.owner == owner && i.started() && self.fsm_state(owner, i.state).name == codel
        };
        self.insts
            .iter()
            .position(|i| at(i) && fits(i))
            .ok_or_else(|| format!("no instance fit for this step is at state `{codel}`"))
    }

    fn codel_start(&mut self, s: &TraceStep, k: usize) -> Result<(), String> {
        let t = self.task_named(s.thread.as_deref())?;
        if !self.spawned(t) {
            return Err("the task has not started yet (boot order)".into());
        }
        if self.running(t).is_some() {
            return Err("the task runs another codel".into());
        }
        let p = self
            .find(s, |i| i.due)
            .map_err(|e| format!("{e} (due in the task's sweep)"))?;
        if self.queue.contains(&Some(t)) && !self.insts[p].ticket {
            return Err("the task holds a ticket for another codel".into());
        }
        // An `async` codel takes no lock and no ticket (7.2).
        if !self
            .fsm_state(self.insts[p].owner, self.insts[p].state)
            .is_async
        {
            self.served(Some(t))?;
        }
        let i = &mut self.insts[p];
        i.due = false;
        i.ticket = false;
        i.busy = Some(self.now);
        let codel = Codel::Fsm(i.owner, i.state);
        self.runs.push(Interval {
            thread: Some(t),
            codel,
            start: self.now,
            end: None,
            step: k,
            end_step: None,
        });
        Ok(())
    }

    fn codel_end(&mut self, s: &TraceStep, k: usize) -> Result<(), String> {
        let t = self.task_named(s.thread.as_deref())?;
        let p = self.find(s, |i| i.busy.is_some())?;
        let i = self.insts[p].clone();
        let def = self.fsm_state(i.owner, i.state);
        let took = self.now - i.busy.unwrap_or(self.now);
        let w = def.wcet_ns.unwrap_or(0);
        if def.is_async && took < w {
            return Err(format!(
                "`async` codel took {took} ns, less than its {w} ns"
            ));
        }
        // Past its WCET, time could not have reached this step (`overdue`).
        if let Some(r) = self.runs.iter_mut().rev().find(|r| r.thread == Some(t)) {
            r.end = Some(self.now);
            r.end_step = Some(k);
        }
        let text = s.outcome.as_deref().ok_or("the step has no outcome")?;
        let y = parse_yield(self.m, i.owner, def, text)?;
        let before = self.insts.len();
        let booting =
            matches!(self.phase, Phase::Boot(b) if b == t) && matches!(i.owner, Owner::Task(_));
        match y {
            Yield::To(state, pause) => {
                self.cont[t] |= !pause;
                let n = &mut self.insts[p];
                n.busy = None;
                if i.flagged && i.status == Status::Run {
                    let stop = self.m.fsm(i.owner).stop;
                    match stop {
                        Some(st) => *n = Inst::new(i.owner, Status::Stop, st),
                        None => {
                            self.insts.remove(p);
                        }
                    }
                } else {
                    n.state = state;
                    n.paused = pause;
                }
            }
            Yield::Ether | Yield::Exception => {
                self.insts.remove(p);
                if let (Yield::Ether, Owner::Activity(a)) = (&y, i.owner) {
                    self.done.insert(self.m.activities[a].service);
                }
                if booting && matches!(y, Yield::Exception) {
                    self.phase = Phase::Failed;
                }
            }
        }
        if let (true, Phase::Boot(b)) = (booting, self.phase) {
            self.phase = Phase::Boot(b + 1);
        }
        let ended = self.insts.len() < before;
        self.settle(ended);
        Ok(())
    }

    /// Whether `after`/`before` let `sid` run.
    fn admissible(&self, sid: ServiceId) -> Result<(), String> {
        let name = self.m.service_name(sid);
        if self.phase != Phase::Run {
            return Err("requests are handled once every task started, until `kill`".into());
        }
        if self.ctl.is_some() {
            return Err("the control thread handles another request".into());
        }
        if self
            .m
            .ordered(sid, true)
            .iter()
            .any(|x| !self.done.contains(x))
        {
            return Err(format!(
                "`{name}` is `after` a service that never completed"
            ));
        }
        if self
            .m
            .ordered(sid, false)
            .iter()
            .any(|x| self.done.contains(x))
        {
            return Err(format!("`{name}` is `before` a service that completed"));
        }
        if let Some(a) = self.activity_of(sid) {
            let mine = |i: &&Inst| i.owner == Owner::Activity(a);
            // A request to an activity that interrupts itself may come
            // while its instances run (it interrupts them and waits).
            if self.insts.iter().filter(mine).count() >= self.m.instance_bound(a) {
                return Err(format!("`{name}` has its most instances already"));
            }
        }
        Ok(())
    }

    fn request(&mut self, s: &TraceStep) -> Result<(), String> {
        let sid = self.service_named(s.service.as_deref())?;
        self.admissible(sid)?;
        if self.timed_codels(sid).is_empty() {
            return Err("its service has no control codel that takes time and a lock".into());
        }
        self.ctl = Some(Request {
            service: sid,
            next: 0,
            since: None,
        });
        Ok(())
    }

    fn ctl_start(&mut self, s: &TraceStep, k: usize) -> Result<(), String> {
        let r = self
            .ctl
            .clone()
            .ok_or("the control thread handles no request")?;
        let codels = self.timed_codels(r.service);
        let i = *codels.get(r.next).ok_or("the request has no codel left")?;
        let name = &self.m.control_codels[&r.service][i].name;
        if r.since.is_some() || s.codel.as_deref() != Some(name.as_str()) {
            return Err(format!("the control thread's next codel is `{name}`"));
        }
        self.served(None)?;
        self.ctl = Some(Request {
            since: Some(self.now),
            ..r
        });
        self.runs.push(Interval {
            thread: None,
            codel: Codel::Ctl(r.service, i),
            start: self.now,
            end: None,
            step: k,
            end_step: None,
        });
        Ok(())
    }

    /// A task takes a ticket for a due codel it cannot begin now.
    fn ticket(&mut self, s: &TraceStep) -> Result<(), String> {
        let t = self.task_named(s.thread.as_deref())?;
        if !self.spawned(t) || self.running(t).is_some() || self.queue.contains(&Some(t)) {
            return Err("the task is not idle without a ticket".into());
        }
        let p = self
            .find(s, |i| i.due)
            .map_err(|e| format!("{e} (due in the task's sweep)"))?;
        let k = Codel::Fsm(self.insts[p].owner, self.insts[p].state);
        if self.queue.is_empty() && !self.held(Some(t), k) {
            return Err("the codel may begin now (its locks are free, no ticket is queued)".into());
        }
        self.insts[p].ticket = true;
        self.queue.push(Some(t));
        Ok(())
    }

    /// The control thread takes a ticket for its next codel.
    fn ctl_ticket(&mut self) -> Result<(), String> {
        let k = self
            .ctl_codel()
            .ok_or("the control thread has no codel to begin")?;
        if self.queue.contains(&None) {
            return Err("the control thread already holds a ticket".into());
        }
        if self.queue.is_empty() && !self.held(None, k) {
            return Err(
                "the control codel may begin now (its locks are free, no ticket is queued)".into(),
            );
        }
        self.queue.push(None);
        Ok(())
    }

    fn ctl_end(&mut self, s: &TraceStep, k: usize) -> Result<(), String> {
        let r = self
            .ctl
            .clone()
            .ok_or("the control thread handles no request")?;
        r.since.ok_or("the control thread runs no codel")?;
        let codels = self.timed_codels(r.service);
        let i = codels.get(r.next).copied().unwrap_or_default();
        let def = &self.m.control_codels[&r.service][i];
        if s.codel.as_deref() != Some(def.name.as_str()) {
            return Err(format!("the control thread runs `{}`", def.name));
        }
        // Past its WCET, time could not have reached this step (`overdue`).
        if let Some(x) = self.runs.iter_mut().rev().find(|x| x.thread.is_none()) {
            x.end = Some(self.now);
            x.end_step = Some(k);
        }
        self.ctl = None;
        match s.outcome.as_deref() {
            Some("exception") if def.ids_copy => {
                Err("an attribute's ids copy throws no exception".into())
            }
            Some("exception") => Ok(()),
            Some("ok") if r.next + 1 < codels.len() => {
                self.ctl = Some(Request {
                    next: r.next + 1,
                    since: None,
                    ..r
                });
                Ok(())
            }
            Some("ok") => {
                self.effect(r.service);
                Ok(())
            }
            _ => Err("a control codel ends `ok` or `exception`".into()),
        }
    }

    fn accept(&mut self, s: &TraceStep) -> Result<(), String> {
        let sid = self.service_named(s.service.as_deref())?;
        self.admissible(sid)?;
        if self.m.builtin(sid) == Some(Builtin::Abort) {
            return Err("`abort_activity` is an `interrupt` step".into());
        }
        let pending = self.effect(sid);
        match (s.outcome.as_deref(), pending) {
            (None, false) | (Some("pending"), true) => Ok(()),
            (Some("pending"), false) => Err("the new instance does not wait: not pending".into()),
            (None, true) => {
                Err("the new instance waits for the ones it interrupts: `pending`".into())
            }
            (Some(o), _) => Err(format!("an accepted request has no outcome `{o}`")),
        }
    }

    /// A request's effect once its control codels succeeded; whether the
    /// new instance waits for the ones it interrupts.
    fn effect(&mut self, sid: ServiceId) -> bool {
        let before = self.insts.len();
        let mut wait = false;
        match self.activity_of(sid) {
            Some(a) => {
                for x in self.targets(sid) {
                    wait |= self.flag(x, false);
                }
                let status = if wait { Status::Delayed } else { Status::Ready };
                self.insts.push(Inst::new(Owner::Activity(a), status, 0));
                self.accepted[a] = Some(self.now);
                let ended = self.insts.len() <= before;
                self.settle(ended);
            }
            None => {
                self.done.insert(sid);
                for x in self.targets(sid) {
                    self.flag(x, false);
                }
                if self.m.builtin(sid) == Some(Builtin::Kill) {
                    self.phase = Phase::Drain;
                }
                let ended = self.insts.len() < before;
                self.settle(ended);
            }
        }
        wait
    }

    /// `abort_activity` on one instance (`codel`: its state if started).
    fn abort(&mut self, s: &TraceStep) -> Result<(), String> {
        let k = self.m.builtin_service(Builtin::Abort);
        let k = k.ok_or("there is no `abort_activity`")?;
        self.admissible(k)?;
        let sid = self.service_named(s.service.as_deref())?;
        let a = self.activity_of(sid).ok_or("that service is no activity")?;
        let fits = |i: &Inst| {
            i.owner == Owner::Activity(a)
                && match s.codel.as_deref() {
                    Some(c) => {
                        i.status == Status::Run && self.fsm_state(i.owner, i.state).name == c
                    }
                    None => !i.started(),
                }
        };
        let p = self.insts.iter().position(fits);
        let p = p.ok_or("no instance to interrupt is at that state")?;
        self.done.insert(k);
        let i = self.insts.remove(p);
        let ended = match self.interrupted(i) {
            Some(i) => {
                self.insts.insert(p, i);
                false
            }
            None => true,
        };
        self.settle(ended);
        Ok(())
    }

    /// What interrupting `i` leaves (see the module doc).
    fn interrupted(&self, i: Inst) -> Option<Inst> {
        match i.status {
            Status::Delayed | Status::Ready => None,
            Status::Run if i.due || i.busy.is_some() => Some(Inst { flagged: true, ..i }),
            Status::Run => {
                let stop = self.m.fsm(i.owner).stop;
                stop.map(|s| Inst::new(i.owner, Status::Stop, s))
            }
            Status::Stop => Some(i),
        }
    }

    /// Interrupts activity `a`'s instances (`spare`: not those not started
    /// yet); whether one of them is stopping afterwards.
    fn flag(&mut self, a: usize, spare: bool) -> bool {
        let old = std::mem::take(&mut self.insts);
        for i in old {
            if i.owner != Owner::Activity(a) || (spare && !i.started()) {
                self.insts.push(i);
            } else if let Some(i) = self.interrupted(i) {
                self.insts.push(i);
            }
        }
        self.insts
            .iter()
            .any(|i| i.owner == Owner::Activity(a) && (i.status == Status::Stop || i.flagged))
    }

    /// What follows at once: boot progress, pending interrupters
    /// re-examined after an end, the shutdown sequence.
    pub(super) fn settle(&mut self, ended: bool) {
        let n = self.m.tasks.len();
        while let Phase::Boot(b) = self.phase {
            if b >= n {
                self.phase = Phase::Run;
            } else if self.insts.iter().any(|i| i.owner == Owner::Task(b)) {
                break;
            } else {
                self.phase = Phase::Boot(b + 1);
            }
        }
        let mut again = ended;
        while again {
            let count = self.insts.len();
            let mut changed = false;
            for a in 0..self.m.activities.len() {
                let mine = |i: &Inst| i.owner == Owner::Activity(a);
                if !self.insts.iter().any(|i| mine(i) && !i.started()) {
                    continue;
                }
                let sid = self.m.activities[a].service;
                let targets = self.targets(sid);
                if targets.is_empty() {
                    continue;
                }
                let old = self.insts.clone();
                let mut wait = false;
                for x in targets {
                    wait |= self.flag(x, x == a);
                }
                if !wait {
                    for i in self.insts.iter_mut().filter(|i| mine(i)) {
                        if i.status == Status::Delayed {
                            i.status = Status::Ready;
                        }
                    }
                }
                changed |= self.insts != old;
            }
            again = changed && self.insts.len() < count;
        }
        let acts = |i: &Inst| matches!(i.owner, Owner::Activity(_));
        if self.phase == Phase::Drain && !self.insts.iter().any(acts) {
            self.insts.clear();
            self.perm_stop(n);
        }
        if let Phase::PermStop(t) = self.phase {
            if !self.insts.iter().any(|i| i.owner == Owner::Task(t)) {
                self.perm_stop(t);
            }
        }
    }

    /// The last task before `below` with a permanent `stop` goes to it.
    fn perm_stop(&mut self, below: usize) {
        for t in (0..below).rev().filter(|&t| self.scope[t]) {
            if let Some(s) = self.m.tasks[t].perm.as_ref().and_then(|f| f.stop) {
                self.insts.push(Inst::new(Owner::Task(t), Status::Stop, s));
                self.phase = Phase::PermStop(t);
                return;
            }
        }
        self.phase = Phase::Stopped;
    }
}
