//! Packing a state's fields into as few words as their widths allow: a
//! semantics lays its state out as fields of known bit widths (a task's
//! flag, a queue entry, a packed instance) and writes them in order with a
//! [`BitWriter`]; a [`BitReader`] reads them back in the same order. Fields
//! may straddle words. The store keeps fewer, denser words per state.

/// Words needed for `bits` bits.
pub fn words_for(bits: usize) -> usize {
    bits.div_ceil(64)
}

/// Appends fields to a state's words.
pub struct BitWriter<'a> {
    out: &'a mut Vec<u64>,
    word: u64,
    used: u32,
}

impl<'a> BitWriter<'a> {
    /// A writer appending to `out`.
    pub fn new(out: &'a mut Vec<u64>) -> Self {
        BitWriter {
            out,
            word: 0,
            used: 0,
        }
    }

    /// Writes the low `bits` bits of `value` (`bits` ≤ 64; higher bits of
    /// `value` must be zero).
    pub fn put(&mut self, value: u64, bits: u32) {
        debug_assert!(bits <= 64 && (bits == 64 || value >> bits == 0));
        if bits == 0 {
            return;
        }
        self.word |= value << self.used;
        let room = 64 - self.used;
        if bits < room {
            self.used += bits;
            return;
        }
        self.out.push(self.word);
        // The bits that did not fit start the next word.
        self.word = if room == 64 { 0 } else { value >> room };
        self.used = bits - room;
    }

    /// Writes a flag.
    pub fn flag(&mut self, on: bool) {
        self.put(u64::from(on), 1);
    }

    /// Ends the state: the last, partial word is written.
    pub fn finish(self) {
        if self.used > 0 {
            self.out.push(self.word);
        }
    }
}

/// Reads the fields a [`BitWriter`] wrote, in the same order; past the end
/// it reads zeros.
pub struct BitReader<'a> {
    words: &'a [u64],
    at: usize,
}

impl<'a> BitReader<'a> {
    /// A reader of `words` from their first bit.
    pub fn new(words: &'a [u64]) -> Self {
        BitReader { words, at: 0 }
    }

    /// The next `bits`-bit field (`bits` ≤ 64).
    pub fn take(&mut self, bits: u32) -> u64 {
        if bits == 0 {
            return 0;
        }
        let (k, off) = (self.at / 64, (self.at % 64) as u32);
        self.at += bits as usize;
        let word = |i: usize| self.words.get(i).copied().unwrap_or(0);
        let mut v = word(k) >> off;
        if off + bits > 64 {
            v |= word(k + 1) << (64 - off);
        }
        if bits == 64 { v } else { v & ((1 << bits) - 1) }
    }

    /// The next flag.
    pub fn flag(&mut self) -> bool {
        self.take(1) == 1
    }
}

/// Bits needed to write every value below `n` (at least 1).
pub fn bits_for(n: u64) -> u32 {
    (64 - n.saturating_sub(1).leading_zeros()).max(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_round_trip_across_words() {
        let fields: Vec<(u64, u32)> = (0..200u64)
            .map(|k| {
                let bits = (k * 7 % 64 + 1) as u32;
                let v = k.wrapping_mul(0x9E37_79B9_7F4A_7C15);
                (if bits == 64 { v } else { v & ((1 << bits) - 1) }, bits)
            })
            .collect();
        let mut out = Vec::new();
        let mut w = BitWriter::new(&mut out);
        for &(v, b) in &fields {
            w.put(v, b);
        }
        w.finish();
        let total: u32 = fields.iter().map(|f| f.1).sum();
        assert_eq!(out.len(), words_for(total as usize));
        let mut r = BitReader::new(&out);
        for &(v, b) in &fields {
            assert_eq!(r.take(b), v, "{b} bits");
        }
        assert_eq!(r.take(7), 0, "zeros past the end");
    }

    #[test]
    fn widths_fit_their_values() {
        assert_eq!(bits_for(0), 1);
        assert_eq!(bits_for(1), 1);
        assert_eq!(bits_for(2), 1);
        assert_eq!(bits_for(3), 2);
        assert_eq!(bits_for(64), 6);
        assert_eq!(bits_for(65), 7);
    }
}
