//! The transition relation of the untimed semantics as set transformers:
//! one guarded [`Step`] per action of the explicit `System::apply`
//! (request, begin, each way a codel finishes, each watchdog), whose
//! effect is a sequence of functional updates of a few variables, written
//! from the same rules as `system::steps` and the same local machines
//! ([`genom_model::behaviour`]). Urgent starts (the explicit `closure`)
//! are applied to the whole image until no configuration has a pending
//! instance ready to start; starts only remove instances or start a
//! pending one in place, so the order in which they are applied does not
//! change the configuration they end in, and the set is exact.

use biodivine_lib_bdd::{Bdd, BddVariable};
use genom_model::behaviour::{Effect as Move, IDLE, PosId};
use genom_model::component::{CodelId, StructureId, ThreadId};

use super::layout::Layout;
use crate::dialect::system::{System, conflict};

/// What a step does to the configurations its guard selects.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Effect {
    /// A request for the member is accepted (steps 1–7).
    Request(usize),
    /// The member's main instance moves to a position.
    SetPos(usize, PosId),
    /// The member's main instance ends.
    End(usize),
    /// The watchdog interrupts the member's pending instance.
    WatchdogPending(usize),
    /// The watchdog interrupts the member's main instance.
    WatchdogMain(usize),
}

impl Effect {
    /// Whether the effect can remove an instance or add a pending one, so
    /// that urgent starts may follow.
    fn releases(self) -> bool {
        !matches!(self, Effect::SetPos(..))
    }
}

/// A guarded action.
#[derive(Debug)]
pub(crate) struct Step {
    pub(crate) guard: Bdd,
    pub(crate) effect: Effect,
}

/// The steps of a system, and what their effects need.
#[derive(Debug)]
pub(crate) struct Steps {
    pub(crate) list: Vec<Step>,
    /// Per member, the interrupt effects grouped by the positions they
    /// apply at.
    interrupts: Vec<Vec<(Bdd, Move)>>,
    /// Per member, every position with an interrupt effect.
    interruptible: Vec<Bdd>,
    /// Per member, the variables its ending resets: position, `timed_out`
    /// and the wait-mask bits naming it.
    end_vars: Vec<Vec<BddVariable>>,
    /// Per member that can stay pending, its urgent-start condition.
    ready: Vec<Option<Bdd>>,
    /// Per member, its start position (`None`: it completes at once).
    start: Vec<Option<PosId>>,
    /// Per member, its request guard (steps 1–3).
    pub(crate) request: Vec<Bdd>,
}

impl Steps {
    /// The steps of `sys` over `l`.
    pub(crate) fn new(
        sys: &System<'_>,
        l: &Layout,
        deadline: Option<std::time::Instant>,
    ) -> Option<Steps> {
        let n = sys.len();
        let mut list = Vec::new();
        let mut request = Vec::with_capacity(n);
        let mut interrupts = Vec::with_capacity(n);
        let mut interruptible = Vec::with_capacity(n);
        for i in 0..n {
            if genom_model::limits::out_of_time(deadline) {
                return None;
            }
            let m = sys.machine_of(i);
            let guard = request_guard(sys, l, i);
            list.push(Step {
                guard: guard.clone(),
                effect: Effect::Request(i),
            });
            request.push(guard);
            codel_steps(sys, l, i, &mut list);
            let groups = interrupt_groups(l, i, &m.interrupt);
            let any = groups
                .iter()
                .fold(l.vars.mk_false(), |acc, (g, _)| acc.or(g));
            if m.watchdog {
                if l.slots[i].pend.is_some() {
                    list.push(Step {
                        guard: l.pend(i),
                        effect: Effect::WatchdogPending(i),
                    });
                }
                list.push(Step {
                    guard: any.clone(),
                    effect: Effect::WatchdogMain(i),
                });
            }
            interrupts.push(groups);
            interruptible.push(any);
        }
        list.retain(|s| !s.guard.is_false());
        Some(Steps {
            list,
            interrupts,
            interruptible,
            end_vars: (0..n).map(|i| end_vars(l, i)).collect(),
            ready: (0..n).map(|i| ready(l, i)).collect(),
            start: (0..n).map(|i| sys.machine_of(i).start).collect(),
            request,
        })
    }

