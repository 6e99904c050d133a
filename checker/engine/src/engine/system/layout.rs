//! The bit layout of an encoded configuration: where each member's
//! position, pending flag, wait mask and watchdog flag lie in the state's
//! words, computed once per system so that encoding and decoding are one
//! shift and mask per field (no field straddles two words), and a member
//! whose fields share a word is encoded with one store.

use genom_model::behaviour::{IDLE, PosId};

use super::{Config, Member, stop_bits};

/// One field: `bits` bits at `shift` in word `word` (`mask == 0` for an
/// absent field, which then reads as zero and writes nothing).
#[derive(Debug, Clone, Copy, Default)]
struct Field {
    word: usize,
    shift: u32,
    mask: u64,
}

impl Field {
    fn read(self, words: &[u64]) -> u64 {
        words
            .get(self.word)
            .map_or(0, |w| (w >> self.shift) & self.mask)
    }
}

/// The fields of one member.
#[derive(Debug, Clone, Copy, Default)]
struct Slots {
    pos: Field,
    /// Pending flag and wait mask (absent unless the member can pend).
    pending: Field,
    wait: Field,
    timed_out: Field,
    /// The word holding all the member's present fields, if one does
    /// (then its fields are or-ed into a register and stored at once).
    word: Option<usize>,
}

impl Slots {
    /// The member's fields, shifted in place and or-ed together (an absent
    /// field has mask 0 and adds nothing).
    fn packed(&self, pos: u64, pending: Option<u64>, timed_out: bool) -> u64 {
        let put = |f: Field, v: u64| (v & f.mask) << f.shift;
        put(self.pos, pos)
            | put(self.pending, u64::from(pending.is_some()))
            | put(self.wait, pending.unwrap_or(0))
            | put(self.timed_out, u64::from(timed_out))
    }

    fn fields(&self) -> [Field; 4] {
        [self.pos, self.pending, self.wait, self.timed_out]
    }
}

/// Where every field of a configuration lies.
#[derive(Debug, Clone, Default)]
pub(super) struct Layout {
    init_done: Field,
    members: Vec<Slots>,
    /// Words per encoded configuration.
    pub(super) width: usize,
}

/// Places fields one after the other, opening a new word when the next
/// one does not fit in the current word.
struct Placer {
    words: usize,
    used: u32,
}

impl Placer {
    fn place(&mut self, bits: u32) -> Field {
        if bits == 0 {
            return Field::default();
        }
        if self.words == 0 || self.used + bits > 64 {
            self.words += 1;
            self.used = 0;
        }
        let field = Field {
            word: self.words - 1,
            shift: self.used,
            mask: if bits >= 64 {
                u64::MAX
            } else {
                (1 << bits) - 1
            },
        };
        self.used += bits;
        field
    }
}

impl Layout {
    /// The layout of `members`' configurations.
    pub(super) fn new(members: &[Member]) -> Self {
        let mut p = Placer { words: 0, used: 0 };
        let init_done = p.place(1);
        let members = members
            .iter()
            .map(|m| {
                let pos = p.place(m.pos_bits);
                let (pending, wait) = if m.can_pend {
                    (p.place(1), p.place(stop_bits(m)))
                } else {
                    (Field::default(), Field::default())
                };
                let timed_out = p.place(u32::from(m.watchdog));
                let mut slots = Slots {
                    pos,
                    pending,
                    wait,
                    timed_out,
                    word: None,
                };
                let mut present = slots.fields().into_iter().filter(|f| f.mask != 0);
                let first = present.next().map_or(0, |f| f.word);
                if present.all(|f| f.word == first) {
                    slots.word = Some(first);
                }
                slots
            })
            .collect();
        Layout {
            init_done,
            members,
            width: p.words.max(1),
        }
    }

    /// Appends the `width` words of `cfg` to `out`.
    pub(super) fn encode(&self, cfg: &Config, out: &mut Vec<u64>) {
        let start = out.len();
        out.resize(start + self.width, 0);
        let words = &mut out[start..];
        let or = |words: &mut [u64], f: Field, v: u64| {
            if let Some(w) = words.get_mut(f.word) {
                *w |= (v & f.mask) << f.shift;
            }
        };
        or(words, self.init_done, u64::from(cfg.init_done));
        for ((slots, &pos), (&pending, &timed_out)) in self
            .members
            .iter()
            .zip(&cfg.main)
            .zip(cfg.pending.iter().zip(&cfg.timed_out))
        {
            match slots.word {
                Some(at) => {
                    if let Some(w) = words.get_mut(at) {
                        *w |= slots.packed(u64::from(pos), pending, timed_out);
                    }
                }
                None => {
                    or(words, slots.pos, u64::from(pos));
                    or(words, slots.pending, u64::from(pending.is_some()));
                    or(words, slots.wait, pending.unwrap_or(0));
                    or(words, slots.timed_out, u64::from(timed_out));
                }
            }
        }
    }

    /// Decodes `words` into `cfg`, reusing its vectors (written in place
    /// when they already have the members' length, as in the explorer).
    pub(super) fn decode(&self, words: &[u64], cfg: &mut Config) {
        cfg.init_done = self.init_done.read(words) == 1;
        let n = self.members.len();
        for v in [cfg.main.len(), cfg.pending.len(), cfg.timed_out.len()] {
            if v != n {
                cfg.main.resize(n, IDLE);
                cfg.pending.resize(n, None);
                cfg.timed_out.resize(n, false);
                break;
            }
        }
        for (slots, (main, (pending, timed_out))) in self.members.iter().zip(
            cfg.main
                .iter_mut()
                .zip(cfg.pending.iter_mut().zip(cfg.timed_out.iter_mut())),
        ) {
            let word = slots.word.and_then(|at| words.get(at)).copied();
            let read = |f: Field| match word {
                Some(w) => (w >> f.shift) & f.mask,
                None => f.read(words),
            };
            *main = PosId::try_from(read(slots.pos)).unwrap_or(IDLE);
            *pending = (read(slots.pending) == 1).then(|| read(slots.wait));
            *timed_out = read(slots.timed_out) == 1;
        }
    }
}
