//! The translation of a component into its Petri net
//! ([`genom_model::petri::PetriNet`]: the net's types, its priorities and
//! what its places and transitions stand for are the model's), from the
//! [`Component`] and its [`Behaviour`] (the per-service local machines), so
//! the codel steps are those of the one table every engine reads.
//! [`BuildPetriNet`] gives it as `PetriNet::build`.
//!
//! This file holds the builder, its basic helpers and the names of
//! positions. Its children add the places (`places`), the request chains
//! (`requests`) and the other transitions (`transitions`).

mod arcs;
mod places;
mod requests;
mod transitions;

pub(crate) use arcs::Arcs;

use genom_model::behaviour::{Behaviour, IDLE, PosId, Position, ServiceMachine};
use genom_model::component::{CodelId, Component, Idx, Ref, Service, ServiceId};
use genom_model::petri::{PetriNet, Place, PlaceId, PlaceKind, ServicePlaces, Transition};
use genom_model::span::Span;

/// The construction of a [`PetriNet`], as an associated function of the
/// net (bring the trait into scope and call `PetriNet::build(c, b)`).
pub trait BuildPetriNet {
    /// Builds the net of a component from its local machines.
    fn build(c: &Component, b: &Behaviour) -> Self;
}

impl BuildPetriNet for PetriNet {
    fn build(c: &Component, b: &Behaviour) -> PetriNet {
        let net = PetriNet::empty();
        let mut builder = Builder { c, b, net };
        builder.places();
        for s in c.services.ids() {
            builder.service_transitions(s);
        }
        builder.net
    }
}

struct Builder<'a> {
    c: &'a Component,
    b: &'a Behaviour,
    net: PetriNet,
}

/// The identifier of a position, unique within its service.
fn position_name(c: &Component, p: Position) -> String {
    let name = |k: CodelId| c.codels[k].name.name.clone();
    match p {
        Position::Idle => "idle".to_owned(),
        Position::Ready {
            codel,
            on_inter: None,
        } => format!("ready.{}", name(codel)),
        Position::Ready {
            codel,
            on_inter: Some(i),
        } => {
            format!("ready.{}.{}", name(codel), name(i))
        }
        Position::Running {
            codel,
            interrupted: false,
        } => format!("run.{}", name(codel)),
        Position::Running {
            codel,
            interrupted: true,
        } => format!("runint.{}", name(codel)),
        Position::StopReady { codel } => format!("stopready.{}", name(codel)),
        Position::StopRunning { codel } => format!("stoprun.{}", name(codel)),
    }
}

/// Where a service is, in words (`running goto`).
fn position_text(c: &Component, p: Position) -> String {
    let name = |k: CodelId| c.codels[k].name.name.as_str();
    match p {
        Position::Idle => "idle".to_owned(),
        Position::Ready {
            codel,
            on_inter: None,
        } => format!("at {} (ready)", name(codel)),
        Position::Ready {
            codel,
            on_inter: Some(i),
        } => {
            format!("at {} (ready, on-inter: {})", name(codel), name(i))
        }
        Position::Running {
            codel,
            interrupted: false,
        } => format!("running {}", name(codel)),
        Position::Running {
            codel,
            interrupted: true,
        } => {
            format!("running {} (interrupted)", name(codel))
        }
        Position::StopReady { codel } => format!("stopping at {} (ready)", name(codel)),
        Position::StopRunning { codel } => format!("stopping, running {}", name(codel)),
    }
}

impl<'a> Builder<'a> {
    fn name(&self, s: ServiceId) -> &'a str {
        &self.c.services[s].name.name
    }

    fn span(&self, s: ServiceId) -> Span {
        self.c.services[s].name.span
    }

    fn machine(&self, s: ServiceId) -> &'a ServiceMachine {
        self.b.machine(s)
    }

    fn sp(&self, s: ServiceId) -> &ServicePlaces {
        &self.net.services[s.index()]
    }

    fn pos(&self, s: ServiceId, p: PosId) -> PlaceId {
        self.sp(s).positions[usize::from(p)]
    }

    fn idle(&self, s: ServiceId) -> PlaceId {
        self.pos(s, IDLE)
    }

    fn add_place(&mut self, name: String, label: String, span: Span, kind: PlaceKind) -> PlaceId {
        let id = PlaceId::new(self.net.places.len());
        self.net.places.push(Place {
            name,
            label,
            span,
            kind,
        });
        self.net.initial.push(0);
        id
    }

    fn add(&mut self, t: Transition) {
        self.net.transitions.push(t);
    }

    fn mark(&mut self, p: PlaceId) {
        if let Some(n) = self.net.initial.get_mut(p.index()) {
            *n += 1;
        }
    }
}

/// The distinct `stops` targets of `s`, in order, with the span of each.
fn stop_targets(c: &Component, s: ServiceId) -> Vec<(ServiceId, Span)> {
    let mut out: Vec<(ServiceId, Span)> = Vec::new();
    for r in &c.services[s].stops {
        if !out.iter().any(|&(t, _)| t == r.id) {
            out.push((r.id, r.span));
        }
    }
    out
}

/// The services `T != s` that list `s` in `rule(T)`.
fn others(
    c: &Component,
    s: ServiceId,
    rule: fn(&Service) -> &Vec<Ref<ServiceId>>,
) -> Vec<ServiceId> {
    c.services
        .iter()
        .filter(|&(t, ts)| t != s && rule(ts).iter().any(|r| r.id == s))
        .map(|(t, _)| t)
        .collect()
}
