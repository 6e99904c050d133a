//! The control task's table: one row per function or attribute (the
//! services of the built-in `genom` interface share one row), with its
//! `validate` codel, its codels (in the order they run) and what it
//! throws, interrupts, waits for.

use genom_model::component::genom3::Genom3Info;
use genom_model::component::{Component, Service, ServiceId};

use super::{duration, info_of, relations};

/// The column titles.
pub(crate) const TABLE_HEADER: [&str; 5] = ["kind", "name", "validate", "codels", "notes"];

/// The functions and attributes, in source order.
#[derive(Debug, Clone, Default)]
pub(crate) struct ControlTable {
    /// One row per service: kind, name, validate, codels, notes.
    pub rows: Vec<[String; 5]>,
}

impl ControlTable {
    /// The table of a component's functions and attributes.
    pub(crate) fn build(c: &Component, g: &Genom3Info) -> ControlTable {
        let mut rows = Vec::new();
        let mut builtin: Vec<String> = Vec::new();
        for (sid, s) in c.services.iter() {
            let Some(info) = info_of(g, sid) else {
                continue;
            };
            if info.kind == "activity" {
                continue;
            }
            if info.interface.as_deref() == Some("genom") {
                builtin.push(s.name.name.clone());
                continue;
            }
            rows.push(row(c, g, sid, s, &info.kind));
        }
        if !builtin.is_empty() {
            rows.push([
                "function".to_owned(),
                builtin.join(", "),
                String::new(),
                String::new(),
                "built-in genom interface".to_owned(),
            ]);
        }
        ControlTable { rows }
    }
}

/// A codel's function, with its WCET when known.
fn codel_cell(c: &Component, g: &Genom3Info, k: genom_model::component::CodelId) -> String {
    let function = g
        .codels
        .iter()
        .find(|i| i.codel == k)
        .map_or_else(String::new, |i| i.fsm.function.name.clone());
    match c.codels.get(k).and_then(|k| k.wcet) {
        Some(w) => format!("{function} ({})", duration(w.ns)),
        None => function,
    }
}

fn row(c: &Component, g: &Genom3Info, sid: ServiceId, s: &Service, kind: &str) -> [String; 5] {
    let validate = s
        .control
        .filter(|&k| c.codels.get(k).is_some_and(|k| k.name.name == "validate"))
        .map_or_else(String::new, |k| codel_cell(c, g, k));
    let codels: Vec<String> = s
        .codels
        .iter()
        .filter(|&&k| c.codels.get(k).is_some_and(|k| k.name.name != "validate"))
        .map(|&k| codel_cell(c, g, k))
        .collect();
    let codels = match (codels.is_empty(), kind) {
        (true, "attribute") => "(copies its parameters)".to_owned(),
        (true, _) => "(none)".to_owned(),
        (false, _) => codels.join(", "),
    };
    [
        kind.to_owned(),
        s.name.name.clone(),
        validate,
        codels,
        relations(c, g, sid, s).join("; "),
    ]
}
