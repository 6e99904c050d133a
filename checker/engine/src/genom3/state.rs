//! A state of the GenoM3 engine and its packed form. Instances of one
//! activity are anonymous and kept sorted (a multiset), so that states
//! differing only by which slot holds which instance are one state.

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
        let s = match self.status {
            Status::Delayed => 1,
            Status::Ready => 2,
            Status::Run => 3,
            Status::Stop => 4,
        };
        s | (u16::from(self.state) << 3) | (u16::from(self.mark & 0x1f) << 11)
    }

    /// The instance of a packed slot (`None` when empty).
    pub fn unpack(v: u16) -> Option<Inst> {
        let status = match v & 7 {
            1 => Status::Delayed,
            2 => Status::Ready,
            3 => Status::Run,
            4 => Status::Stop,
            _ => return None,
        };
        Some(Inst {
            status,
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

    /// Packs into words: phase and boot, `done`, then 16-bit slots (the
    /// permanent activities, then `max` slots per activity).
    pub fn encode(&self, max: usize, out: &mut Vec<u64>) {
        out.push(self.phase.code() | u64::from(self.booted) << 16);
        out.extend(&self.done);
        let mut halves = self.perm.iter().map(|p| p.map_or(0, Inst::pack)).chain(
            self.inst
                .iter()
                .flat_map(|v| (0..max).map(move |i| v.get(i).map_or(0, |x| x.pack()))),
        );
        loop {
            let mut word = 0u64;
            let mut any = false;
            for k in 0..4 {
                if let Some(h) = halves.next() {
                    word |= u64::from(h) << (16 * k);
                    any = true;
                }
            }
            if !any {
                break;
            }
            out.push(word);
        }
    }

    /// The words of [`G3State::encode`] for `tasks` tasks, `acts`
    /// activities and `done_words` words of flags.
    pub fn decode(w: &[u64], tasks: usize, acts: usize, max: usize, done_words: usize) -> G3State {
        let head = w.first().copied().unwrap_or(0);
        let done = w.get(1..1 + done_words).unwrap_or(&[]).to_vec();
        let half = |i: usize| -> u16 {
            let word = w.get(1 + done_words + i / 4).copied().unwrap_or(0);
            (word >> (16 * (i % 4)) & 0xffff) as u16
        };
        let perm = (0..tasks).map(|t| Inst::unpack(half(t))).collect();
        let inst = (0..acts)
            .map(|a| {
                (0..max)
                    .filter_map(|i| Inst::unpack(half(tasks + a * max + i)))
                    .collect()
            })
            .collect();
        G3State {
            phase: Phase::from_code(head & 0xffff),
            booted: ((head >> 16) & 0xff) as u8,
            done,
            perm,
            inst,
        }
    }

    /// Words of the packed form.
    pub fn width(tasks: usize, acts: usize, max: usize, done_words: usize) -> usize {
        1 + done_words + (tasks + acts * max).div_ceil(4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packing_round_trips() {
        let s = G3State {
            phase: Phase::PermStop(3),
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
        let mut w = Vec::new();
        s.encode(2, &mut w);
        assert_eq!(w.len(), G3State::width(2, 3, 2, 1));
        assert_eq!(G3State::decode(&w, 2, 3, 2, 1), s);
    }
}
