//! A growable column of per-state values stored in chunks: appending never
//! moves what is stored (no copy of the whole column on growth, as a
//! doubling `Vec` does), and the capacity beyond the stored values is at
//! most one chunk, so the bytes a store counts per state are what it uses.

/// States per chunk (after the first chunk, which grows up to this size so
/// that a small exploration stays small).
const CHUNK_SHIFT: u32 = 12;
const CHUNK: usize = 1 << CHUNK_SHIFT;

/// `per` values for each state, in chunks of [`CHUNK`] states.
#[derive(Debug)]
pub(super) struct Column<T> {
    per: usize,
    chunks: Vec<Vec<T>>,
    /// Stored states.
    len: usize,
    /// Values the chunks have room for (kept, not summed on each ask: the
    /// explorer asks for the store's bytes every few transitions).
    capacity: usize,
}

impl<T> Column<T> {
    /// An empty column of `per` values a state.
    pub(super) fn new(per: usize) -> Self {
        Column {
            per,
            chunks: Vec::new(),
            len: 0,
            capacity: 0,
        }
    }

    /// The chunk the next state goes in, with room for it.
    fn tail(&mut self) -> &mut Vec<T> {
        let chunk = self.len >> CHUNK_SHIFT;
        if chunk == self.chunks.len() {
            // The first chunk starts small and doubles; later ones are full
            // size from the start.
            let states = if chunk == 0 { 16 } else { CHUNK };
            let fresh = Vec::with_capacity(states * self.per);
            self.capacity = self.capacity.saturating_add(fresh.capacity());
            self.chunks.push(fresh);
        }
        let per = self.per;
        let last = &mut self.chunks[chunk];
        if last.len() + per > last.capacity() {
            let (before, states) = (last.capacity(), (last.capacity() / per.max(1)).max(1));
            last.reserve_exact(states.min(CHUNK - states).max(1) * per);
            self.capacity = self.capacity.saturating_add(last.capacity() - before);
        }
        last
    }

    /// Appends one state's value (`per == 1`).
    pub(super) fn push(&mut self, value: T) {
        debug_assert_eq!(self.per, 1);
        self.tail().push(value);
        self.len += 1;
    }

    /// The values of state `id` (`id < len`).
    pub(super) fn get(&self, id: usize) -> &[T] {
        let off = (id & (CHUNK - 1)) * self.per;
        &self.chunks[id >> CHUNK_SHIFT][off..off + self.per]
    }

    /// The first value of state `id`, if stored.
    pub(super) fn first(&self, id: usize) -> Option<&T> {
        self.chunks
            .get(id >> CHUNK_SHIFT)?
            .get((id & (CHUNK - 1)) * self.per)
    }

    /// The first value of state `id`, mutable.
    pub(super) fn first_mut(&mut self, id: usize) -> Option<&mut T> {
        let per = self.per;
        self.chunks
            .get_mut(id >> CHUNK_SHIFT)?
            .get_mut((id & (CHUNK - 1)) * per)
    }

    /// Stored states.
    pub(super) fn len(&self) -> usize {
        self.len
    }

    /// Values the column has room for (stored or not).
    pub(super) fn capacity(&self) -> usize {
        self.capacity
    }

    /// The stored states' values in order, `per` at a time.
    pub(super) fn states(&self) -> impl Iterator<Item = &[T]> + '_ {
        self.chunks
            .iter()
            .flat_map(move |c| c.chunks_exact(self.per.max(1)))
    }
}

impl<T: Copy> Column<T> {
    /// Appends one state's `per` values.
    pub(super) fn push_slice(&mut self, values: &[T]) {
        debug_assert_eq!(values.len(), self.per);
        self.tail().extend_from_slice(values);
        self.len += 1;
    }

    /// Appends one state's `per` values, written by `write` at the end of
    /// the chunk it goes in.
    pub(super) fn push_with(&mut self, write: impl FnOnce(&mut Vec<T>)) {
        let per = self.per;
        let tail = self.tail();
        let before = tail.len();
        write(tail);
        debug_assert_eq!(tail.len(), before + per);
        self.len += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_stay_where_they_were_put_and_slack_is_one_chunk() {
        let mut c: Column<u64> = Column::new(3);
        let n = 3 * CHUNK + 17;
        for k in 0..n as u64 {
            c.push_slice(&[k, k + 1, k + 2]);
        }
        assert_eq!(c.len(), n);
        for k in [0, 1, 15, 16, CHUNK - 1, CHUNK, 2 * CHUNK + 5, n - 1] {
            let k64 = k as u64;
            assert_eq!(c.get(k), &[k64, k64 + 1, k64 + 2]);
        }
        assert_eq!(c.first(n - 1), Some(&(n as u64 - 1)));
        assert_eq!(c.first(n), None);
        assert!(c.capacity() >= 3 * n && c.capacity() <= 3 * (n + CHUNK));
        let summed: usize = c.chunks.iter().map(Vec::capacity).sum();
        assert_eq!(c.capacity(), summed);
        assert_eq!(c.states().count(), n);
        assert!(c.states().enumerate().all(|(k, s)| s[0] == k as u64));
        let mut small: Column<bool> = Column::new(1);
        for _ in 0..20 {
            small.push(false);
        }
        assert!(small.capacity() <= 32, "{}", small.capacity());
        if let Some(b) = small.first_mut(19) {
            *b = true;
        }
        assert_eq!(small.get(19), &[true]);
    }
}
