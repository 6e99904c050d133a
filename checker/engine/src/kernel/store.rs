//! Compact storage of explored states: every state is a fixed number of
//! 64-bit words in one arena, deduplicated by a hash table of `u32` slots
//! (an index and a hash tag, [`table`]), with the parent that first reached
//! it and, unless the model re-derives it, the action, so that
//! counterexamples are replayable paths.
//! The arena and the per-state columns grow in chunks ([`column`]): no
//! per-state allocation, no copy on growth, and the bytes counted per state
//! are about the bytes used.
//!
//! A state may also carry a *zone* (the timed engine's clock zone): states
//! with the same words are chained, and a new state whose zone is included
//! in a stored one is not new (inclusion checking in the passed list).
//! Zones are kept once each ([`pool`]) and states hold their index. For
//! untimed models the zone is `()` and every same-words state subsumes.

pub mod bits;
mod column;
mod packed;
mod pool;
mod table;

use std::hash::Hash;

use column::Column;
use packed::Packed;
use pool::Pool;
use table::{Probe, Table, hash};

/// Index of a stored state.
pub type StateId = u32;

/// The symbolic part of a state: `a.subsumed_by(b)` when every concrete
/// state of `a` is one of `b` (zone inclusion). Equal values are stored
/// once (hence `Hash + Eq`).
pub trait Subsumes: Hash + Eq {
    /// Whether `self` is included in `other`.
    fn subsumed_by(&self, other: &Self) -> bool;

    /// Bytes the value owns on the heap (counted against `--max-memory`).
    fn heap_bytes(&self) -> usize {
        0
    }

    /// Every value subsumes every other (untimed models): a state is
    /// known by its words alone, so the store keeps no same-words chains
    /// and no covered flags.
    const TRIVIAL: bool = false;
}

impl Subsumes for () {
    fn subsumed_by(&self, _: &()) -> bool {
        true
    }

    const TRIVIAL: bool = true;
}

/// End of a same-words chain.
const NONE: StateId = StateId::MAX;

/// The stored states of one exploration.
pub struct Store<A, Z = ()> {
    /// The states' words, each in the bytes its bits need.
    words: Packed,
    /// Per state (chained stores only), side by side so that a walk along a
    /// chain reads one place per state: the previous state with the same
    /// words ([`NONE`] at the end), and its zone's index in `pool`.
    chain: Column<u32>,
    /// The distinct zones.
    pool: Pool<Z>,
    /// States whose zone a later state includes: no need to expand them
    /// (chained stores only).
    covered: Column<bool>,
    /// For each stored words, the newest state with them.
    table: Table,
    parents: Column<StateId>,
    /// Per state, the action that first reached it; empty when the store
    /// keeps no actions (the model finds them again from the parents:
    /// [`super::explore::Exploration::path`]).
    via: Column<Option<A>>,
    /// Whether `via` is kept.
    keeps_actions: bool,
}

impl<A, Z> std::fmt::Debug for Store<A, Z> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Store")
            .field("states", &self.parents.len())
            .field("width", &self.words.width())
            .finish()
    }
}

impl<A: Copy, Z: Subsumes> Store<A, Z> {
    /// An empty store of states `width` words wide, with the action that
    /// reached each state.
    pub fn new(width: usize) -> Self {
        Self::with_layout(width, 64 * width, true)
    }

    /// An empty store of states `width` words wide that use `bits` bits of
    /// their words (those past it are zero: each is kept in `bits / 8`
    /// bytes, rounded up), keeping the action that reached each state or
    /// not (then a path is found again from the parents by the model:
    /// [`super::explore::Exploration::path`]).
    pub fn with_layout(width: usize, bits: usize, keeps_actions: bool) -> Self {
        Store {
            words: Packed::new(width.max(1), bits),
            chain: Column::new(2),
            pool: Pool::new(),
            covered: Column::new(1),
            table: Table::new(),
            parents: Column::new(1),
            via: Column::new(1),
            keeps_actions,
        }
    }

    /// Whether the action that reached each state is kept.
    pub fn keeps_actions(&self) -> bool {
        self.keeps_actions
    }

