//! The hash table of a store: open addressing with linear probing over
//! `u32` slots. A slot holds a state's id and, in the bits the id does not
//! need (those above the capacity's bit length), a tag taken from the
//! state's hash, so that a probe passing over other states almost never
//! reads their words: a lookup costs one cache miss in the table, plus one
//! in the arena when the state is there.

use super::StateId;

/// Grow when the table is this full (`LOAD_NUM / LOAD_DEN`).
const LOAD_NUM: usize = 4;
const LOAD_DEN: usize = 5;

/// Smallest capacity.
const MIN_CAPACITY: usize = 16;

/// The hash of a state's words: a folded 64×64→128-bit multiply per word
/// (all 64 bits of the result depend on every bit of the words).
pub(super) fn hash(words: &[u64]) -> u64 {
    let mut h: u64 = 0x243F_6A88_85A3_08D3;
    for &w in words {
        h = fold_mul(h ^ w, 0x9E37_79B9_7F4A_7C15);
    }
    h
}

fn fold_mul(a: u64, b: u64) -> u64 {
    let p = u128::from(a) * u128::from(b);
    #[allow(clippy::cast_possible_truncation)]
    let (lo, hi) = (p as u64, (p >> 64) as u64);
    lo ^ hi
}

/// Where a lookup ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Probe {
    /// The state is stored, its id in that slot.
    Found(usize, StateId),
    /// The state is not stored; this empty slot is where it goes.
    Vacant(usize),
}

/// Slots of state ids with hash tags.
#[derive(Debug)]
pub(super) struct Table {
    slots: Vec<u32>,
    /// Low bits of a slot holding `id + 1` (0: empty); the others hold
    /// the tag. Every id of the store (not only those in the table: a
    /// chained store keeps one id per same-words chain) fits, because the
    /// table grows with the store ([`Self::full`]).
    id_bits: u32,
}

impl Table {
    /// An empty table.
    pub(super) fn new() -> Self {
        Self::with_capacity(MIN_CAPACITY)
    }

    fn with_capacity(capacity: usize) -> Self {
        let capacity = capacity.max(MIN_CAPACITY);
        Table {
            slots: vec![0; capacity],
            id_bits: (usize::BITS - capacity.leading_zeros()).min(32),
        }
    }

    /// The first slot to probe for `hash` (its high bits, scaled to the
    /// capacity: any capacity works, not only powers of two).
    fn home(&self, hash: u64) -> usize {
        let cap = self.slots.len() as u128;
        #[allow(clippy::cast_possible_truncation)]
        let at = ((u128::from(hash) * cap) >> 64) as usize;
        at
    }

    /// The tag bits of `hash` in a slot.
    fn tag(&self, hash: u64) -> u32 {
        #[allow(clippy::cast_possible_truncation)]
        let low = hash as u32;
        low.checked_shl(self.id_bits).unwrap_or(0)
    }

    fn id_mask(&self) -> u32 {
        u32::MAX.checked_shr(32 - self.id_bits).unwrap_or(0)
    }

    /// Looks `hash` up; `same(id)` says whether stored state `id` is the
    /// one looked for (asked only of states whose tag matches).
    pub(super) fn probe(&self, hash: u64, mut same: impl FnMut(StateId) -> bool) -> Probe {
        let (tag, mask) = (self.tag(hash), self.id_mask());
        let cap = self.slots.len();
        let mut at = self.home(hash);
        loop {
            let slot = self.slots[at];
            if slot == 0 {
                return Probe::Vacant(at);
            }
            if slot & !mask == tag {
                let id = (slot & mask).wrapping_sub(1);
                if same(id) {
                    return Probe::Found(at, id);
                }
            }
            at += 1;
            if at == cap {
                at = 0;
            }
        }
    }

    /// Puts `id` (of hash `hash`) in `slot`, found by [`Self::probe`] (a
    /// vacant slot, or the slot of a state `id` replaces).
    pub(super) fn set(&mut self, slot: usize, hash: u64, id: StateId) {
        self.slots[slot] = self.tag(hash) | (id.saturating_add(1) & self.id_mask());
    }

    /// Whether a store of `states` states must grow the table before it
    /// stores one more: past the load limit, ids would not fit the slots.
    pub(super) fn full(&self, states: usize) -> bool {
        (states + 1) * LOAD_DEN > self.slots.len() * LOAD_NUM
    }

    /// The stored ids, in slot order.
    pub(super) fn ids(&self) -> impl Iterator<Item = StateId> + '_ {
        let mask = self.id_mask();
        self.slots
            .iter()
            .filter(|&&s| s != 0)
            .map(move |s| (s & mask).wrapping_sub(1))
    }

    /// A table half again as large, holding `entries` (distinct states,
    /// with their hashes).
    pub(super) fn grown(&self, entries: impl Iterator<Item = (StateId, u64)>) -> Table {
        let mut t = Table::with_capacity(self.slots.len() + self.slots.len() / 2);
        for (id, hash) in entries {
            if let Probe::Vacant(at) = t.probe(hash, |_| false) {
                t.set(at, hash, id);
            }
        }
        t
    }

    /// Slots (each 4 bytes).
    pub(super) fn capacity(&self) -> usize {
        self.slots.capacity()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn probes_find_what_was_set_and_tags_spare_comparisons() {
        let mut t = Table::new();
        let keys: Vec<u64> = (0..5000u64).collect();
        let mut compared = 0;
        for (id, &k) in keys.iter().enumerate() {
            let id = StateId::try_from(id).unwrap_or(StateId::MAX);
            if t.full(id as usize) {
                t = t.grown(t.ids().map(|i| (i, hash(&[keys[i as usize]]))));
            }
            match t.probe(hash(&[k]), |other| {
                compared += 1;
                keys[other as usize] == k
            }) {
                Probe::Vacant(at) => t.set(at, hash(&[k]), id),
                Probe::Found(..) => panic!("{k} found before it was set"),
            }
        }
        // Different keys share a tag by chance only.
        assert!(compared < 100, "{compared} comparisons");
        for (id, &k) in keys.iter().enumerate() {
            let found = t.probe(hash(&[k]), |other| keys[other as usize] == k);
            assert!(
                matches!(found, Probe::Found(_, i) if i as usize == id),
                "{k}"
            );
        }
        let absent = t.probe(hash(&[99_999]), |other| keys[other as usize] == 99_999);
        assert!(matches!(absent, Probe::Vacant(_)));
        assert_eq!(t.ids().count(), keys.len());
        assert!(keys.len() * 5 <= t.capacity() * 4);
    }

    #[test]
    fn the_hash_spreads_nearby_words() {
        let mut homes = std::collections::HashSet::new();
        let t = Table::with_capacity(1 << 16);
        for k in 0..1000u64 {
            homes.insert(t.home(hash(&[k << 3, 1])));
        }
        assert!(homes.len() > 980, "{}", homes.len());
        assert_ne!(hash(&[1, 2]), hash(&[2, 1]));
        assert_ne!(hash(&[0]), hash(&[0, 0]));
    }
}
