//! A state of the GenoM3 engine and its packed form. Instances of one
//! activity are anonymous and kept sorted (a multiset), so that states
//! differing only by which slot holds which instance are one state.

use super::machine::Machine;
use crate::kernel::store::bits::{BitReader, BitWriter, bits_for, words_for};

/// The life cycle of the component.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Phase {
    /// Tasks are spawned one after the other; no request is handled until
    /// every task's permanent activity ran its first codel.
    Boot,
    /// Requests are handled.
    Run,
    /// `kill` succeeded: every instance was interrupted; waiting for them
    /// to end.
    Drain,
    /// Running the stop path of the permanent activity of this task
    /// (tasks are stopped in reverse declaration order).
    PermStop(u8),
    /// The component stopped (terminal).
    Stopped,
    /// A permanent activity failed while the component started (terminal).
    Failed,
}

impl Phase {
    fn code(self) -> u64 {
        match self {
            Phase::Boot => 0,
            Phase::Run => 1,
            Phase::Drain => 2,
            Phase::Stopped => 3,
            Phase::Failed => 4,
            Phase::PermStop(t) => 5 + u64::from(t),
        }
    }

    fn from_code(c: u64) -> Phase {
        match c {
            0 => Phase::Boot,
            1 => Phase::Run,
            2 => Phase::Drain,
            3 => Phase::Stopped,
            4 => Phase::Failed,
            t => Phase::PermStop(u8::try_from(t - 5).unwrap_or(u8::MAX)),
        }
    }
}

/// The status of an instance.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Status {
    /// Accepted, waiting for interrupted instances to end (it delays).
    Delayed,
    /// Accepted, starts at its task's next sweep.
    Ready,
    /// Running its state machine.
    Run,
    /// Interrupted: on its stop path (not interrupted again).
    Stop,
}

impl Status {
    /// Its code in a packed slot (1–4; 0 is an empty slot).
    fn code(self) -> u16 {
        match self {
            Status::Delayed => 1,
            Status::Ready => 2,
            Status::Run => 3,
            Status::Stop => 4,
        }
    }

    /// The status of a code (`None`: an empty slot).
    fn from_code(c: u16) -> Option<Status> {
        match c {
            1 => Some(Status::Delayed),
            2 => Some(Status::Ready),
            3 => Some(Status::Run),
            4 => Some(Status::Stop),
            _ => None,
        }
    }
}

/// Timing marks of an instance (always 0 in the untimed engine).
pub mod mark {
    /// It runs a codel in its task's current sweep and has not yet.
    pub const DUE: u8 = 1;
    /// Its last transition was `pause::`: it waits for a wake-up.
    pub const PAUSED: u8 = 2;
    /// Its codel is running now.
    pub const BUSY: u8 = 4;
    /// Interrupted while its codel runs or is due in this sweep: it goes
    /// to `stop` (or ends) after that codel.
    pub const FLAGGED: u8 = 8;
    /// Its task holds a ticket in GenoM3's resource FIFO for this codel
    /// (8.3): the task is committed to it and waits for its turn.
    pub const TICKET: u8 = 16;
}

/// One instance: its status, the state whose codel runs next, and its
/// timing [`mark`]s.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Inst {
    /// Its status.
    pub status: Status,
    /// Its state (meaningless before it starts).
    pub state: u8,
    /// Timing marks (bits of [`mark`]).
    pub mark: u8,
}

impl Inst {
    /// An instance without marks.
    pub fn new(status: Status, state: u8) -> Inst {
        Inst {
            status,
            state,
            mark: 0,
        }
    }

    /// Whether mark `m` is set.
    pub fn has(self, m: u8) -> bool {
        self.mark & m != 0
    }

    /// The packed form; 0 is an empty slot.
    pub fn pack(self) -> u16 {
        self.status.code() | (u16::from(self.state) << 3) | (u16::from(self.mark & 0x1f) << 11)
    }

    /// The instance of a packed slot (`None` when empty).
    pub fn unpack(v: u16) -> Option<Inst> {
        Some(Inst {
            status: Status::from_code(v & 7)?,
            state: ((v >> 3) & 0xff) as u8,
            mark: (v >> 11) as u8,
        })
    }

    /// Whether it runs codels (started, not ended).
    pub fn running(self) -> bool {
        matches!(self.status, Status::Run | Status::Stop)
    }
}

