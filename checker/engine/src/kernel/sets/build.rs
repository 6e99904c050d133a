//! A BDD built bottom-up from a batch of packed states: the keys sorted in
//! the variables' order, then one node per distinct prefix that branches,
//! shared through a unique table, so the result is reduced and no BDD
//! operation runs per state.

use biodivine_lib_bdd::{Bdd, BddNode, BddPointer, BddVariable, BddVariableSet};
use rustc_hash::FxHashMap;

/// A batch of packed states, each stored as its words with their bits
/// reversed, so that comparing keys word by word compares them in the
/// order of the BDD variables (variable `k` is bit `k % 64` of word
/// `k / 64`; variable 0 is the root's).
#[derive(Debug)]
pub(super) struct Keys {
    width: usize,
    bits: usize,
    flat: Vec<u64>,
}

/// The empty set over `bits` variables.
pub(super) fn empty(bits: usize) -> Bdd {
    BddVariableSet::new_anonymous(var_count(bits)).mk_false()
}

/// The number of variables as the library counts them.
fn var_count(bits: usize) -> u16 {
    u16::try_from(bits).unwrap_or(u16::MAX)
}

impl Keys {
    /// An empty batch of states of `width` words, `bits` of them used.
    pub(super) fn new(width: usize, bits: usize) -> Self {
        Keys {
            width,
            bits,
            flat: Vec::new(),
        }
    }

    /// Adds a packed state.
    pub(super) fn push(&mut self, words: &[u64]) {
        self.flat.extend(words.iter().map(|w| w.reverse_bits()));
    }

    /// States in the batch (with repeats).
    pub(super) fn len(&self) -> usize {
        self.flat.len() / self.width.max(1)
    }

    /// The set of the batch's states; the batch is emptied.
    pub(super) fn take_bdd(&mut self) -> Bdd {
        let width = self.width.max(1);
        let mut rows: Vec<&[u64]> = self.flat.chunks_exact(width).collect();
        rows.sort_unstable();
        rows.dedup();
        let bdd = Builder::new(self.bits).set(&rows);
        self.flat.clear();
        bdd
    }
}

/// The nodes of a BDD under construction.
struct Builder {
    bits: usize,
    nodes: Vec<BddNode>,
    unique: FxHashMap<(u16, u32, u32), u32>,
}

impl Builder {
    fn new(bits: usize) -> Self {
        let n = var_count(bits);
        Builder {
            bits,
            nodes: vec![BddNode::mk_zero(n), BddNode::mk_one(n)],
            unique: FxHashMap::default(),
        }
    }

    /// The BDD of the sorted, distinct `rows`.
    fn set(mut self, rows: &[&[u64]]) -> Bdd {
        if rows.is_empty() {
            return empty(self.bits);
        }
        let root = self.node(rows, 0);
        // The last node made is the root (the low branch is built first
        // and the high one, when equal, makes no node); the library reads
        // the root there.
        let last = self.nodes.len() - 1;
        debug_assert_eq!(root as usize, last, "root is the last node");
        if root == 1 {
            self.nodes.truncate(2);
        }
        Bdd::from_nodes(&self.nodes).unwrap_or_else(|_| empty(self.bits))
    }

    /// The node of the `rows` (sharing variables `0..var`) from `var` on.
    fn node(&mut self, rows: &[&[u64]], var: usize) -> u32 {
        if var >= self.bits {
            return 1;
        }
        let (word, shift) = (var / 64, 63 - var % 64);
        let split = rows.partition_point(|r| (r[word] >> shift) & 1 == 0);
        let low = match split {
            0 => 0,
            _ => self.node(&rows[..split], var + 1),
        };
        let high = match split == rows.len() {
            true => 0,
            false => self.node(&rows[split..], var + 1),
        };
        if low == high {
            return low;
        }
        let v = var_count(var);
        let next = self.nodes.len() as u32;
        *self.unique.entry((v, low, high)).or_insert_with(|| {
            self.nodes.push(BddNode::mk_node(
                BddVariable::from_index(usize::from(v)),
                BddPointer::from_index(low as usize),
                BddPointer::from_index(high as usize),
            ));
            next
        })
    }
}