    /// The configurations one step from `from` (closed under urgent
    /// starts).
    pub(crate) fn image(&self, l: &Layout, from: &Bdd) -> Bdd {
        self.image_until(l, from, None)
            .unwrap_or_else(|| l.vars.mk_false())
    }

    /// [`Self::image`], or `None` once `deadline` has passed (checked
    /// between steps).
    pub(crate) fn image_until(
        &self,
        l: &Layout,
        from: &Bdd,
        deadline: Option<std::time::Instant>,
    ) -> Option<Bdd> {
        let mut quiet = l.vars.mk_false();
        let mut loud = l.vars.mk_false();
        for s in &self.list {
            if genom_model::limits::out_of_time(deadline) {
                return None;
            }
            let x = from.and(&s.guard);
            if x.is_false() {
                continue;
            }
            let y = self.effect(l, &x, s.effect);
            if s.effect.releases() {
                loud = loud.or(&y);
            } else {
                quiet = quiet.or(&y);
            }
        }
        Some(quiet.or(&self.closure(l, loud)))
    }

    /// The configurations step `k` leads to from `from` (closed under
    /// urgent starts).
    pub(crate) fn step_image(&self, l: &Layout, from: &Bdd, k: usize) -> Bdd {
        self.step_image_until(l, from, k, None)
            .unwrap_or_else(|| l.vars.mk_false())
    }

    /// [`Self::step_image`], or `None` once `deadline` has passed (checked
    /// between the urgent starts of the closure).
    pub(crate) fn step_image_until(
        &self,
        l: &Layout,
        from: &Bdd,
        k: usize,
        deadline: Option<std::time::Instant>,
    ) -> Option<Bdd> {
        let Some(s) = self.list.get(k) else {
            return Some(l.vars.mk_false());
        };
        let x = from.and(&s.guard);
        if x.is_false() {
            return Some(x);
        }
        let y = self.effect(l, &x, s.effect);
        if s.effect.releases() {
            self.closure_until(l, y, deadline)
        } else {
            Some(y)
        }
    }

    /// Applies an effect to configurations satisfying its guard.
    pub(crate) fn effect(&self, l: &Layout, x: &Bdd, e: Effect) -> Bdd {
        match e {
            Effect::Request(i) => self.request(l, x, i),
            Effect::SetPos(i, q) => assign_pos(l, x, i, q),
            Effect::End(i) => self.end(l, x, i),
            Effect::WatchdogPending(i) => interrupt_pending(l, x, i),
            Effect::WatchdogMain(i) => self.interrupt_main(l, x, i, true),
        }
    }

    /// Steps 4–7 of a request for member `i`. Its own pending slot is
    /// cleared first (it is either empty or, with a self-stop, interrupted
    /// below and overwritten at the end), then its wait-mask bits collect
    /// which targets still have a main instance.
    fn request(&self, l: &Layout, x: &Bdd, i: usize) -> Bdd {
        let mut x = interrupt_pending(l, x, i);
        for (bit, &t) in l.facts[i].stops.iter().enumerate() {
            if t != i {
                x = interrupt_pending(l, &x, t);
            }
            x = self.interrupt_main(l, &x, t, false);
            let v = l.slots[i].mask[bit];
            let busy = l.pos_eq(t, IDLE).not();
            x = x.var_exists(v).and(&l.vars.mk_var(v).iff(&busy));
        }
        match l.slots[i].pend {
            Some(v) => x.var_exists(v).and(&l.vars.mk_var(v)),
            // It cannot stay pending: it starts at once.
            None => self.start(l, &x, i),
        }
    }

