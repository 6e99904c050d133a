//! The clusters of a component: the connected components of its
//! `stops`/`delays`/`forbids` relation, explored independently (see
//! [`super::analysis`]).

use genom_model::component::{Component, Idx, ServiceId};

use crate::kernel::parts::Links;

/// The clusters: connected components of the `stops`/`delays`/`forbids`
/// relation, each sorted, in order of their first service.
pub fn clusters(c: &Component) -> Vec<Vec<ServiceId>> {
    let mut links = Links::new(c.services.len());
    for (s, svc) in c.services.iter() {
        for r in svc.stops.iter().chain(&svc.delays).chain(&svc.forbids) {
            links.link(s.index(), r.id.index());
        }
    }
    links
        .parts(c.services.ids().map(Idx::index))
        .into_iter()
        .map(|part| part.into_iter().map(<ServiceId as Idx>::new).collect())
        .collect()
}
