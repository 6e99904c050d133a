//! Which codels exclude each other: for every codel of a member and every
//! member's control codel, the set of codels whose structure accesses
//! conflict with it, as a bit set over codel ids, computed once per system
//! so that asking whether a running codel holds a lock is one bit test.

use genom_model::component::{CodelId, StructureId};

use super::conflict;

/// Above this many codels with structure accesses, the sets are not built
/// (their size is quadratic) and conflicts are computed from the accesses.
const MAX_CODELS: usize = 4096;

/// A codel, or the control codel of a member, asking for its locks.
#[derive(Debug, Clone, Copy)]
pub(super) enum Who {
    /// A codel of a member.
    Codel(CodelId),
    /// The control codel of member `i`.
    Control(usize),
}

/// The conflict sets of a system.
#[derive(Debug, Default)]
pub(super) struct Locks {
    /// Per codel id: the codels it conflicts with.
    codels: Vec<Box<[u64]>>,
    /// Per member: the codels its control codel conflicts with.
    controls: Vec<Box<[u64]>>,
}

impl Locks {
    /// The sets, given each codel's accesses (empty for codels of other
    /// services) and each member's control accesses; `None` when too many.
    pub(super) fn new(
        codel_structures: &[Vec<(StructureId, bool)>],
        controls: &[&[(StructureId, bool)]],
    ) -> Option<Self> {
        let using: Vec<usize> = (0..codel_structures.len())
            .filter(|&k| !codel_structures[k].is_empty())
            .collect();
        if using.len() > MAX_CODELS {
            return None;
        }
        let words = codel_structures.len().div_ceil(64);
        let set = |uses: &[(StructureId, bool)]| -> Box<[u64]> {
            if uses.is_empty() {
                return Box::default();
            }
            let mut bits = vec![0u64; words];
            for &b in &using {
                if conflict(uses, &codel_structures[b]) {
                    bits[b / 64] |= 1 << (b % 64);
                }
            }
            bits.into_boxed_slice()
        };
        Some(Locks {
            codels: codel_structures.iter().map(|u| set(u)).collect(),
            controls: controls.iter().map(|u| set(u)).collect(),
        })
    }

    /// Whether `who` conflicts with `codel`.
    pub(super) fn conflicts(&self, who: Who, codel: CodelId) -> bool {
        let set = match who {
            Who::Codel(k) => self.codels.get(k.0 as usize),
            Who::Control(i) => self.controls.get(i),
        };
        let b = codel.0 as usize;
        set.and_then(|s| s.get(b / 64))
            .is_some_and(|w| w >> (b % 64) & 1 == 1)
    }
}