    /// Interrupts member `t`'s main instance, wherever it is.
    fn interrupt_main(&self, l: &Layout, x: &Bdd, t: usize, watchdog: bool) -> Bdd {
        let mut out = x.and_not(&self.interruptible[t]);
        for (at, mv) in &self.interrupts[t] {
            let y = x.and(at);
            if y.is_false() {
                continue;
            }
            let y = match *mv {
                Move::Goto(q) => {
                    let y = assign_pos(l, &y, t, q);
                    match l.slots[t].tout.filter(|_| watchdog) {
                        Some(v) => assign_bit(l, &y, v, true),
                        None => y,
                    }
                }
                Move::End(_) => self.end(l, &y, t),
            };
            out = out.or(&y);
        }
        out
    }

    /// Member `i`'s main instance ends: idle, not timed out, and no longer
    /// waited for.
    fn end(&self, l: &Layout, x: &Bdd, i: usize) -> Bdd {
        let vars = &self.end_vars[i];
        let zero = vars
            .iter()
            .fold(l.vars.mk_true(), |acc, &v| acc.and(&l.vars.mk_not_var(v)));
        x.exists(vars).and(&zero)
    }

    /// Starts member `i`'s pending instance (its wait mask is empty).
    fn start(&self, l: &Layout, x: &Bdd, i: usize) -> Bdd {
        let x = match l.slots[i].pend {
            Some(v) => assign_bit(l, x, v, false),
            None => x.clone(),
        };
        match self.start[i] {
            Some(p) => assign_pos(l, &x, i, p),
            None => self.end(l, &x, i),
        }
    }

    /// Urgent starts until no configuration has a pending instance ready.
    pub(crate) fn closure(&self, l: &Layout, x: Bdd) -> Bdd {
        self.closure_until(l, x, None)
            .unwrap_or_else(|| l.vars.mk_false())
    }

    /// [`Self::closure`], or `None` once `deadline` has passed.
    fn closure_until(
        &self,
        l: &Layout,
        mut x: Bdd,
        deadline: Option<std::time::Instant>,
    ) -> Option<Bdd> {
        loop {
            let mut changed = false;
            for (i, ready) in self.ready.iter().enumerate() {
                if genom_model::limits::out_of_time(deadline) {
                    return None;
                }
                let Some(ready) = ready else { continue };
                let r = x.and(ready);
                if r.is_false() {
                    continue;
                }
                x = x.and_not(ready).or(&self.start(l, &r, i));
                changed = true;
            }
            if !changed {
                return Some(x);
            }
        }
    }
}

/// `x` with member `i` moved to position `q`.
fn assign_pos(l: &Layout, x: &Bdd, i: usize, q: PosId) -> Bdd {
    x.exists(&l.slots[i].pos).and(&l.pos_eq(i, q))
}

fn assign_bit(l: &Layout, x: &Bdd, v: BddVariable, value: bool) -> Bdd {
    x.var_exists(v).and(&l.vars.mk_literal(v, value))
}

/// Member `t`'s pending instance (if any) is interrupted: slot emptied.
fn interrupt_pending(l: &Layout, x: &Bdd, t: usize) -> Bdd {
    let s = &l.slots[t];
    let Some(p) = s.pend else {
        return x.clone();
    };
    let vars: Vec<BddVariable> = std::iter::once(p).chain(s.mask.iter().copied()).collect();
    let zero = vars
        .iter()
        .fold(l.vars.mk_true(), |acc, &v| acc.and(&l.vars.mk_not_var(v)));
    x.exists(&vars).and(&zero)
}

/// Steps 1–3: init done (or the init service), not forbidden, no instance
/// already (unless it stops itself), and the control codel's locks free.
fn request_guard(sys: &System<'_>, l: &Layout, i: usize) -> Bdd {
    let f = &l.facts[i];
    let mut g = if sys.init() == Some(sys.service(i)) {
        l.vars.mk_true()
    } else {
        l.vars.mk_var(l.init_done)
    };
    for &t in &f.forbidders {
        g = g.and_not(&l.has_instance(t));
    }
    if !f.self_stop {
        g = g.and_not(&l.has_instance(i));
    }
    g.and_not(&locked(sys, l, &f.control, None))
}

