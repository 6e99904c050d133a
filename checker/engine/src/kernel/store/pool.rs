//! The distinct zones of a store, each kept once: states refer to their
//! zone by a `u32` index. A timed exploration reaches many states for few
//! zones (nhfc with its WCETs: about 4,400 distinct zones in its first two
//! million states), so a zone costs a state four bytes instead of its
//! bound matrix.

use std::hash::{BuildHasher, Hash};

use hashbrown::DefaultHashBuilder;
use hashbrown::HashTable;

use super::Subsumes;

/// Index of a zone in a [`Pool`].
pub(super) type ZoneId = u32;

/// Distinct zones in first-seen order, with a table to find them.
pub(super) struct Pool<Z> {
    zones: Vec<Z>,
    table: HashTable<ZoneId>,
    hasher: DefaultHashBuilder,
    /// Heap bytes the zones own.
    heap: usize,
}

impl<Z: Subsumes + Hash + Eq> Pool<Z> {
    /// An empty pool.
    pub(super) fn new() -> Self {
        Pool {
            zones: Vec::new(),
            table: HashTable::new(),
            hasher: DefaultHashBuilder::default(),
            heap: 0,
        }
    }

    /// The index of `zone`, added when new.
    pub(super) fn intern(&mut self, zone: Z) -> ZoneId {
        let hash = self.hasher.hash_one(&zone);
        let zones = &self.zones;
        if let Some(&id) = self.table.find(hash, |&id| zones[id as usize] == zone) {
            return id;
        }
        let id = ZoneId::try_from(self.zones.len()).unwrap_or(ZoneId::MAX);
        self.heap += zone.heap_bytes();
        self.zones.push(zone);
        let (zones, hasher) = (&self.zones, &self.hasher);
        self.table
            .insert_unique(hash, id, |&id| hasher.hash_one(&zones[id as usize]));
        id
    }

    /// The zone of index `id`.
    pub(super) fn get(&self, id: ZoneId) -> &Z {
        &self.zones[id as usize]
    }

    /// Approximate bytes used.
    pub(super) fn bytes(&self) -> usize {
        self.zones.capacity() * size_of::<Z>()
            + self.table.capacity() * (size_of::<ZoneId>() + 1)
            + self.heap
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_zones_share_one_index() {
        let mut p: Pool<(u32, u32)> = Pool::new();
        let a = p.intern((1, 2));
        let b = p.intern((3, 4));
        assert_ne!(a, b);
        assert_eq!(p.intern((1, 2)), a);
        for k in 0..1000 {
            p.intern((k + 10, k));
        }
        assert_eq!(p.intern((3, 4)), b);
        assert_eq!(*p.get(b), (3, 4));
        assert_eq!(p.zones.len(), 1002);
    }
}
