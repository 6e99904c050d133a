//! Splitting into parts, for every semantics: each language gives its
//! *interference relation* (which items — services, tasks — may influence
//! one another's steps) as links, and a part is a connected component of
//! it. Parts are explored alone; that this is exact is each semantics'
//! argument (the dialect's clusters, GenoM3's untimed parts and timed
//! groups), the computation is this one.

use std::collections::BTreeMap;

use petgraph::unionfind::UnionFind;

/// Links between `n` items; read as connected components.
#[derive(Debug, Clone)]
pub struct Links {
    sets: UnionFind<usize>,
    n: usize,
}

impl Links {
    /// `n` items, none linked.
    pub fn new(n: usize) -> Self {
        Links {
            sets: UnionFind::new(n),
            n,
        }
    }

    /// Links items `a` and `b` (ignored when either is out of range).
    pub fn link(&mut self, a: usize, b: usize) {
        if a < self.n && b < self.n {
            self.sets.union(a, b);
        }
    }

    /// Whether `a` and `b` are in the same part.
    pub fn same(&self, a: usize, b: usize) -> bool {
        a < self.n && b < self.n && self.sets.equiv(a, b)
    }

    /// The parts of `items` (each in the order given), in the order of
    /// their first item; items out of range are left out.
    pub fn parts(&self, items: impl IntoIterator<Item = usize>) -> Vec<Vec<usize>> {
        let mut index: BTreeMap<usize, usize> = BTreeMap::new();
        let mut out: Vec<Vec<usize>> = Vec::new();
        for x in items.into_iter().filter(|&x| x < self.n) {
            let k = *index.entry(self.sets.find(x)).or_insert_with(|| {
                out.push(Vec::new());
                out.len() - 1
            });
            out[k].push(x);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_are_connected_components_in_order_of_first_item() {
        let mut l = Links::new(6);
        l.link(4, 1);
        l.link(1, 3);
        l.link(0, 5);
        l.link(2, 9);
        assert!(l.same(4, 3) && !l.same(0, 1));
        assert_eq!(l.parts(0..6), [vec![0, 5], vec![1, 3, 4], vec![2]]);
        assert_eq!(l.parts([3, 2, 1]), [vec![3, 1], vec![2]]);
    }
}
