//! The transitions of the GenoM3 engine (the rules of
//! `docs/genom3-semantics.md`, untimed): requests and calls handled by the
//! control thread, instance starts, one codel of an instance or of a
//! task's permanent activity, `abort_activity`, and the `kill` shutdown.
//! After every transition [`Engine::settle`] applies the steps that follow
//! at once: the boot order of tasks, pending interrupters re-examined when
//! an instance ended, and the shutdown sequence.

use genom_model::component::Idx;

use super::machine::{ControlKind, Machine, Owner, Target};
use super::state::{G3State, Inst, Layout, Phase, Status, mark};
use crate::kernel::explore::Model;

/// A transition.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum G3Action {
    /// A request for activity `a` is accepted (validate succeeded).
    Accept(u16),
    /// Function or attribute `k` runs and succeeds.
    Call(u16),
    /// `abort_activity` interrupts an instance of activity `a` (packed).
    Abort(u16, u16),
    /// An accepted instance of activity `a` (packed) starts and runs its
    /// `start` codel with outcome `o` in the same step (GenoM3's sweep
    /// starts an instance and runs its first codel at once: no
    /// interruption comes in between); `o` is 0 without a `start` codel.
    Start(u16, u16, u8),
    /// An instance of activity `a` (packed) runs its codel, with outcome
    /// `o` (a yield index; one past the yields: an exception).
    Codel(u16, u16, u8),
    /// Task `t`'s permanent activity runs its codel, with outcome `o`.
    Perm(u8, u8),
}

/// The GenoM3 engine: the machine plus the packing parameters.
#[derive(Debug)]
pub struct Engine<'a> {
    /// The component.
    pub m: Machine<'a>,
    done_words: usize,
    /// How a state is packed.
    layout: Layout,
    /// Per activity: requested in this exploration.
    acts: Vec<bool>,
    /// Per control service: requested in this exploration.
    pub(crate) ctls: Vec<bool>,
    /// Per task: whether its permanent activity runs.
    perms: Vec<bool>,
    /// The services whose completion some step reads (`after`/`before`
    /// name them), as bits: the only completion flags kept in a state.
    /// The others are history no step reads; keeping them multiplied the
    /// states by the subsets of services completed so far.
    tracked: Vec<u64>,
    /// The completions of every service seen in the steps fired so far
    /// (tracked or not): the facts `completed` reads.
    seen_done: std::cell::RefCell<Vec<u64>>,
}

impl<'a> Engine<'a> {
    /// The engine of a whole machine.
    pub fn new(m: Machine<'a>) -> Self {
        let (acts, ctls) = (vec![true; m.activities.len()], vec![true; m.controls.len()]);
        Self::part(m, acts, ctls, true)
    }

    /// The engine of a part of a machine: only the activities and control
    /// services marked are requested; the permanent activities run if
    /// `perms`. The others stay idle (their slots empty).
    pub fn part(m: Machine<'a>, acts: Vec<bool>, ctls: Vec<bool>, perms: bool) -> Self {
        let perms = vec![perms; m.tasks.len()];
        Self::part_tasks(m, acts, ctls, perms)
    }

    /// [`Engine::part`] with the permanent activities of the tasks marked
    /// in `perms` only.
    pub fn part_tasks(m: Machine<'a>, acts: Vec<bool>, ctls: Vec<bool>, perms: Vec<bool>) -> Self {
        let done_words = m.c.services.len().div_ceil(64).max(1);
        let slots = m.slots();
        let tracked = m.completions_read();
        let layout = Layout::new(&m, slots, done_words, &tracked);
        Engine {
            m,
            done_words,
            layout,
            acts,
            ctls,
            perms,
            tracked,
            seen_done: std::cell::RefCell::new(vec![0; done_words]),
        }
    }