/// A state of the GenoM3 engine.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct G3State {
    /// The component's life cycle.
    pub phase: Phase,
    /// Tasks spawned so far (in declaration order; boot only).
    pub booted: u8,
    /// Per service: it completed successfully once (`after`/`before`).
    pub done: Vec<u64>,
    /// Per task: its permanent activity (`None`: none or ended).
    pub perm: Vec<Option<Inst>>,
    /// Per activity: its instances, sorted, at most `max_instances`.
    pub inst: Vec<Vec<Inst>>,
}

impl G3State {
    /// Whether service `s` (by index) completed successfully once.
    pub fn is_done(&self, s: usize) -> bool {
        self.done[s / 64] >> (s % 64) & 1 == 1
    }

    /// Records that service `s` completed successfully.
    pub fn set_done(&mut self, s: usize) {
        self.done[s / 64] |= 1 << (s % 64);
    }

    /// Instances of task `t`'s activities plus its permanent one.
    pub fn slots_used(&self, t: usize, task_of: impl Fn(usize) -> usize) -> usize {
        let perm = usize::from(self.perm[t].is_some());
        perm + self
            .inst
            .iter()
            .enumerate()
            .filter(|(a, _)| task_of(*a) == t)
            .map(|(_, v)| v.len())
            .sum::<usize>()
    }
}

/// How a [`G3State`] is packed into words ([`bits`]): the phase, the boot
/// counter, the kept completion flags (those some step reads), then per
/// permanent activity and per activity slot its instance: status, state
/// (as many bits as its state machine needs) and marks.
#[derive(Debug, Clone)]
pub struct Layout {
    tasks: usize,
    slots: usize,
    /// Bits of a state index: per task's permanent activity, then per
    /// activity.
    state_bits: Vec<u32>,
    done_words: usize,
    /// The completion flags kept, by service index (the others are always
    /// clear).
    kept: Vec<usize>,
    /// Bits of an instance's [`mark`]s: [`MARK_BITS`] in the timed engine,
    /// none in the untimed one, where they are always 0.
    mark_bits: u32,
}

/// Bits of an instance's status (0: empty slot) and of its marks.
const STATUS_BITS: u32 = 3;
const MARK_BITS: u32 = 5;

impl Layout {
    /// The layout of states of `m` with `slots` slots per activity and
    /// `done_words` words of completion flags, of which only `tracked`
    /// are kept.
    pub fn new(m: &Machine<'_>, slots: usize, done_words: usize, tracked: &[u64]) -> Self {
        let states = |n: usize| bits_for(n as u64);
        let state_bits = m
            .tasks
            .iter()
            .map(|t| states(t.perm.as_ref().map_or(0, |f| f.states.len())))
            .chain(m.activities.iter().map(|a| states(a.fsm.states.len())))
            .collect();
        let kept = (0..tracked.len() * 64)
            .filter(|&s| tracked[s / 64] >> (s % 64) & 1 == 1)
            .collect();
        Layout {
            tasks: m.tasks.len(),
            slots,
            state_bits,
            done_words,
            kept,
            mark_bits: 0,
        }
    }

    /// The same layout with room for the timed engine's [`mark`]s.
    pub fn with_marks(self) -> Self {
        Layout {
            mark_bits: MARK_BITS,
            ..self
        }
    }

    fn phase_bits(&self) -> u32 {
        bits_for(5 + self.tasks as u64 + 1)
    }

    fn booted_bits(&self) -> u32 {
        bits_for(self.tasks as u64 + 1)
    }

