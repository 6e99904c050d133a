//! The replayed state: each service's instances (pending, active or
//! stopping) and whether initialisation is done.

use std::collections::BTreeSet;

use genom_model::component::{CodelId, Component, ServiceId};

/// Identity of one instance within a replay.
pub type InstanceId = u32;

/// Where an instance is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Phase {
    /// Acknowledged, not started; still waiting for these interrupted
    /// instances to end (step 7b).
    Pending {
        /// Instances (of services in its `stops`) it waits for.
        waits_for: BTreeSet<InstanceId>,
    },
    /// Active at `codel`.
    Active {
        /// The next codel (ready) or the running one.
        codel: CodelId,
        /// Its thread runs `codel` now.
        running: bool,
        /// The codel it ran last (`None` before its start codel ran).
        last_ran: Option<CodelId>,
        /// Interrupted while `codel` runs.
        interrupted: bool,
    },
    /// Interrupted, following its inter codels.
    Stopping {
        /// The next codel (ready) or the running one.
        codel: CodelId,
        /// Its thread runs `codel` now.
        running: bool,
    },
}

/// One service instance.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Instance {
    /// Its identity in this replay.
    pub id: InstanceId,
    /// Where it is.
    pub phase: Phase,
    /// Interrupted by the max-time watchdog (it will reply `TIMEOUT`).
    pub by_watchdog: bool,
}

impl Instance {
    /// True while acknowledged and not started.
    pub fn is_pending(&self) -> bool {
        matches!(self.phase, Phase::Pending { .. })
    }

    /// The codel it is at, if started.
    pub fn codel(&self) -> Option<CodelId> {
        match self.phase {
            Phase::Pending { .. } => None,
            Phase::Active { codel, .. } | Phase::Stopping { codel, .. } => Some(codel),
        }
    }

    /// The codel its thread runs now, if any.
    pub fn running(&self) -> Option<CodelId> {
        match self.phase {
            Phase::Active {
                codel,
                running: true,
                ..
            }
            | Phase::Stopping {
                codel,
                running: true,
            } => Some(codel),
            _ => None,
        }
    }

    /// True once interrupted: stopping, or running with the interrupt noted.
    pub fn is_interrupted(&self) -> bool {
        matches!(
            self.phase,
            Phase::Stopping { .. }
                | Phase::Active {
                    interrupted: true,
                    ..
                }
        )
    }
}

/// The replayed state of the component.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct State {
    /// The `init` service has completed successfully (always true without
    /// one).
    pub init_done: bool,
    /// The instances of each service, by service index.
    pub instances: Vec<Vec<Instance>>,
    pub(super) next_id: InstanceId,
}

/// One instance as compared between the two ends of a loop: identities
/// are forgotten; an active instance between codels is described by what
/// an interrupt would do to it.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Shape {
    Pending(Vec<(ServiceId, Option<CodelId>)>),
    Ready {
        codel: CodelId,
        interrupt_leads_to: Option<CodelId>,
    },
    Running {
        codel: CodelId,
        interrupted: bool,
        by_watchdog: bool,
    },
    Stopping {
        codel: CodelId,
        running: bool,
        by_watchdog: bool,
    },
}

impl State {
    /// The instances of `s`.
    pub fn of(&self, s: ServiceId) -> &[Instance] {
        self.instances.get(s.0 as usize).map_or(&[], Vec::as_slice)
    }

    /// The pending instance of `s`, if any.
    pub fn pending(&self, s: ServiceId) -> Option<&Instance> {
        self.of(s).iter().find(|i| i.is_pending())
    }

    /// The started (active or stopping) instance of `s`, if any.
    pub fn started(&self, s: ServiceId) -> Option<&Instance> {
        self.of(s).iter().find(|i| !i.is_pending())
    }

    pub(super) fn has_instance(&self, s: ServiceId) -> bool {
        !self.of(s).is_empty()
    }

    pub(super) fn find(&self, id: InstanceId) -> Option<(ServiceId, &Instance)> {
        self.instances.iter().enumerate().find_map(|(k, v)| {
            let s = ServiceId(u32::try_from(k).ok()?);
            v.iter().find(|i| i.id == id).map(|i| (s, i))
        })
    }

    pub(super) fn shape(&self, c: &Component) -> Vec<Vec<Shape>> {
        let owner = |id: InstanceId| self.find(id).map(|(s, i)| (s, i.codel()));
        self.instances
            .iter()
            .map(|v| {
                let mut shapes: Vec<Shape> = v
                    .iter()
                    .map(|i| match &i.phase {
                        Phase::Pending { waits_for } => {
                            let mut w: Vec<_> =
                                waits_for.iter().filter_map(|&id| owner(id)).collect();
                            w.sort();
                            Shape::Pending(w)
                        }
                        &Phase::Active {
                            codel,
                            running: false,
                            last_ran,
                            ..
                        } => Shape::Ready {
                            codel,
                            interrupt_leads_to: interrupt_target(c, last_ran),
                        },
                        &Phase::Active {
                            codel,
                            running: true,
                            interrupted,
                            ..
                        } => Shape::Running {
                            codel,
                            interrupted,
                            by_watchdog: i.by_watchdog,
                        },
                        &Phase::Stopping { codel, running } => Shape::Stopping {
                            codel,
                            running,
                            by_watchdog: i.by_watchdog,
                        },
                    })
                    .collect();
                shapes.sort();
                shapes
            })
            .collect()
    }

    pub(super) fn describe(&self, c: &Component) -> String {
        let mut parts = Vec::new();
        for (k, v) in self.instances.iter().enumerate() {
            let Some(svc) = u32::try_from(k)
                .ok()
                .and_then(|k| c.services.get(ServiceId(k)))
            else {
                continue;
            };
            for i in v {
                let what = match &i.phase {
                    Phase::Pending { .. } => "pending".to_owned(),
                    Phase::Active {
                        codel,
                        running,
                        interrupted,
                        ..
                    } => format!(
                        "active {} `{}`{}",
                        if *running { "running" } else { "at" },
                        c.codels[*codel].name.name,
                        if *interrupted { " (interrupted)" } else { "" }
                    ),
                    Phase::Stopping { codel, running } => {
                        format!(
                            "stopping, {} `{}`",
                            if *running { "running" } else { "at" },
                            c.codels[*codel].name.name
                        )
                    }
                };
                parts.push(format!("`{}` {what}", svc.name.name));
            }
        }
        if parts.is_empty() {
            "no instance".to_owned()
        } else {
            parts.join(", ")
        }
    }
}

/// The inter codel an interrupt leads to for an active instance between
/// codels: the `on-inter` of the codel it ran last (none before its start
/// codel ran: it then ends at once).
pub(super) fn interrupt_target(c: &Component, last_ran: Option<CodelId>) -> Option<CodelId> {
    last_ran.and_then(|k| c.codels[k].on_inter.map(|r| r.id))
}