    /// The state before anything ran.
    pub fn initial(&self) -> G3State {
        let mut s = G3State {
            phase: Phase::Boot,
            booted: 0,
            done: vec![0; self.done_words],
            perm: self
                .m
                .tasks
                .iter()
                .enumerate()
                .map(|(k, t)| {
                    if !self.perms[k] {
                        return None;
                    }
                    let start = t.perm.as_ref()?.start?;
                    Some(Inst::new(Status::Run, start))
                })
                .collect(),
            inst: vec![Vec::new(); self.m.activities.len()],
        };
        self.settle(&mut s, false);
        self.forget_untracked(&mut s);
        s
    }

    /// Packs `s` into `w`, where the timed engine's fields follow.
    pub(crate) fn write(&self, s: &G3State, w: &mut crate::kernel::store::bits::BitWriter<'_>) {
        self.layout.write(s, w);
    }

    /// Unpacks a state [`Engine::write`] wrote.
    pub(crate) fn read(&self, r: &mut crate::kernel::store::bits::BitReader<'_>) -> G3State {
        self.layout.read(r)
    }

    /// The engine with room in its states for the timed engine's marks.
    pub(crate) fn with_marks(mut self) -> Self {
        self.layout = self.layout.with_marks();
        self
    }

    /// Records the completions of `n` as seen, then keeps only the tracked
    /// ones in it.
    fn forget_untracked(&self, n: &mut G3State) {
        let mut seen = self.seen_done.borrow_mut();
        for ((d, t), w) in n.done.iter_mut().zip(&self.tracked).zip(seen.iter_mut()) {
            *w |= *d;
            *d &= t;
        }
    }

    /// The services some fired step completed successfully, by index bits.
    pub fn completions_seen(&self) -> Vec<u64> {
        self.seen_done.borrow().clone()
    }

    /// Whether `after`/`before` let service `sid` be accepted.
    pub fn admissible(&self, s: &G3State, sid: genom_model::component::ServiceId) -> bool {
        let done = |x: &genom_model::component::ServiceId| s.is_done(x.index());
        self.m.after.get(&sid).is_none_or(|v| v.iter().all(done))
            && self.m.before.get(&sid).is_none_or(|v| !v.iter().any(done))
    }

    /// Interrupts activity `a`'s instances (`spare`: not the not yet
    /// started ones, for a pending interrupter re-examining its own
    /// activity); see [`interrupted`]. Returns whether one is stopping.
    fn flag(&self, s: &mut G3State, a: usize, spare: bool) -> bool {
        let stop = self.m.activities[a].fsm.stop;
        let old = std::mem::take(&mut s.inst[a]);
        let mut kept = Vec::with_capacity(old.len());
        for i in old {
            if spare && i.status <= Status::Ready {
                kept.push(i);
            } else {
                kept.extend(interrupted(i, stop));
            }
        }
        kept.sort_unstable();
        let stopping = kept.iter().any(|&i| stopping(i));
        s.inst[a] = kept;
        stopping
    }

    /// Interrupts the targets of activity `a` (for a new instance of it, or,
    /// `pending`, for one re-examined while it waits: then its own activity's
    /// instances not started yet are spared); whether it must wait for one
    /// of them to end.
    pub(crate) fn interrupt_for(&self, s: &mut G3State, a: usize, pending: bool) -> bool {
        let mut delay = false;
        for &t in &self.m.activities[a].interrupts {
            delay |= self.flag(s, t, pending && t == a);
        }
        delay
    }

    /// Ends one instance of `a` (packed `v`), successfully or not.
    pub(crate) fn end(&self, s: &mut G3State, a: usize, v: u16, success: bool) {
        remove(&mut s.inst[a], v);
        if success {
            s.set_done(self.m.activities[a].service.index());
        }
    }