    /// The words of state `id`, into `out` (cleared first).
    pub fn load(&self, id: StateId, out: &mut Vec<u64>) {
        self.words.load(id as usize, out);
    }

    /// The words of state `id`.
    pub fn get(&self, id: StateId) -> Vec<u64> {
        let mut out = Vec::with_capacity(self.words.width());
        self.load(id, &mut out);
        out
    }

    /// Whether state `id`'s words are `key`.
    pub fn matches(&self, id: StateId, key: &[u64]) -> bool {
        self.words.same(id as usize, key)
    }

    /// The zone of state `id`.
    pub fn zone(&self, id: StateId) -> &Z {
        if Z::TRIVIAL {
            // Untimed: no zone is stored; the pool holds the one value.
            return self.pool.get(0);
        }
        self.pool.get(self.chain.get(id as usize)[1])
    }

    /// Looks `key` (of hash `hash`) up in the table.
    fn probe(&self, key: &[u64], hash: u64) -> Probe {
        let words = &self.words;
        self.table.probe(hash, |id| words.same(id as usize, key))
    }

    /// Grows the table when one more state would overfill it.
    fn reserve(&mut self) {
        if !self.table.full(self.len()) {
            return;
        }
        let words = &self.words;
        self.table = if Z::TRIVIAL {
            // Every state is in the table: rehash them in id order, reading
            // the arena sequentially.
            self.table.grown((0..).zip(words.map_all(hash)))
        } else {
            let heads: Vec<StateId> = self.table.ids().collect();
            let mut buf = Vec::with_capacity(self.words.width());
            self.table.grown(heads.into_iter().map(|id| {
                words.load(id as usize, &mut buf);
                (id, hash(&buf))
            }))
        };
    }

    /// Inserts a state reached from `parent` by `via`; returns its id and
    /// whether it is new (not subsumed by a stored state with the same words).
    pub fn insert(
        &mut self,
        key: &[u64],
        zone: Z,
        parent: Option<(StateId, A)>,
    ) -> (StateId, bool) {
        debug_assert_eq!(key.len(), self.words.width());
        self.reserve();
        let hash = hash(key);
        let id = StateId::try_from(self.len()).unwrap_or(StateId::MAX);
        let probe = self.probe(key, hash);
        if Z::TRIVIAL {
            return match probe {
                Probe::Found(_, found) => (found, false),
                Probe::Vacant(slot) => {
                    if self.is_empty() {
                        self.pool.intern(zone);
                    }
                    self.table.set(slot, hash, id);
                    self.push(key, parent);
                    (id, true)
                }
            };
        }
        let (slot, head) = match probe {
            Probe::Found(slot, head) => (slot, head),
            Probe::Vacant(slot) => (slot, NONE),
        };
        // One pass over the chain: a stored zone that includes the new one
        // makes it old; one the new zone includes needs no expansion and
        // leaves the chain (what it includes, its coverer includes too), so
        // chains hold only zones that none of them includes.
        let mut kept = NONE;
        let mut last = NONE;
        let mut found = None;
        let mut cur = head;
        while cur != NONE {
            let next = self.chain.get(cur as usize)[0];
            let other = self.zone(cur);
            let old = zone.subsumed_by(other);
            if !old && other.subsumed_by(&zone) {
                if let Some(flag) = self.covered.first_mut(cur as usize) {
                    *flag = true;
                }
                cur = next;
                continue;
            }
            // `cur` stays, after the last state that stayed.
            if last == NONE {
                kept = cur;
            } else {
                self.set_same(last, cur);
            }
            last = cur;
            if old {
                // The chain goes on whole from `cur`.
                found = Some(cur);
                break;
            }
            cur = next;
        }
        if let Some(cur) = found {
            if kept != head {
                self.table.set(slot, hash, kept);
            }
            return (cur, false);
        }
        if last != NONE {
            self.set_same(last, NONE);
        }
        let zid = self.pool.intern(zone);
        self.table.set(slot, hash, id);
        self.covered.push(false);
        self.chain.push_slice(&[kept, zid]);
        self.push(key, parent);
        (id, true)
    }

