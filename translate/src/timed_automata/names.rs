//! What the two network builders share: the empty network they start
//! from, and the identifiers they make (sanitised, fresh). The printers'
//! keyword renaming is the model's ([`genom_model::timed_automata::Renaming`]).

use std::collections::BTreeSet;

use genom_model::timed_automata::{Event, Expr, Network, VarId};

/// A network without clocks, variables or processes yet, with its events
/// (`(name, description)`), for the builders to fill.
pub(super) fn empty(name: String, unit_ns: u64, events: &[(&str, &str)]) -> Network {
    Network {
        name,
        unit_ns,
        horizon: 1,
        clocks: Vec::new(),
        vars: Vec::new(),
        events: events
            .iter()
            .map(|(n, d)| Event {
                name: (*n).to_owned(),
                description: (*d).to_owned(),
            })
            .collect(),
        processes: Vec::new(),
        syncs: Vec::new(),
        labels: Vec::new(),
        services: Vec::new(),
        frozen: VarId(0),
        urgency: Expr::FALSE,
    }
}

/// A name made of `want` (sanitised) not in `taken`, with a numeric suffix
/// when needed; `tmpN` names are kept for locals. Records it in `taken`.
pub(super) fn fresh(taken: &mut BTreeSet<String>, want: &str) -> String {
    let base = sanitize(want);
    let mut name = base.clone();
    let mut k = 2;
    while taken.contains(&name) || name.starts_with("tmp") && name[3..].parse::<u32>().is_ok() {
        name = format!("{base}_{k}");
        k += 1;
    }
    taken.insert(name.clone());
    name
}

/// `s` with every character but ASCII letters and digits replaced by `_`.
pub(super) fn sanitize(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect()
}
