//! Compact storage of explored states: every state is a fixed number of
//! 64-bit words in one arena, deduplicated by a hash table of `u32` indices
//! (no per-state allocation), with the parent and the action that first
//! reached it, so that counterexamples are replayable paths.

use std::hash::BuildHasher;

use hashbrown::HashTable;
use rustc_hash::FxBuildHasher;

/// Index of a stored state.
pub type StateId = u32;

/// The stored states of one exploration.
pub struct Store<A> {
    width: usize,
    words: Vec<u64>,
    table: HashTable<StateId>,
    parents: Vec<StateId>,
    via: Vec<Option<A>>,
    hasher: FxBuildHasher,
}

impl<A> std::fmt::Debug for Store<A> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Store")
            .field("states", &self.parents.len())
            .field("width", &self.width)
            .finish()
    }
}

impl<A: Copy> Store<A> {
    /// An empty store of states `width` words wide.
    pub fn new(width: usize) -> Self {
        Store {
            width: width.max(1),
            words: Vec::new(),
            table: HashTable::new(),
            parents: Vec::new(),
            via: Vec::new(),
            hasher: FxBuildHasher,
        }
    }

    fn hash(&self, key: &[u64]) -> u64 {
        self.hasher.hash_one(key)
    }

    /// The words of state `id`.
    pub fn get(&self, id: StateId) -> &[u64] {
        let start = id as usize * self.width;
        &self.words[start..start + self.width]
    }

    /// Inserts a state reached from `parent` by `via`; returns its id and
    /// whether it is new.
    pub fn insert(&mut self, key: &[u64], parent: Option<(StateId, A)>) -> (StateId, bool) {
        debug_assert_eq!(key.len(), self.width);
        let hash = self.hash(key);
        let (words, width) = (&self.words, self.width);
        let eq = |&id: &StateId| words[id as usize * width..(id as usize + 1) * width] == *key;
        if let Some(&id) = self.table.find(hash, eq) {
            return (id, false);
        }
        let id = StateId::try_from(self.parents.len()).unwrap_or(StateId::MAX);
        self.words.extend_from_slice(key);
        let (words, width, hasher) = (&self.words, self.width, &self.hasher);
        self.table.insert_unique(hash, id, |&other| {
            hasher.hash_one(&words[other as usize * width..(other as usize + 1) * width])
        });
        self.parents.push(parent.map_or(id, |(p, _)| p));
        self.via.push(parent.map(|(_, a)| a));
        (id, true)
    }

    /// Number of stored states.
    pub fn len(&self) -> usize {
        self.parents.len()
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.parents.is_empty()
    }

    /// The actions from an initial state to `id`.
    pub fn path(&self, id: StateId) -> Vec<A> {
        let mut out = Vec::new();
        let mut cur = id;
        while let Some(a) = self.via.get(cur as usize).copied().flatten() {
            out.push(a);
            cur = self.parents[cur as usize];
        }
        out.reverse();
        out
    }

    /// The initial state a path to `id` starts from.
    pub fn root(&self, id: StateId) -> StateId {
        let mut cur = id;
        while self.via.get(cur as usize).copied().flatten().is_some() {
            cur = self.parents[cur as usize];
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
        self.words.capacity() * 8
            + self.table.capacity() * (size_of::<StateId>() + 1)
            + self.parents.capacity() * size_of::<StateId>()
            + self.via.capacity() * size_of::<Option<A>>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn states_are_deduplicated_and_paths_replayable() {
        let mut s: Store<char> = Store::new(2);
        let (a, new_a) = s.insert(&[1, 2], None);
        let (b, new_b) = s.insert(&[3, 4], Some((a, 'x')));
        let (c, _) = s.insert(&[5, 6], Some((b, 'y')));
        let (a2, again) = s.insert(&[1, 2], Some((c, 'z')));
        assert!(new_a && new_b && !again);
        assert_eq!(a2, a);
        assert_eq!(s.len(), 3);
        assert_eq!(s.get(b), &[3, 4]);
        assert_eq!(s.path(c), vec!['x', 'y']);
        assert_eq!(s.root(c), a);
        assert!(s.bytes_per_state() > 0.0);
    }
}