    /// Points `id`'s chain link at `next`.
    fn set_same(&mut self, id: StateId, next: StateId) {
        if let Some(link) = self.chain.first_mut(id as usize) {
            *link = next;
        }
    }

    /// Appends a new state's words, parent and action.
    fn push(&mut self, key: &[u64], parent: Option<(StateId, A)>) {
        let id = StateId::try_from(self.len()).unwrap_or(StateId::MAX);
        self.words.push(key);
        self.parents.push(parent.map_or(id, |(p, _)| p));
        if self.keeps_actions {
            self.via.push(parent.map(|(_, a)| a));
        }
    }

    /// The newest stored state with these words, if any (for untimed models,
    /// the only one).
    pub fn find(&self, key: &[u64]) -> Option<StateId> {
        match self.probe(key, hash(key)) {
            Probe::Found(_, id) => Some(id),
            Probe::Vacant(_) => None,
        }
    }

    /// Whether a later state's zone includes this one's.
    pub fn is_covered(&self, id: StateId) -> bool {
        self.covered.first(id as usize).copied().unwrap_or(false)
    }

    /// Number of stored states.
    pub fn len(&self) -> usize {
        self.parents.len()
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.parents.len() == 0
    }

    /// The action that first reached `id` (`None` for an initial state).
    fn via(&self, id: StateId) -> Option<A> {
        self.via.first(id as usize).copied().flatten()
    }

    /// The state that first reached `id` (`None` for an initial state,
    /// which is its own parent).
    pub fn parent(&self, id: StateId) -> Option<StateId> {
        let p = self.parents.get(id as usize)[0];
        (p != id).then_some(p)
    }

    /// The actions from an initial state to `id`, in a store that keeps
    /// them (empty otherwise: see [`super::explore::Exploration::path`]).
    pub fn path(&self, id: StateId) -> Vec<A> {
        let mut out = Vec::new();
        let mut cur = id;
        while let Some(a) = self.via(cur) {
            out.push(a);
            cur = self.parents.get(cur as usize)[0];
        }
        out.reverse();
        out
    }

    /// The initial state a path to `id` starts from.
    pub fn root(&self, id: StateId) -> StateId {
        let mut cur = id;
        while let Some(p) = self.parent(cur) {
            cur = p;
        }
        cur
    }

    /// Approximate bytes used per state (arena, table, parent links).
    pub fn bytes_per_state(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        #[allow(clippy::cast_precision_loss)]
        let per = self.bytes() as f64 / self.len() as f64;
        per
    }

    /// Approximate total bytes used.
    pub fn bytes(&self) -> usize {
        self.words.capacity_bytes()
            + self.table.capacity() * size_of::<u32>()
            + (self.parents.capacity() + self.chain.capacity()) * size_of::<u32>()
            + self.covered.capacity()
            + self.via.capacity() * size_of::<Option<A>>()
            + self.pool.bytes()
    }
}

/// The bytes per state of the largest of several explorations (the one
/// with most states): the figure a user reads about memory (a small
/// store's first chunks would make it look large).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Footprint {
    states: usize,
    /// Bytes per state of that exploration.
    pub bytes_per_state: f64,
}

impl Footprint {
    /// Counts one more exploration's store.
    pub fn add<A: Copy, Z: Subsumes>(&mut self, store: &Store<A, Z>) {
        self.join(Footprint {
            states: store.len(),
            bytes_per_state: store.bytes_per_state(),
        });
    }

