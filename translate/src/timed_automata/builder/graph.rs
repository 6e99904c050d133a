//! Adding processes, locations and edges to the network, and the guard
//! that every step but a watchdog probe's needs.

use genom_model::span::Span;
use genom_model::timed_automata::{
    Edge, Expr, Label, LabelKind, Location, LocationId, Process, ProcessId, ProcessKind,
};

use super::{Builder, sanitize};

impl<'a> Builder<'a> {
    pub(super) fn add_process(
        &mut self,
        name: &str,
        kind: ProcessKind,
        span: Span,
        description: String,
    ) -> ProcessId {
        let name = self.fresh(name);
        let id = ProcessId(u32::try_from(self.net.processes.len()).unwrap_or(u32::MAX));
        self.net.processes.push(Process {
            name,
            kind,
            locations: Vec::new(),
            edges: Vec::new(),
            span,
            description,
        });
        id
    }

    pub(super) fn add_location(&mut self, p: ProcessId, loc: Location) -> LocationId {
        self.add_labelled(p, loc, None)
    }

    pub(super) fn add_labelled(
        &mut self,
        p: ProcessId,
        loc: Location,
        kind: Option<LabelKind>,
    ) -> LocationId {
        let proc = &mut self.net.processes[p.0 as usize];
        let mut name = sanitize(&loc.name);
        let base = name.clone();
        let mut k = 2;
        while proc.locations.iter().any(|l| l.name == name) {
            name = format!("{base}_{k}");
            k += 1;
        }
        let id = LocationId(u32::try_from(proc.locations.len()).unwrap_or(u32::MAX));
        if let Some(kind) = kind {
            for l in &loc.labels {
                self.net.labels.push(Label {
                    name: l.clone(),
                    kind,
                    process: p,
                    location: id,
                });
            }
        }
        proc.locations.push(Location { name, ..loc });
        id
    }

    pub(super) fn add_edge(&mut self, p: ProcessId, e: Edge) {
        if e.guard.is_false() {
            return;
        }
        self.net.processes[p.0 as usize].edges.push(e);
    }

    pub(super) fn frozen_ok(&self) -> Expr {
        Expr::eq(Expr::var(self.net.frozen), Expr::int(0))
    }
}

pub(super) fn loc(name: &str, span: Span, description: &str) -> Location {
    Location {
        name: name.to_owned(),
        initial: false,
        urgent: false,
        committed: false,
        invariant: Vec::new(),
        labels: Vec::new(),
        span,
        description: description.to_owned(),
    }
}
