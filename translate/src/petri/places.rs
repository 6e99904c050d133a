//! The places of the net: per service its positions, pending flag, wait
//! and dropping places and request stages, and the initial marking.

use genom_model::behaviour::PosId;
use genom_model::component::{CodelId, ServiceId};
use genom_model::kinds::ServiceKind;
use genom_model::petri::{PlaceId, PlaceKind, ServicePlaces};

use super::{Builder, position_name, position_text, stop_targets};

impl<'a> Builder<'a> {
    pub(super) fn places(&mut self) {
        for s in self.c.services.ids() {
            let sp = self.service_places(s);
            self.net.services.push(sp);
        }
        let (init, span) = match self.c.init_service() {
            Some(i) => (Some(i), self.span(i)),
            None => (None, self.c.name.span),
        };
        let done = "initialisation has completed".to_owned();
        self.net.init_done = self.add_place("init_done".into(), done, span, PlaceKind::InitDone);
        let not_done = "initialisation has not completed".to_owned();
        self.net.init_not_done = self.add_place(
            "init_not_done".into(),
            not_done,
            span,
            PlaceKind::InitNotDone,
        );
        self.initial_marking(init.is_some());
    }

    pub(super) fn service_places(&mut self, s: ServiceId) -> ServicePlaces {
        let (name, span) = (self.name(s), self.span(s));
        let mut positions = Vec::new();
        for (k, &p) in self.machine(s).positions.iter().enumerate() {
            let pspan = p.codel().map_or(span, |k| self.c.codels[k].name.span);
            let label = format!("{name} {}", position_text(self.c, p));
            let kind = PlaceKind::Position(s, PosId::try_from(k).unwrap_or(PosId::MAX));
            positions.push(self.add_place(
                format!("{name}.{}", position_name(self.c, p)),
                label,
                pspan,
                kind,
            ));
        }
        let label = format!("{name} pending (acknowledged, not started)");
        let pending = self.add_place(
            format!("{name}.pending"),
            label,
            span,
            PlaceKind::Pending(s),
        );
        let mut waits = Vec::new();
        for t in stop_targets(self.c, s) {
            let (tn, tspan) = (self.name(t.0), t.1);
            let label = format!("pending {name} waits for the interrupted {tn} to end");
            let w = self.add_place(
                format!("{name}.wait.{tn}"),
                label,
                tspan,
                PlaceKind::Wait(s, t.0),
            );
            waits.push((t.0, w));
        }
        let dropping = (!waits.is_empty()).then(|| {
            let label = format!("the removed pending {name} discards its wait tokens");
            self.add_place(
                format!("{name}.dropping"),
                label,
                span,
                PlaceKind::Dropping(s),
            )
        });
        ServicePlaces {
            positions,
            pending,
            waits,
            dropping,
        }
    }

    /// Every service idle; without an init service, initialisation is done
    /// and the autos are active at their start codel (autos are never
    /// pending; one without start codel has completed at once).
    pub(super) fn initial_marking(&mut self, has_init: bool) {
        let started: Vec<(ServiceId, Option<PosId>)> = if has_init {
            Vec::new()
        } else {
            self.autos()
                .into_iter()
                .map(|a| (a, self.machine(a).start))
                .collect()
        };
        for s in self.c.services.ids() {
            let place = match started.iter().find(|(a, _)| *a == s) {
                Some(&(a, Some(p))) => self.pos(a, p),
                _ => self.idle(s),
            };
            self.mark(place);
        }
        let p = if has_init {
            self.net.init_not_done
        } else {
            self.net.init_done
        };
        self.mark(p);
    }

    pub(super) fn autos(&self) -> Vec<ServiceId> {
        self.c
            .services
            .iter()
            .filter(|(_, s)| s.kind == ServiceKind::Auto)
            .map(|(id, _)| id)
            .collect()
    }

    /// Every place that holds an instance of `t`: non-idle positions and
    /// the pending place.
    pub(super) fn instance_places(&self, t: ServiceId) -> Vec<PlaceId> {
        let sp = self.sp(t);
        sp.positions
            .iter()
            .skip(1)
            .copied()
            .chain([sp.pending])
            .collect()
    }

    /// Running places of `t` with their codel.
    pub(super) fn running_places(&self, t: ServiceId) -> Vec<(PlaceId, CodelId)> {
        let m = self.machine(t);
        let running = m
            .positions
            .iter()
            .enumerate()
            .filter(|(_, p)| p.is_running());
        running
            .filter_map(|(k, p)| Some((self.sp(t).positions[k], p.codel()?)))
            .collect()
    }
}