    /// The larger of the two.
    pub fn join(&mut self, other: Footprint) {
        if other.states > self.states {
            *self = other;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn states_are_deduplicated_and_paths_replayable() {
        let mut s: Store<char> = Store::new(2);
        let (a, new_a) = s.insert(&[1, 2], (), None);
        let (b, new_b) = s.insert(&[3, 4], (), Some((a, 'x')));
        let (c, _) = s.insert(&[5, 6], (), Some((b, 'y')));
        let (a2, again) = s.insert(&[1, 2], (), Some((c, 'z')));
        assert!(new_a && new_b && !again);
        assert_eq!(a2, a);
        assert_eq!(s.len(), 3);
        assert_eq!(s.get(b), &[3, 4]);
        assert_eq!(s.path(c), vec!['x', 'y']);
        assert_eq!(s.root(c), a);
        assert!(s.bytes_per_state() > 0.0);
    }

    /// Spread keys, as packed states are.
    fn key(k: u64) -> u64 {
        k.wrapping_mul(0x9E37_79B9_7F4A_7C15)
    }

    /// A zone-less state kept the way zones are (same-words chains and
    /// covered flags).
    #[derive(PartialEq, Eq, Hash)]
    struct Chained;

    impl Subsumes for Chained {
        fn subsumed_by(&self, _: &Chained) -> bool {
            true
        }
    }

    #[test]
    fn untimed_states_are_found_again_and_cost_no_chains() {
        let n: u64 = 200_000;
        let mut s: Store<char> = Store::new(1);
        let mut timed: Store<char, Chained> = Store::new(1);
        let (root, _) = s.insert(&[u64::MAX], (), None);
        timed.insert(&[u64::MAX], Chained, None);
        for k in 0..n {
            let (id, new) = s.insert(&[key(k)], (), Some((root, 'a')));
            assert!(new, "{k}");
            assert_eq!(u64::from(id), k + 1);
            assert!(timed.insert(&[key(k)], Chained, Some((root, 'a'))).1);
        }
        for k in (0..n).step_by(97) {
            let id = u32::try_from(k + 1).unwrap();
            assert_eq!(s.insert(&[key(k)], (), None), (id, false));
            assert_eq!(s.find(&[key(k)]), Some(id));
        }
        assert_eq!(s.len(), timed.len());
        assert_eq!(s.path(5), vec!['a']);
        assert_eq!(s.root(5), root);
        let (per, per_timed) = (s.bytes_per_state(), timed.bytes_per_state());
        // Words, table, parent and action; no same-words link (4 bytes)
        // nor covered flag (1) per state, which zones need.
        assert!(per > 8.0 && per <= 32.0, "{per} bytes per state");
        assert!(per_timed - per >= 5.0, "{per_timed} against {per}");
    }

    /// Intervals ordered by inclusion, standing in for zones.
    impl Subsumes for (u32, u32) {
        fn subsumed_by(&self, other: &Self) -> bool {
            other.0 <= self.0 && self.1 <= other.1
        }
    }

    #[test]
    fn included_zones_are_not_new_and_larger_ones_are() {
        let mut s: Store<char, (u32, u32)> = Store::new(1);
        let (a, _) = s.insert(&[7], (2, 5), None);
        assert_eq!(s.insert(&[7], (3, 4), Some((a, 'x'))), (a, false));
        let (b, new) = s.insert(&[7], (1, 9), Some((a, 'y')));
        assert!(new);
        // Both are kept; a zone included in the newer one is not new either.
        assert!(!s.insert(&[7], (6, 8), Some((b, 'z'))).1);
        assert!(s.insert(&[8], (3, 4), None).1);
        assert_eq!(*s.zone(b), (1, 9));
    }

    #[test]
    fn long_chains_outgrow_the_table_and_stay_found() {
        // Many states share their words (incomparable zones): the table
        // holds one entry per words but every id must fit its slots.
        let mut s: Store<char, (u32, u32)> = Store::new(2);
        let n = 3000;
        for k in 0..n {
            for w in 0..3u64 {
                let (_, new) = s.insert(&[w, 7], (k, k), None);
                assert!(new);
            }
        }
        assert_eq!(s.len(), 3 * n as usize);
        for w in 0..3u64 {
            let newest = s.find(&[w, 7]).unwrap();
            assert_eq!(s.get(newest), &[w, 7]);
            assert_eq!(*s.zone(newest), (n - 1, n - 1));
            assert!(!s.insert(&[w, 7], (5, 5), None).1);
            assert!(!s.is_covered(newest));
        }
        // A zone including all of them covers them.
        let (all, new) = s.insert(&[1, 7], (0, n), None);
        assert!(new && !s.is_covered(all));
        assert!(s.is_covered(1) && !s.is_covered(0));
        assert_eq!(s.find(&[9, 9]), None);
    }
}
