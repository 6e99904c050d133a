//! The arena of encoded states, each kept in the bytes its bits need: a
//! model encodes a state as 64-bit words whose bits past
//! [`crate::kernel::explore::Model::bits`] are zero, and the arena keeps
//! only the bytes up to that bit (a 140-bit state takes 18 bytes, not 24).
//! States are read back into words ([`Packed::load`]) and compared with a
//! key without unpacking ([`Packed::same`]).

use super::column::Column;

/// The encoded states, `bytes` bytes each.
#[derive(Debug)]
pub(super) struct Packed {
    /// Words of an encoded state.
    width: usize,
    /// Bytes kept per state (at most `8 * width`).
    bytes: usize,
    column: Column<u8>,
}

impl Packed {
    /// An empty arena of states `width` words wide using `bits` bits.
    pub(super) fn new(width: usize, bits: usize) -> Self {
        let bytes = bits.div_ceil(8).clamp(1, 8 * width);
        Packed {
            width,
            bytes,
            column: Column::new(bytes),
        }
    }

    /// Words of an encoded state.
    pub(super) fn width(&self) -> usize {
        self.width
    }

    /// Appends a state's words (its bits past the kept bytes are zero).
    pub(super) fn push(&mut self, key: &[u64]) {
        debug_assert_eq!(key.len(), self.width);
        debug_assert!(self.fits(key), "bits past the state's bytes are set");
        let bytes = self.bytes;
        self.column.push_with(|chunk| {
            for (k, w) in key.iter().enumerate() {
                let take = bytes.saturating_sub(8 * k).min(8);
                chunk.extend_from_slice(&w.to_le_bytes()[..take]);
            }
        });
    }

    /// Whether every set bit of `key` is in the kept bytes.
    fn fits(&self, key: &[u64]) -> bool {
        key.iter().enumerate().all(|(k, &w)| {
            let kept = self.bytes.saturating_sub(8 * k).min(8);
            kept == 8 || w >> (8 * kept) == 0
        })
    }

    /// Whether state `id` is `key`.
    pub(super) fn same(&self, id: usize, key: &[u64]) -> bool {
        let stored = self.column.get(id);
        key.len() == self.width
            && key
                .iter()
                .zip(stored.chunks(8).map(word).chain(std::iter::repeat(0)))
                .all(|(&k, s)| k == s)
    }

    /// The words of state `id`, into `out` (cleared first).
    pub(super) fn load(&self, id: usize, out: &mut Vec<u64>) {
        out.clear();
        out.extend(self.column.get(id).chunks(8).map(word));
        out.resize(self.width, 0);
    }

    /// `f` of the words of every state, in id order (each read into one
    /// reused buffer).
    pub(super) fn map_all<'s, R>(
        &'s self,
        mut f: impl FnMut(&[u64]) -> R + 's,
    ) -> impl Iterator<Item = R> + 's {
        let mut buf = Vec::with_capacity(self.width);
        self.column.states().map(move |stored| {
            buf.clear();
            buf.extend(stored.chunks(8).map(word));
            buf.resize(self.width, 0);
            f(&buf)
        })
    }

    /// Bytes allocated.
    pub(super) fn capacity_bytes(&self) -> usize {
        self.column.capacity()
    }
}

/// A little-endian word of up to 8 bytes.
fn word(bytes: &[u8]) -> u64 {
    match <[u8; 8]>::try_from(bytes) {
        Ok(whole) => u64::from_le_bytes(whole),
        Err(_) => bytes.iter().rev().fold(0, |w, &b| (w << 8) | u64::from(b)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn states_keep_their_bytes_only_and_read_back_whole() {
        // 70 bits: 9 bytes, over two words.
        let mut p = Packed::new(2, 70);
        let a = [u64::MAX, 0x3f];
        let b = [0x0123_4567_89ab_cdef, 0x21];
        p.push(&a);
        p.push(&b);
        let mut out = Vec::new();
        p.load(1, &mut out);
        assert_eq!(out, b);
        p.load(0, &mut out);
        assert_eq!(out, a);
        assert!(p.same(0, &a) && p.same(1, &b) && !p.same(0, &b));
        assert!(!p.same(1, &[b[0], 0x20]));
        let seen: Vec<Vec<u64>> = p.map_all(<[u64]>::to_vec).collect();
        assert_eq!(seen, vec![a.to_vec(), b.to_vec()]);
        assert!(p.fits(&[0, 0xff]) && !p.fits(&[0, 0x100]));
        // Rounded up to whole bytes: 70 bits keep 9 bytes, not 16.
        assert_eq!(p.bytes, 9);
    }
}