    /// Per slot, its state bits: the permanent activities, then `slots`
    /// per activity.
    fn slot_bits(&self) -> impl Iterator<Item = u32> + '_ {
        let (perms, acts) = self.state_bits.split_at(self.tasks);
        perms.iter().copied().chain(
            acts.iter()
                .flat_map(|&b| std::iter::repeat_n(b, self.slots)),
        )
    }

    /// Words of a packed state.
    pub fn width(&self) -> usize {
        words_for(self.bits())
    }

    /// Bits of a packed state (those of its last word past them are 0).
    pub fn bits(&self) -> usize {
        let slots: usize = self
            .slot_bits()
            .map(|b| (STATUS_BITS + b + self.mark_bits) as usize)
            .sum();
        let head = (self.phase_bits() + self.booted_bits()) as usize;
        head + self.kept.len() + slots
    }

    /// Packs `s`.
    pub fn encode(&self, s: &G3State, out: &mut Vec<u64>) {
        let mut w = BitWriter::new(out);
        self.write(s, &mut w);
        w.finish();
    }

    /// Packs `s` into `w`, where more fields may follow.
    pub fn write(&self, s: &G3State, w: &mut BitWriter<'_>) {
        w.put(s.phase.code(), self.phase_bits());
        w.put(u64::from(s.booted), self.booted_bits());
        for &k in &self.kept {
            w.flag(s.is_done(k));
        }
        let insts = s.perm.iter().copied().chain(
            s.inst
                .iter()
                .flat_map(|v| (0..self.slots).map(move |i| v.get(i).copied())),
        );
        for (i, b) in insts.zip(self.slot_bits()) {
            w.put(i.map_or(0, |i| u64::from(i.status.code())), STATUS_BITS);
            w.put(i.map_or(0, |i| u64::from(i.state)), b);
            w.put(i.map_or(0, |i| u64::from(i.mark & 0x1f)), self.mark_bits);
        }
    }

    /// Unpacks a state [`Layout::encode`] packed.
    pub fn decode(&self, words: &[u64]) -> G3State {
        self.read(&mut BitReader::new(words))
    }

    /// Unpacks a state [`Layout::write`] wrote, from `r`.
    pub fn read(&self, r: &mut BitReader<'_>) -> G3State {
        let phase = Phase::from_code(r.take(self.phase_bits()));
        let booted = u8::try_from(r.take(self.booted_bits())).unwrap_or(u8::MAX);
        let mut done = vec![0; self.done_words];
        for &k in &self.kept {
            if r.flag() {
                done[k / 64] |= 1 << (k % 64);
            }
        }
        let mut insts = self.slot_bits().map(|b| {
            let status = r.take(STATUS_BITS);
            let state = (r.take(b) & 0xff) as u8;
            let mark = r.take(self.mark_bits) as u8;
            let status = match status {
                1 => Status::Delayed,
                2 => Status::Ready,
                3 => Status::Run,
                4 => Status::Stop,
                _ => return None,
            };
            Some(Inst {
                status,
                state,
                mark,
            })
        });
        let perm = insts.by_ref().take(self.tasks).collect();
        let acts = self.state_bits.len() - self.tasks;
        let inst = (0..acts)
            .map(|_| insts.by_ref().take(self.slots).flatten().collect())
            .collect();
        G3State {
            phase,
            booted,
            done,
            perm,
            inst,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packing_round_trips() {
        let s = G3State {
            phase: Phase::PermStop(1),
            booted: 2,
            done: vec![0b101],
            perm: vec![
                None,
                Some(Inst {
                    status: Status::Run,
                    state: 7,
                    mark: mark::BUSY | mark::FLAGGED,
                }),
            ],
            inst: vec![
                vec![Inst::new(Status::Delayed, 0), Inst::new(Status::Stop, 200)],
                vec![],
                vec![Inst::new(Status::Ready, 1)],
            ],
        };
        let layout = Layout {
            tasks: 2,
            slots: 2,
            state_bits: vec![1, 3, 8, 1, 1],
            done_words: 1,
            kept: vec![0, 1, 2],
            mark_bits: MARK_BITS,
        };
        let mut w = Vec::new();
        layout.encode(&s, &mut w);
        assert_eq!(w.len(), layout.width());
        assert_eq!(
            layout.width(),
            2,
            "4 + 2 + 3 flags + 8 slots of 9 to 16 bits"
        );
        assert_eq!(layout.decode(&w), s);
        // A completion flag no step reads is not kept.
        let narrow = Layout {
            kept: vec![0],
            ..layout
        };
        let mut w = Vec::new();
        narrow.encode(&s, &mut w);
        assert_eq!(narrow.decode(&w).done, vec![0b001]);
        // Without marks (the untimed engine's states, whose marks are 0),
        // 8 slots take 5 bits less each, and the state reads back.
        let plain = Layout {
            mark_bits: 0,
            ..narrow
        };
        let mut unmarked = s.clone();
        unmarked.perm[1] = unmarked.perm[1].map(|i| Inst { mark: 0, ..i });
        let mut w = Vec::new();
        plain.encode(&unmarked, &mut w);
        assert_eq!(plain.decode(&w).perm, unmarked.perm);
        assert_eq!(plain.decode(&w).inst, unmarked.inst);
        assert_eq!(plain.bits() + 8 * 5, plain.clone().with_marks().bits());
    }
}
