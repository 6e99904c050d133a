//! A transition of a Petri net made step by step, shared by both
//! languages' net builders: its identity, then its arcs of weight one (an
//! inhibitor arc once per place).

use genom_model::petri::{PlaceId, Transition, TransitionKind};
use genom_model::span::Span;

/// The builder methods of a [`Transition`].
pub(crate) trait Arcs: Sized {
    fn new(name: String, label: String, span: Span, priority: u8, kind: TransitionKind) -> Self;
    fn pre(self, p: PlaceId) -> Self;
    fn post(self, p: PlaceId) -> Self;
    fn read(self, p: PlaceId) -> Self;
    fn inhibit(self, places: impl IntoIterator<Item = PlaceId>) -> Self;
    /// Where what the transition stands for is written.
    fn at(self, span: Span) -> Self;
    fn pres(self, ps: impl IntoIterator<Item = PlaceId>) -> Self {
        ps.into_iter().fold(self, Arcs::pre)
    }
    fn posts(self, ps: impl IntoIterator<Item = PlaceId>) -> Self {
        ps.into_iter().fold(self, Arcs::post)
    }
    fn reads(self, ps: impl IntoIterator<Item = PlaceId>) -> Self {
        ps.into_iter().fold(self, Arcs::read)
    }
}

impl Arcs for Transition {
    fn new(name: String, label: String, span: Span, priority: u8, kind: TransitionKind) -> Self {
        Transition {
            name,
            label,
            span,
            priority,
            kind,
            pre: Vec::new(),
            post: Vec::new(),
            read: Vec::new(),
            inhibit: Vec::new(),
        }
    }

    fn pre(mut self, p: PlaceId) -> Self {
        self.pre.push((p, 1));
        self
    }

    fn post(mut self, p: PlaceId) -> Self {
        self.post.push((p, 1));
        self
    }

    fn read(mut self, p: PlaceId) -> Self {
        self.read.push((p, 1));
        self
    }

    fn inhibit(mut self, places: impl IntoIterator<Item = PlaceId>) -> Self {
        for p in places {
            if !self.inhibit.iter().any(|&(q, _)| q == p) {
                self.inhibit.push((p, 1));
            }
        }
        self
    }

    fn at(mut self, span: Span) -> Self {
        self.span = span;
        self
    }
}
