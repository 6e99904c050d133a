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

/// A member whose fields share one word, ready to pack: the flags
/// already in place (0 when absent).
#[derive(Debug, Clone, Copy)]
struct Pack {
    word: usize,
    pos_mask: u64,
    pos_shift: u32,
    pending: u64,
    wait_mask: u64,
    wait_shift: u32,
    timed_out: u64,
}

impl Pack {
    fn new(word: usize, s: &Slots) -> Self {
        Pack {
            word,
            pos_mask: s.pos.mask,
            pos_shift: s.pos.shift,
            pending: s.pending.mask << s.pending.shift,
            wait_mask: s.wait.mask,
            wait_shift: s.wait.shift,
            timed_out: s.timed_out.mask << s.timed_out.shift,
        }
    }

    /// [`Slots::packed`], without a branch.
    fn packed(&self, pos: u64, pending: Option<u64>, timed_out: bool) -> u64 {
        let wait = pending.map_or(0, |m| {
            self.pending | (m & self.wait_mask) << self.wait_shift
        });
        (pos & self.pos_mask) << self.pos_shift
            | wait
            | self.timed_out & u64::from(timed_out).wrapping_neg()
    }
}

/// Where every field of a configuration lies.
#[derive(Debug, Clone, Default)]
pub(super) struct Layout {
    init_done: Field,
    members: Vec<Slots>,
    /// When every member's fields share a word (the common case): the
    /// members ready to pack, for [`Self::encode`]'s fast path.
    packs: Option<Vec<Pack>>,
    /// Words per encoded configuration.
    pub(super) width: usize,
}

/// [`Layout::encode`] of the members when each lies in one word: the
/// fields of the current word are or-ed into a register, stored when the
/// next member's word differs.
fn encode_packed(packs: &[Pack], cfg: &Config, words: &mut [u64]) {
    let n = packs
        .len()
        .min(cfg.main.len())
        .min(cfg.pending.len())
        .min(cfg.timed_out.len());
    let (packs, main) = (&packs[..n], &cfg.main[..n]);
    let (pending, timed_out) = (&cfg.pending[..n], &cfg.timed_out[..n]);
    let (mut at, mut acc) = (0, 0u64);
    for i in 0..n {
        let p = &packs[i];
        if p.word != at {
            if let Some(w) = words.get_mut(at) {
                *w |= acc;
            }
            (at, acc) = (p.word, 0);
        }
        acc |= p.packed(u64::from(main[i]), pending[i], timed_out[i]);
    }
    if let Some(w) = words.get_mut(at) {
        *w |= acc;
    }
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
            .collect::<Vec<Slots>>();
        let packs = members
            .iter()
            .map(|s| s.word.map(|w| Pack::new(w, s)))
            .collect();
        Layout {
            init_done,
            members,
            packs,
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
        if let Some(packs) = &self.packs {
            encode_packed(packs, cfg, words);
            return;
        }
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

    /// The same layout without the packed fast path (for tests: both ways
    /// must encode alike); whether this one has it.
    #[cfg(test)]
    pub(super) fn field_by_field(&self) -> (Layout, bool) {
        let plain = Layout {
            packs: None,
            ..self.clone()
        };
        (plain, self.packs.is_some())
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