    /// The steps that follow a transition at once (see the module doc).
    /// `ended`: an instance ended (pending interrupters are re-examined
    /// then, as GenoM3's control thread does on every end).
    pub fn settle(&self, s: &mut G3State, ended: bool) {
        if s.phase == Phase::Boot {
            let n = self.m.tasks.len();
            while usize::from(s.booted) < n && s.perm[usize::from(s.booted)].is_none() {
                s.booted += 1;
            }
            if usize::from(s.booted) >= n {
                s.phase = Phase::Run;
            }
        }
        let mut ended = ended;
        while ended {
            let before = total(s);
            let mut changed = false;
            for a in 0..s.inst.len() {
                let pending = |s: &G3State| s.inst[a].iter().any(|i| i.status <= Status::Ready);
                if !pending(s) || self.m.activities[a].interrupts.is_empty() {
                    continue;
                }
                let old = s.inst[a].clone();
                let delay = self.interrupt_for(s, a, true);
                if !delay {
                    for i in s.inst[a].iter_mut().filter(|i| i.status == Status::Delayed) {
                        i.status = Status::Ready;
                    }
                    s.inst[a].sort_unstable();
                }
                changed |= s.inst[a] != old;
            }
            ended = changed && total(s) < before;
        }
        self.shutdown_sequence(s);
    }

    /// `kill`: once no instance is left, each task's permanent activity
    /// runs its stop path, last task first; then the component stops.
    fn shutdown_sequence(&self, s: &mut G3State) {
        if s.phase == Phase::Drain && s.inst.iter().all(Vec::is_empty) {
            s.phase = Phase::PermStop(u8::try_from(self.m.tasks.len()).unwrap_or(u8::MAX));
            s.perm.iter_mut().for_each(|p| *p = None);
            self.next_perm_stop(s, self.m.tasks.len());
        }
        if let Phase::PermStop(t) = s.phase {
            if s.perm[usize::from(t)].is_none() {
                self.next_perm_stop(s, usize::from(t));
            }
        }
    }

    /// Puts the permanent activity of the last task before `below` that
    /// has a stop codel in its stop state (`Stopped` when none is left).
    fn next_perm_stop(&self, s: &mut G3State, below: usize) {
        for t in (0..below).rev().filter(|&t| self.perms[t]) {
            if let Some(stop) = self.m.tasks[t].perm.as_ref().and_then(|f| f.stop) {
                s.perm[t] = Some(Inst::new(Status::Stop, stop));
                s.phase = Phase::PermStop(t as u8);
                return;
            }
        }
        s.phase = Phase::Stopped;
    }

    pub(crate) fn requests(&self, s: &G3State, out: &mut Vec<G3Action>) {
        for (a, act) in self.m.activities.iter().enumerate() {
            if !self.acts[a] || !self.admissible(s, act.service) {
                continue;
            }
            let used = s.slots_used(act.task, |x| self.m.activities[x].task);
            if used >= self.m.pool {
                continue;
            }
            if s.inst[a].len() >= self.m.instance_bound(a) {
                continue;
            }
            out.push(G3Action::Accept(a as u16));
        }
        for (k, ctl) in self.m.controls.iter().enumerate() {
            if !self.ctls[k] || !self.admissible(s, ctl.service) {
                continue;
            }
            match ctl.kind {
                ControlKind::Abort => {
                    for (a, v) in distinct(s) {
                        if matches!(Inst::unpack(v), Some(i) if i.status != Status::Stop) {
                            out.push(G3Action::Abort(a, v));
                        }
                    }
                }
                _ => out.push(G3Action::Call(k as u16)),
            }
        }
    }

    fn codels(&self, s: &G3State, out: &mut Vec<G3Action>) {
        for (a, v) in distinct(s) {
            let Some(i) = Inst::unpack(v) else { continue };
            if i.status == Status::Ready {
                let n = match self.m.activities[usize::from(a)].fsm.start {
                    Some(st) => self.outcomes(Owner::Activity(usize::from(a)), st),
                    None => 1,
                };
                out.extend((0..n).map(|o| G3Action::Start(a, v, o)));
            } else if i.running() {
                let n = self.outcomes(Owner::Activity(usize::from(a)), i.state);
                out.extend((0..n).map(|o| G3Action::Codel(a, v, o)));
            }
        }
        for (t, p) in s.perm.iter().enumerate() {
            let Some(i) = p else { continue };
            if !self.perms[t] {
                continue;
            }
            if s.phase == Phase::Boot && t > usize::from(s.booted) {
                continue;
            }
            let n = self.outcomes(Owner::Task(t), i.state);
            out.extend((0..n).map(|o| G3Action::Perm(t as u8, o)));
        }
    }