/// Some running codel of another thread (or of `thread`) conflicts with
/// `uses`: `System::locked_by` as a set.
fn locked(
    sys: &System<'_>,
    l: &Layout,
    uses: &[(StructureId, bool)],
    thread: Option<(usize, ThreadId)>,
) -> Bdd {
    let mut out = l.vars.mk_false();
    for (j, f) in l.facts.iter().enumerate() {
        for &(q, codel) in &f.running {
            let blocks = match thread {
                Some((me, _)) if j == me => false,
                Some((_, t)) if f.thread == Some(t) => true,
                _ => conflict(uses, sys.codel_uses(codel)),
            };
            if blocks {
                out = out.or(&l.pos_eq(j, q));
            }
        }
    }
    out
}

/// Begin and finish steps of member `i`.
fn codel_steps(sys: &System<'_>, l: &Layout, i: usize, list: &mut Vec<Step>) {
    let m = sys.machine_of(i);
    for (p, pos) in m.positions.iter().enumerate() {
        let Ok(pid) = PosId::try_from(p) else {
            continue;
        };
        let at = l.pos_eq(i, pid);
        if let Some(q) = m.begin[p] {
            if let Some(codel) = m.positions[usize::from(q)].codel() {
                list.push(Step {
                    guard: at.and_not(&begin_blocked(sys, l, i, codel)),
                    effect: Effect::SetPos(i, q),
                });
            }
        }
        if pos.codel().is_none() {
            continue;
        }
        for f in &m.finish[p] {
            let effect = match f.effect {
                Move::Goto(q) => Effect::SetPos(i, q),
                Move::End(_) => Effect::End(i),
            };
            list.push(Step {
                guard: at.clone(),
                effect,
            });
        }
    }
}

/// `System::can_begin` negated, as a set.
fn begin_blocked(sys: &System<'_>, l: &Layout, i: usize, codel: CodelId) -> Bdd {
    let thread = l.facts[i].thread.map(|t| (i, t));
    locked(sys, l, sys.codel_uses(codel), thread)
}

/// Member `i`'s interrupt effects, grouped by effect.
fn interrupt_groups(l: &Layout, i: usize, table: &[Option<Move>]) -> Vec<(Bdd, Move)> {
    let mut groups: Vec<(Bdd, Move)> = Vec::new();
    for (p, mv) in table.iter().enumerate() {
        let (Some(mv), Ok(pid)) = (mv, PosId::try_from(p)) else {
            continue;
        };
        let at = l.pos_eq(i, pid);
        match groups.iter_mut().find(|(_, m)| m == mv) {
            Some((g, _)) => *g = g.or(&at),
            None => groups.push((at, *mv)),
        }
    }
    groups
}

/// What member `i`'s ending resets.
fn end_vars(l: &Layout, i: usize) -> Vec<BddVariable> {
    let mut vars = l.slots[i].pos.clone();
    vars.extend(l.slots[i].tout);
    for (k, f) in l.facts.iter().enumerate() {
        for (bit, &t) in f.stops.iter().enumerate() {
            if t == i {
                vars.push(l.slots[k].mask[bit]);
            }
        }
    }
    vars
}

/// Step 7's condition for member `i`: pending, waiting for nothing, idle,
/// and not delayed.
fn ready(l: &Layout, i: usize) -> Option<Bdd> {
    let s = &l.slots[i];
    let mut r = l.vars.mk_var(s.pend?).and(&l.pos_eq(i, IDLE));
    for &v in &s.mask {
        r = r.and(&l.vars.mk_not_var(v));
    }
    for &t in &l.facts[i].delayers {
        r = r.and_not(&l.has_instance(t));
    }
    Some(r)
}
