//! What the end of a timed trace must show: the claim of its verdict.

use genom_model::TraceStep;
use genom_model::component::ThreadId;

use super::{Checker, Main, TimedClaim, wcet};

impl Checker<'_> {
    pub(super) fn claim(
        &mut self,
        claim: TimedClaim<'_>,
        steps: &[TraceStep],
    ) -> Result<(), String> {
        let over: Vec<ThreadId> = self
            .threads
            .iter()
            .filter(|(_, th)| th.overrun_at.is_some())
            .map(|(&t, _)| t)
            .collect();
        match claim {
            TimedClaim::Rules => {
                if !over.is_empty() {
                    return Err("an overrun the verdict does not claim".to_owned());
                }
                Ok(())
            }
            TimedClaim::Overrun(name) => {
                let tid = self
                    .c
                    .thread_named(name)
                    .ok_or_else(|| format!("no thread `{name}`"))?;
                if over != [tid] {
                    return Err(format!("the last wake-up of `{name}` is not an overrun"));
                }
                let th = &self.threads[&tid];
                let (k, w) = th.overrun_at.ok_or("no overrun")?;
                if k + 2 != steps.len() {
                    return Err(
                        "the overrun wake-up is not the step before the violation".to_owned()
                    );
                }
                if let Some((_, codel, since)) = self.running_on(tid) {
                    if w - since < wcet(self.c, codel) {
                        return Ok(());
                    }
                    return Err(format!(
                        "`{}` has run its whole WCET at the wake-up instant: it ends then, in time",
                        self.c.codel_label(codel)
                    ));
                }
                let genuine = th
                    .eligible
                    .iter()
                    .filter(|s| !th.ran.contains(s))
                    .any(|&s| {
                        self.ready_codel(s).is_some_and(|k| {
                            wcet(self.c, k) > 0
                                || self.running_elsewhere(tid).iter().any(|&(_, o, since)| {
                                    self.c.conflicts(k, o) && w - since < wcet(self.c, o)
                                })
                        })
                    });
                if genuine {
                    Ok(())
                } else {
                    Err("the services still to run can all end at the wake-up instant".to_owned())
                }
            }
            TimedClaim::LateService(name) => {
                if !over.is_empty() {
                    return Err("an overrun the verdict does not claim".to_owned());
                }
                let s = self.c.service_named(name).ok_or("no service")?;
                let m = self.c.services[s].max_time.ok_or("no max-time")?.ns;
                let v = &self.svc[s.0 as usize];
                let (ack, alive) = match (&v.main, v.main_ack, v.pending_ack) {
                    (_, _, Some(p)) if v.main == Main::Idle => (p, true),
                    (Main::Ready { stopping, .. }, Some(a), _) => (a, !stopping),
                    (
                        Main::Running {
                            interrupted,
                            stopping,
                            ..
                        },
                        Some(a),
                        _,
                    ) => (a, !interrupted && !stopping),
                    _ => return Err(format!("`{name}` has no instance at the end")),
                };
                if !alive {
                    return Err(format!("`{name}` was interrupted before the end"));
                }
                if self.now <= ack + m {
                    return Err(format!(
                        "the violation at {} ns is not after the deadline {} ns",
                        self.now,
                        ack + m
                    ));
                }
                self.end.late_ack_ns = Some(ack);
                Ok(())
            }
            TimedClaim::PastDeadline(name, deadline) => {
                if !over.is_empty() {
                    return Err("an overrun the verdict does not claim".to_owned());
                }
                let s = self.c.service_named(name).ok_or("no service")?;
                let v = &self.svc[s.0 as usize];
                // The oldest instance without reply: the main one if any.
                let ack = match (&v.main, v.main_ack, v.pending_ack) {
                    (Main::Idle, _, Some(p)) => p,
                    (Main::Idle, _, None) => {
                        return Err(format!("`{name}` has no instance at the end"));
                    }
                    (_, Some(a), _) => a,
                    (_, None, _) => return Err(format!("`{name}` has no acknowledged instance")),
                };
                if self.owed.contains(&s) {
                    return Err(format!("`{name}` has ended and owes its reply"));
                }
                if self.now <= ack + deadline {
                    return Err(format!(
                        "the violation at {} ns is not after the deadline {} ns",
                        self.now,
                        ack + deadline
                    ));
                }
                self.end.late_ack_ns = Some(ack);
                Ok(())
            }
        }
    }
}