    /// Outcomes of the codel of `state`: its yields, then an exception.
    pub fn outcomes(&self, owner: Owner, state: u8) -> u8 {
        let n = self.m.fsm(owner).states[usize::from(state)].yields.len();
        u8::try_from(n + 1).unwrap_or(u8::MAX)
    }

    /// Applies an accepted request or a successful call.
    pub(crate) fn control(&self, s: &mut G3State, action: G3Action) {
        match action {
            G3Action::Accept(a) => {
                let a = usize::from(a);
                let delay = self.interrupt_for(s, a, false);
                let status = if delay {
                    Status::Delayed
                } else {
                    Status::Ready
                };
                insert(&mut s.inst[a], Inst::new(status, 0));
            }
            G3Action::Call(k) => {
                let ctl = &self.m.controls[usize::from(k)];
                s.set_done(ctl.service.index());
                for &t in &ctl.interrupts {
                    self.flag(s, t, false);
                }
                if ctl.kind == ControlKind::Kill {
                    s.phase = Phase::Drain;
                }
            }
            G3Action::Abort(a, v) => self.abort(s, usize::from(a), v),
            _ => {}
        }
    }

    /// `abort_activity` on one instance: as `flag`, for it alone.
    fn abort(&self, s: &mut G3State, a: usize, v: u16) {
        if let Some(k) = self
            .m
            .controls
            .iter()
            .find(|k| k.kind == ControlKind::Abort)
        {
            s.set_done(k.service.index());
        }
        let Some(i) = Inst::unpack(v) else { return };
        remove(&mut s.inst[a], v);
        if let Some(kept) = interrupted(i, self.m.activities[a].fsm.stop) {
            insert(&mut s.inst[a], kept);
        }
    }

    /// Runs the codel of an instance of `a` with outcome `o`.
    pub(crate) fn codel(&self, s: &mut G3State, a: usize, v: u16, o: u8) {
        let Some(i) = Inst::unpack(v) else { return };
        let fsm = &self.m.activities[a].fsm;
        match fsm.states[usize::from(i.state)].yields.get(usize::from(o)) {
            Some(Target::State { state, .. }) => {
                remove(&mut s.inst[a], v);
                insert(&mut s.inst[a], Inst { state: *state, ..i });
            }
            Some(Target::Ether) => self.end(s, a, v, true),
            None => self.end(s, a, v, false),
        }
    }

    /// Starts a ready instance of `a` (packed `v`) and runs its `start`
    /// codel with outcome `o`; without a `start` codel it completes.
    pub(crate) fn start(&self, s: &mut G3State, a: usize, v: u16, o: u8) {
        remove(&mut s.inst[a], v);
        match self.m.activities[a].fsm.start {
            Some(state) => {
                let i = Inst::new(Status::Run, state);
                insert(&mut s.inst[a], i);
                self.codel(s, a, i.pack(), o);
            }
            None => s.set_done(self.m.activities[a].service.index()),
        }
    }

    /// Runs the permanent codel of task `t` with outcome `o`.
    pub(crate) fn perm(&self, s: &mut G3State, t: usize, o: u8) {
        let Some(i) = s.perm[t] else { return };
        let fsm = self.m.fsm(Owner::Task(t));
        let booting = s.phase == Phase::Boot && t == usize::from(s.booted);
        match fsm.states[usize::from(i.state)].yields.get(usize::from(o)) {
            Some(Target::State { state, .. }) => {
                s.perm[t] = Some(Inst { state: *state, ..i });
            }
            Some(Target::Ether) => s.perm[t] = None,
            None if booting => s.phase = Phase::Failed,
            None => s.perm[t] = None,
        }
        if booting {
            s.booted += 1;
        }
    }
}

