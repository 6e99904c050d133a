//! The clusters of a component: the connected components of its
//! `stops`/`delays`/`forbids` relation, explored independently (see
//! [`super::analysis`]).

use std::collections::BTreeMap;

use genom_model::component::{Component, ServiceId};

/// The clusters: connected components of the `stops`/`delays`/`forbids`
/// relation, each sorted, in order of their first service.
pub fn clusters(c: &Component) -> Vec<Vec<ServiceId>> {
    let n = c.services.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(parent: &mut [usize], x: usize) -> usize {
        let mut r = x;
        while parent[r] != r {
            r = parent[r];
        }
        let mut y = x;
        while parent[y] != r {
            let next = parent[y];
            parent[y] = r;
            y = next;
        }
        r
    }
    for (s, svc) in c.services.iter() {
        for r in svc.stops.iter().chain(&svc.delays).chain(&svc.forbids) {
            let (a, b) = (
                find(&mut parent, s.0 as usize),
                find(&mut parent, r.id.0 as usize),
            );
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut groups: BTreeMap<usize, Vec<ServiceId>> = BTreeMap::new();
    for s in c.services.ids() {
        let root = find(&mut parent, s.0 as usize);
        groups.entry(root).or_default().push(s);
    }
    groups.into_values().collect()
}
