//! The steps of the timed-trace checker: wake-ups, requests and their
//! control codels, acknowledgments and starts, codels beginning and
//! ending, interruptions and watchdogs, replies.

use std::collections::BTreeSet;

use genom_model::component::{CodelId, ServiceId};
use genom_model::{Event, TraceStep};

use super::{Checker, Main, Thr, is_auto, watchdog_instant, wcet};

impl Checker<'_> {
    pub(super) fn step(
        &mut self,
        k: usize,
        step: &TraceStep,
        t: u64,
        last: bool,
    ) -> Result<(), String> {
        self.advance(t, last)?;
        if !last {
            if let Some((tid, _)) = self.threads.iter().find(|(_, th)| th.overrun_at.is_some()) {
                return Err(format!(
                    "thread `{}` overran at its last wake-up, and the trace goes on",
                    self.c.threads[*tid].name.name
                ));
            }
        }
        match step.event {
            Event::ComponentStart => Err("the component starts only once".to_owned()),
            Event::WakeUp => self.wake_up(k, step, t),
            Event::Request => self.request(step, t),
            Event::Accept | Event::Reject => self.control_end(step),
            Event::Acknowledge => {
                let s = self.service(step)?;
                let v = &mut self.svc[s.0 as usize];
                v.pending_ack = Some(t);
                if let Some(tid) = self.thread_of(s) {
                    if let Some(th) = self.threads.get_mut(&tid) {
                        th.order.retain(|&x| x != s);
                        th.order.push(s);
                    }
                }
                Ok(())
            }
            Event::Start => {
                let s = self.service(step)?;
                let auto = is_auto(self.c, s) && self.svc[s.0 as usize].pending_ack.is_none();
                if auto {
                    // Autos are never pending: their start is their
                    // acknowledgment (the max-time clock starts now).
                    self.svc[s.0 as usize].pending_ack = Some(t);
                    if let Some(th) = self.thread_of(s).and_then(|tid| self.threads.get_mut(&tid)) {
                        th.order.retain(|&x| x != s);
                        th.order.push(s);
                    }
                }
                let v = &mut self.svc[s.0 as usize];
                v.main_ack = v.pending_ack.take();
                v.last_ran = None;
                match self.c.services[s].start {
                    Some(start) => {
                        v.main = Main::Ready {
                            codel: start,
                            stopping: false,
                        };
                    }
                    None => self.owed.push(s),
                }
                Ok(())
            }
            Event::CodelStart => self.codel_start(step, t),
            Event::CodelEnd => self.codel_end(step, t),
            Event::Interrupt | Event::Watchdog => self.interrupt(step, t),
            Event::Reply => {
                let s = self.service(step)?;
                let at = self
                    .owed
                    .iter()
                    .position(|&x| x == s)
                    .ok_or("a reply with no ended instance")?;
                self.owed.remove(at);
                let v = &self.svc[s.0 as usize];
                if v.main == Main::Idle && v.pending_ack.is_none() {
                    if let Some(tid) = self.thread_of(s) {
                        if let Some(th) = self.threads.get_mut(&tid) {
                            th.order.retain(|&x| x != s);
                        }
                    }
                }
                Ok(())
            }
            Event::Delay | Event::Violation => Ok(()),
            Event::LockWait => Err("`lock-wait` is a GenoM3 step".to_owned()),
        }
    }

    fn wake_up(&mut self, k: usize, step: &TraceStep, t: u64) -> Result<(), String> {
        let name = step.thread.as_deref().ok_or("no thread")?;
        let tid = self
            .c
            .thread_named(name)
            .ok_or_else(|| format!("no thread `{name}`"))?;
        let period = self.c.threads[tid]
            .period
            .map(|p| p.ns)
            .ok_or("an aperiodic thread does not wake up")?;
        let running = self.running_on(tid);
        let th = self.threads.entry(tid).or_insert_with(|| Thr {
            period: Some(period),
            next_wake: 0,
            ..Thr::default()
        });
        if t % period != 0 || t != th.next_wake {
            return Err(format!(
                "wakes up at {t} ns, expected {} ns (period {period} ns)",
                th.next_wake
            ));
        }
        let unfinished: Vec<ServiceId> = th
            .eligible
            .iter()
            .copied()
            .filter(|s| !th.ran.contains(s))
            .collect();
        if running.is_some() || !unfinished.is_empty() {
            th.overrun_at = Some((k, t));
            self.end
                .wake_ups
                .entry(name.to_owned())
                .or_default()
                .push(t);
            return Ok(());
        }
        th.next_wake = t + period;
        th.ran.clear();
        let mut eligible = BTreeSet::new();
        for s in self.c.services.ids() {
            if self.thread_of(s) == Some(tid)
                && matches!(self.svc[s.0 as usize].main, Main::Ready { .. })
            {
                eligible.insert(s);
            }
        }
        let th = self.threads.get_mut(&tid).ok_or("thread")?;
        th.eligible = eligible;
        self.end
            .wake_ups
            .entry(name.to_owned())
            .or_default()
            .push(t);
        Ok(())
    }

    fn request(&mut self, step: &TraceStep, t: u64) -> Result<(), String> {
        let s = self.service(step)?;
        let Some(ctl) = self.c.services[s].control else {
            return Ok(());
        };
        if self.control.is_some() {
            return Err("the control thread handles one request at a time".to_owned());
        }
        if step.codel.is_none() {
            // A request rejected by rules 1–3 (`NOT_INITIALIZED`,
            // `FORBIDDEN`, `BUSY`): its control codel does not run.
            return Ok(());
        }
        // FIFO: a thread at its turn that wants a lock of this control codel
        // gets it first.
        for &tid in self.threads.keys() {
            if let Some(k) = self.turn(tid).and_then(|x| self.ready_codel(x)) {
                if self.c.conflicts(k, ctl) {
                    return Err(format!(
                        "the control codel takes a lock that thread `{}`, at its turn with `{}`, gets first",
                        self.c.threads[tid].name.name,
                        self.c.codel_label(k)
                    ));
                }
            }
        }
        // A control codel never runs with a conflicting codel.
        for (_, codel, _) in self.running_all() {
            if self.c.conflicts(codel, ctl) {
                return Err(format!(
                    "the control codel conflicts with running `{}`",
                    self.c.codel_label(codel)
                ));
            }
        }
        self.control = Some((s, t));
        Ok(())
    }

    fn running_all(&self) -> Vec<(ServiceId, CodelId, u64)> {
        self.c
            .services
            .ids()
            .filter_map(|s| match self.svc[s.0 as usize].main {
                Main::Running { codel, since, .. } => Some((s, codel, since)),
                _ => None,
            })
            .collect()
    }

    fn control_end(&mut self, step: &TraceStep) -> Result<(), String> {
        let s = self.service(step)?;
        if let Some((r, _)) = self.control {
            if r != s {
                return Err("the control codel running is another service's".to_owned());
            }
            self.control = None;
        }
        Ok(())
    }

    fn codel_start(&mut self, step: &TraceStep, t: u64) -> Result<(), String> {
        let s = self.service(step)?;
        let codel = self.codel(s, step)?.ok_or("no codel")?;
        let tid = self.thread_of(s).ok_or("the service has no thread")?;
        let tname = &self.c.threads[tid].name.name;
        if step.thread.as_deref() != Some(tname.as_str()) {
            return Err(format!("runs on `{tname}`"));
        }
        if self.ready_codel(s) != Some(codel) {
            return Err("the service is not ready at this codel".to_owned());
        }
        if let Some((_, other, _)) = self.running_on(tid) {
            return Err(format!(
                "thread `{tname}` still runs `{}`",
                self.c.codel_label(other)
            ));
        }
        if let Some(holder) = self.lock_holder(tid, codel) {
            return Err(format!("`{holder}` holds a lock it needs"));
        }
        let periodic = self.c.threads[tid].period.is_some();
        if periodic {
            let th = self.threads.get(&tid).ok_or("the thread never woke up")?;
            if !th.eligible.contains(&s) {
                return Err("the service was not ready at the thread's last wake-up".to_owned());
            }
            if th.ran.contains(&s) {
                return Err("the service already ran a codel in this period".to_owned());
            }
            if self.turn(tid) != Some(s) {
                let first = self.turn(tid).map(|x| self.c.services[x].name.name.clone());
                return Err(format!(
                    "not its turn: `{}` was acknowledged first",
                    first.unwrap_or_default()
                ));
            }
            if let Some(th) = self.threads.get_mut(&tid) {
                th.ran.insert(s);
            }
        }
        let stopping = matches!(
            self.svc[s.0 as usize].main,
            Main::Ready { stopping: true, .. }
        );
        self.svc[s.0 as usize].main = Main::Running {
            codel,
            since: t,
            interrupted: false,
            stopping,
        };
        self.end.codels.push((
            self.c.services[s].name.name.clone(),
            self.c.codels[codel].name.name.clone(),
            t,
            None,
        ));
        Ok(())
    }

    fn codel_end(&mut self, step: &TraceStep, t: u64) -> Result<(), String> {
        let s = self.service(step)?;
        let codel = self.codel(s, step)?.ok_or("no codel")?;
        let Main::Running {
            codel: running,
            since,
            interrupted,
            stopping,
        } = self.svc[s.0 as usize].main
        else {
            return Err("the codel is not running".to_owned());
        };
        if running != codel {
            return Err("another codel of the service is running".to_owned());
        }
        if t < since || t - since > wcet(self.c, codel) {
            return Err(format!(
                "ends {} ns after its start, outside [0, WCET = {} ns]",
                t.saturating_sub(since),
                wcet(self.c, codel)
            ));
        }
        let label = (
            self.c.services[s].name.name.clone(),
            self.c.codels[codel].name.name.clone(),
        );
        if let Some(entry) = self
            .end
            .codels
            .iter_mut()
            .rev()
            .find(|e| e.0 == label.0 && e.1 == label.1 && e.3.is_none())
        {
            entry.3 = Some(t);
        }
        let i = s.0 as usize;
        self.svc[i].last_ran = Some(codel);
        let next = if interrupted {
            self.c.codels[codel].on_inter.map(|r| (r.id, true))
        } else {
            match step.outcome.as_deref() {
                Some(o) => self.c.codel_named(s, o).map(|n| (n, stopping)),
                None => return Err("an uninterrupted codel ends with an outcome".to_owned()),
            }
        };
        match next {
            Some((n, stop)) => {
                self.svc[i].main = Main::Ready {
                    codel: n,
                    stopping: stop,
                };
            }
            None => self.ended(s),
        }
        Ok(())
    }

    fn interrupt(&mut self, step: &TraceStep, t: u64) -> Result<(), String> {
        let s = self.service(step)?;
        let i = s.0 as usize;
        let codel = self.codel(s, step)?;
        let main_live = matches!(self.svc[i].main, Main::Ready { .. } | Main::Running { .. });
        let pending = (codel.is_none() && self.svc[i].pending_ack.is_some()) || !main_live;
        if step.event == Event::Watchdog {
            let m = self.c.services[s]
                .max_time
                .ok_or("no max-time, no watchdog")?
                .ns;
            let ack = if pending {
                self.svc[i].pending_ack
            } else {
                self.svc[i].main_ack
            }
            .ok_or("no instance for the watchdog")?;
            if t < ack {
                return Err("the watchdog fires before the acknowledgment".to_owned());
            }
            let (at, exact) = watchdog_instant(self.c, s);
            if exact && t != ack + m {
                return Err(format!(
                    "the watchdog fires at {t} ns, not at the deadline {} ns",
                    ack + m
                ));
            }
            if !exact && t < ack + at {
                return Err(format!(
                    "the watchdog fires at {t} ns, before the horizon {} ns of its abstracted deadline",
                    ack + at
                ));
            }
        }
        if pending {
            self.svc[i].pending_ack = None;
            self.owed.push(s);
            return Ok(());
        }
        match self.svc[i].main.clone() {
            Main::Running {
                codel,
                since,
                stopping,
                ..
            } => {
                self.svc[i].main = Main::Running {
                    codel,
                    since,
                    interrupted: true,
                    stopping,
                };
            }
            Main::Ready { .. } => {
                match self.svc[i].last_ran.and_then(|r| self.c.codels[r].on_inter) {
                    Some(inter) => {
                        self.svc[i].main = Main::Ready {
                            codel: inter.id,
                            stopping: true,
                        };
                    }
                    None => self.ended(s),
                }
            }
            Main::Idle => return Err("no instance to interrupt".to_owned()),
        }
        Ok(())
    }

    /// The main instance of `s` ends: it owes a reply and leaves its
    /// thread's current period (a new instance runs from the next one).
    fn ended(&mut self, s: ServiceId) {
        let i = s.0 as usize;
        self.svc[i].main = Main::Idle;
        self.svc[i].main_ack = None;
        self.owed.push(s);
        if let Some(th) = self.thread_of(s).and_then(|t| self.threads.get_mut(&t)) {
            th.eligible.remove(&s);
        }
    }
}