impl Model for Engine<'_> {
    type State = G3State;
    type Action = G3Action;
    type Zone = ();

    /// Paths are found again from the parents (no reduction; a step read
    /// again records only completions already read: the analysis reads
    /// them before it asks for paths).
    const KEEPS_ACTIONS: bool = false;

    fn width(&self) -> usize {
        self.layout.width()
    }

    fn bits(&self) -> usize {
        self.layout.bits()
    }

    fn init_states(&self) -> Vec<G3State> {
        vec![self.initial()]
    }

    fn actions(&self, s: &G3State, out: &mut Vec<G3Action>) {
        match s.phase {
            Phase::Stopped | Phase::Failed => {}
            Phase::Run => {
                self.requests(s, out);
                self.codels(s, out);
            }
            Phase::Boot | Phase::Drain | Phase::PermStop(_) => self.codels(s, out),
        }
    }

    fn next_state(&self, s: &G3State, action: G3Action) -> Option<G3State> {
        let mut n = s.clone();
        match action {
            G3Action::Start(a, v, o) => self.start(&mut n, usize::from(a), v, o),
            G3Action::Codel(a, v, o) => self.codel(&mut n, usize::from(a), v, o),
            G3Action::Perm(t, o) => self.perm(&mut n, usize::from(t), o),
            _ => self.control(&mut n, action),
        }
        let added = usize::from(matches!(action, G3Action::Accept(_)));
        let ended = total(&n) < total(s) + added;
        self.settle(&mut n, ended);
        self.forget_untracked(&mut n);
        (n != *s).then_some(n)
    }

    fn encode(&self, s: &G3State, out: &mut Vec<u64>) {
        self.layout.encode(s, out);
    }

    fn decode(&self, w: &[u64], (): &()) -> G3State {
        self.layout.decode(w)
    }

    fn zone(&self, _: &G3State) {}
}

/// What interrupting instance `i` leaves (`stop`: its activity's stop
/// state): not started, nothing (it ends); running, its stop path, or
/// nothing without one; stopping, itself. A running instance whose codel
/// runs or is due in the current sweep (timed engine) is only flagged: it
/// goes to `stop` after that codel.
pub(crate) fn interrupted(i: Inst, stop: Option<u8>) -> Option<Inst> {
    match i.status {
        Status::Delayed | Status::Ready => None,
        Status::Run if i.has(mark::BUSY | mark::DUE) => Some(Inst {
            mark: i.mark | mark::FLAGGED,
            ..i
        }),
        Status::Run => stop.map(|state| Inst::new(Status::Stop, state)),
        Status::Stop => Some(i),
    }
}

/// Whether an instance is on its way to end by an interruption.
fn stopping(i: Inst) -> bool {
    i.status == Status::Stop || i.has(mark::FLAGGED)
}

/// Every distinct (activity, packed instance) of a state.
pub(crate) fn distinct(s: &G3State) -> Vec<(u16, u16)> {
    let mut out = Vec::new();
    for (a, v) in s.inst.iter().enumerate() {
        let mut last = None;
        for i in v {
            let p = i.pack();
            if last != Some(p) {
                out.push((a as u16, p));
                last = Some(p);
            }
        }
    }
    out
}

/// Instances in a state.
pub(crate) fn total(s: &G3State) -> usize {
    s.inst.iter().map(Vec::len).sum()
}

pub(crate) fn remove(v: &mut Vec<Inst>, packed: u16) {
    if let Some(pos) = v.iter().position(|i| i.pack() == packed) {
        v.remove(pos);
    }
}

pub(crate) fn insert(v: &mut Vec<Inst>, i: Inst) {
    let pos = v.partition_point(|x| *x < i);
    v.insert(pos, i);
}
