//! The `tina` export: the component's Petri net ([`PetriNet::build`]) in the
//! textual `.net` format of the TINA toolbox (`tina`, `nd`, `sift`,
//! `selt`...), as a time Petri net with priorities.
//!
//! - `net NAME` is the component's name;
//! - `pl NAME (m)` declares every place, with its initial marking when not
//!   zero;
//! - `tr NAME I inputs -> outputs`: `I` is the static interval (below);
//!   inputs are the consumed places (`p`, `p*2`), read arcs `p?1` and
//!   inhibitor arcs `p?-1` (enabled while `p` holds fewer than 1 token);
//!   outputs are the produced places;
//! - `pr T1 T2 > T3 T4`: the priorities. genom-check's rule (a transition
//!   may fire only when no transition of a higher level is enabled) is
//!   written, for each level that has a higher one, as one `pr` declaration
//!   with every transition of the higher levels on the left and every
//!   transition of the level on the right, so no transitive closure is
//!   needed.
//!
//! Time intervals (TINA's semantics: a transition may fire between `a` and
//! `b` time units after it last became enabled, and time cannot pass beyond
//! the upper bound of an enabled transition). One unit is the timed
//! engine's unit ([`Network::unit_ns`], the GCD of the component's
//! durations), given in the header:
//!
//! - the `finish` transitions of a codel with a WCET of `w` units:
//!   `[0,w]` — the codel ends at most `w` after its thread began it (they
//!   are enabled exactly while its running place is marked);
//! - every transition above priority 0 (drop, the request chain, clear,
//!   start): `[0,0]` — urgent, they take no time, as in the engine;
//! - everything else (client requests, codel begins, finishes of codels
//!   without WCET, watchdogs): `[0,w[`, untimed.
//!
//! Thread periods, wake-ups, lock waits and `max-time` deadlines are not
//! expressed: those transitions stay untimed, so the timed net allows every
//! behaviour of the engine (an over-approximation of it) while removing the
//! untimed behaviours where a codel outlives its WCET. One more
//! over-approximation: a codel interrupted while it runs moves to its
//! `runint` place, which restarts the clock of its finish transitions (at
//! most `2w` in all, as a codel is interrupted at most once).
//!
//! Names are the net's names. A name that is not a plain TINA identifier
//! (letters, digits, primes, `_`, starting with a letter, not a keyword) is
//! written between braces (`{moveDistance.run.goto}`), with `{`, `}` and `\`
//! escaped; nothing is renamed unless a name cannot be written even so (a
//! line break) or clashes, and then the header lists the renamings.
//! Labels and source locations are in `#` comment lines.

use std::collections::BTreeSet;
use std::fmt::Write as _;

use genom_model::behaviour::Behaviour;
use genom_model::component::{Component, Idx};
use genom_model::petri::{PRIORITY_STEP, PetriNet, PlaceId, Transition, TransitionKind};
use genom_model::timed_automata::Network;
use genom_translate::timed_automata::BuildNetwork;

use crate::pnml::{NetOf, location, tool_version};
use crate::{ExportError, ExportInput, Exported};

/// Exports the component's Petri net as a TINA `.net` file.
pub fn export(input: &ExportInput<'_>) -> Result<Exported, ExportError> {
    let c = input.component;
    let of = NetOf::of(c);
    let net = &of.net;
    let behaviour = Behaviour::new(c);
    let mut names = Names::default();
    let net_name = names.take(&c.name.name);
    let places: Vec<String> = net.places.iter().map(|p| names.take(&p.name)).collect();
    let transitions: Vec<String> = net
        .transitions
        .iter()
        .map(|t| names.take(&t.name))
        .collect();

    // A GenoM3 net is untimed: its steps `[0,w[`, the rest urgent.
    let timing = c.genom3.is_none().then(|| Timing::new(c, &behaviour));
    let mut out = String::new();
    match &timing {
        Some(timing) => header(&mut out, input, &of, &tool_version(input), timing.unit_ns),
        None => genom3_header(&mut out, input, &of, &tool_version(input)),
    }
    if names.renamed.is_empty() {
        out.push_str("# Renamed: none (every name is the net's own name).\n");
    } else {
        out.push_str("# Renamed (genom-check name -> name in this file):\n");
        for (from, to) in &names.renamed {
            let _ = writeln!(out, "#   {} -> {to}", line(from));
        }
    }
    let _ = writeln!(out, "\nnet {net_name}\n");

    out.push_str("# ---- places: (initial marking) ----\n");
    for (k, place) in net.places.iter().enumerate() {
        let _ = writeln!(out, "# {}{}", line(&place.label), at(input, place.span));
        let marking = net.initial.get(k).copied().unwrap_or(0);
        if marking > 0 {
            let _ = writeln!(out, "pl {} ({marking})", places[k]);
        } else {
            let _ = writeln!(out, "pl {}", places[k]);
        }
    }

    out.push_str("\n# ---- transitions: (interval) inputs -> outputs ----\n");
    for (k, t) in net.transitions.iter().enumerate() {
        let _ = writeln!(
            out,
            "# {} (priority {} {}){}",
            line(&t.label),
            t.priority,
            of.level_name(t.priority),
            at(input, t.span)
        );
        let interval = match &timing {
            Some(timing) => timing.interval(t),
            None => untimed(t),
        };
        let _ = writeln!(
            out,
            "{}",
            transition(t, &transitions[k], &interval, &places)
        );
    }

    out.push_str("\n# ---- priorities: higher levels first ----\n");
    for &(level, name, _) in of.levels.iter().rev() {
        let lower: Vec<&str> = members(net, &transitions, |p| p == level);
        let higher: Vec<&str> = members(net, &transitions, |p| p > level);
        if lower.is_empty() || higher.is_empty() {
            continue;
        }
        let _ = writeln!(out, "# level {level} ({name}) yields to every higher level");
        let _ = writeln!(out, "pr {} > {}", higher.join(" "), lower.join(" "));
    }
    Ok(Exported::single(out))
}

/// The first two lines: the component, the tool, the net's size and the
/// verification.
fn opening(out: &mut String, input: &ExportInput<'_>, net: &PetriNet, version: &str) {
    let _ = writeln!(
        out,
        "# The Petri net of component {}, generated by genom-check {}.",
        line(&input.component.name.name),
        line(version)
    );
    let _ = writeln!(
        out,
        "# {} places, {} transitions. Verification: {}.",
        net.places.len(),
        net.transitions.len(),
        if input.verification.verified {
            "verified (no error, complete exploration)"
        } else {
            "NOT verified"
        }
    );
}

/// The priority levels, then how to read arcs and how to analyse.
fn closing(out: &mut String, of: &NetOf) {
    for (level, name, what) in of.levels {
        let _ = writeln!(out, "#   {level} {name}: {what}");
    }
    out.push_str(
        "#\n\
         # Arcs: p?1 read arc (p must hold a token, kept), p?-1 inhibitor arc (p must\n\
         # be empty). Names are genom-check's; those that are not plain identifiers are\n\
         # between braces.\n\
         #\n\
         # Analyse: tina -R FILE.net (marking graph, time ignored)\n\
         #          tina FILE.net    (state class graph, with the intervals)\n\
         #          nd FILE.net      (edit, draw, simulate)\n",
    );
}

/// The header of a GenoM3 component's (untimed) net.
fn genom3_header(out: &mut String, input: &ExportInput<'_>, of: &NetOf, version: &str) {
    opening(out, input, &of.net, version);
    out.push_str(
        "#\n\
         # GenoM3's untimed semantics (docs/genom3-semantics.md section 14, one\n\
         # instance per activity; docs/exports/petri-nets.md). Its reachable stable\n\
         # markings (no transition above priority 0 enabled) are the states after\n\
         # each step. Untimed: [0,w[ on the steps, [0,0] on every transition above\n\
         # priority 0 (urgent). Priorities (pr declarations at the end): a transition\n\
         # may fire only when no transition of a higher level is enabled. Levels:\n",
    );
    closing(out, of);
}

/// The interval of a transition of an untimed net.
fn untimed(t: &Transition) -> String {
    if t.priority > PRIORITY_STEP {
        "[0,0]".to_owned()
    } else {
        "[0,w[".to_owned()
    }
}

fn header(out: &mut String, input: &ExportInput<'_>, of: &NetOf, version: &str, unit_ns: u64) {
    opening(out, input, &of.net, version);
    out.push_str(
        "#\n\
         # The semantics of the component (LANGUAGE.md section 3, docs/semantics.md\n\
         # section 4) as a time Petri net. Ignoring the intervals (tina -R), its\n\
         # reachable stable markings (no transition above priority 0 enabled) are\n\
         # exactly the configurations genom-check explores.\n\
         #\n",
    );
    let _ = writeln!(
        out,
        "# Time: 1 unit = {} ({unit_ns} ns). Intervals count from the instant the\n\
         # transition became enabled: [0,w] on the finish transitions of a codel\n\
         # with a WCET of w units (it ends at most w after it began); [0,0] on every\n\
         # transition above priority 0 (urgent, no time passes); [0,w[ (untimed)\n\
         # elsewhere: requests, codel begins, codels without WCET, watchdogs. Thread\n\
         # periods and max-times are not expressed (see docs/exports/petri-nets.md).\n\
         #\n\
         # Priorities (pr declarations at the end): a transition may fire only when no\n\
         # transition of a higher level is enabled. Levels:",
        crate::dot::duration(unit_ns)
    );
    closing(out, of);
}

/// The `tr` declaration of a transition.
fn transition(t: &Transition, name: &str, interval: &str, places: &[String]) -> String {
    let place = |p: PlaceId| places[p.index()].as_str();
    let mut inputs: Vec<String> = Vec::new();
    for &(p, w) in &t.pre {
        inputs.push(weighted(place(p), w));
    }
    for &(p, w) in &t.read {
        inputs.push(format!("{}?{w}", place(p)));
    }
    for &(p, w) in &t.inhibit {
        inputs.push(format!("{}?-{w}", place(p)));
    }
    let outputs: Vec<String> = t.post.iter().map(|&(p, w)| weighted(place(p), w)).collect();
    let mut s = format!("tr {name} {interval}");
    for i in &inputs {
        s.push(' ');
        s.push_str(i);
    }
    s.push_str(" ->");
    for o in &outputs {
        s.push(' ');
        s.push_str(o);
    }
    s
}

/// The time intervals of the transitions.
struct Timing<'a> {
    c: &'a Component,
    b: &'a Behaviour,
    /// Nanoseconds per unit.
    unit_ns: u64,
}

impl<'a> Timing<'a> {
    fn new(c: &'a Component, b: &'a Behaviour) -> Self {
        let unit_ns = Network::build(c, b).unit_ns.max(1);
        Timing { c, b, unit_ns }
    }

    /// The static interval of `t` (see the module documentation).
    fn interval(&self, t: &Transition) -> String {
        if t.priority > PRIORITY_STEP {
            return "[0,0]".to_owned();
        }
        match self.finish_wcet(t) {
            Some(ns) => format!("[0,{}]", ns / self.unit_ns),
            None => "[0,w[".to_owned(),
        }
    }

    /// The WCET of the codel a finish transition ends, if it has one.
    fn finish_wcet(&self, t: &Transition) -> Option<u64> {
        let TransitionKind::Finish(s, p, _) = t.kind else {
            return None;
        };
        let position = self.b.machine(s).positions.get(usize::from(p))?;
        let codel = position.codel()?;
        self.c.codels[codel].wcet.map(|w| w.ns)
    }
}

fn weighted(place: &str, w: u32) -> String {
    if w == 1 {
        place.to_owned()
    } else {
        format!("{place}*{w}")
    }
}

fn members<'a>(net: &PetriNet, names: &'a [String], keep: impl Fn(u8) -> bool) -> Vec<&'a str> {
    net.transitions
        .iter()
        .zip(names)
        .filter(|(t, _)| keep(t.priority))
        .map(|(_, n)| n.as_str())
        .collect()
}

/// ` (file.gen:12:5)` or nothing.
fn at(input: &ExportInput<'_>, span: genom_model::Span) -> String {
    location(input.sources, span).map_or_else(String::new, |(file, line_no, column)| {
        format!(" ({file}:{line_no}:{column})")
    })
}

/// Text fit for one comment line.
fn line(s: &str) -> String {
    s.replace(['\n', '\r'], " ")
}

/// TINA names, unique in the file, with the renamings made.
#[derive(Debug, Default)]
struct Names {
    used: BTreeSet<String>,
    renamed: Vec<(String, String)>,
}

impl Names {
    /// The TINA spelling of `name`: itself when a plain identifier, else
    /// between braces; renamed when it has a line break or clashes.
    fn take(&mut self, name: &str) -> String {
        let mut base: String = name.replace(['\n', '\r'], "_");
        if base.is_empty() {
            base.push('_');
        }
        let mut candidate = base.clone();
        let mut n = 2;
        while self.used.contains(&candidate) {
            candidate = format!("{base}_{n}");
            n += 1;
        }
        self.used.insert(candidate.clone());
        let written = quote(&candidate);
        if candidate != name {
            self.renamed.push((name.to_owned(), written.clone()));
        }
        written
    }
}

/// Keywords of the `.net` format, which a plain name must not be.
const KEYWORDS: [&str; 6] = ["net", "tr", "pl", "pr", "lb", "nt"];

/// Whether `name` is a plain TINA identifier (ANAME).
pub(crate) fn is_plain(name: &str) -> bool {
    name.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '\'')
        && !KEYWORDS.iter().any(|k| k.eq_ignore_ascii_case(name))
}

/// `name` as a TINA name: plain, or between braces with `{`, `}` and `\`
/// escaped.
pub(crate) fn quote(name: &str) -> String {
    if is_plain(name) {
        return name.to_owned();
    }
    let mut out = String::with_capacity(name.len() + 2);
    out.push('{');
    for c in name.chars() {
        if matches!(c, '{' | '}' | '\\') {
            out.push('\\');
        }
        out.push(c);
    }
    out.push('}');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_names_and_quoting() {
        assert_eq!(quote("init_done"), "init_done");
        assert_eq!(quote("moveDistance.run.goto"), "{moveDistance.run.goto}");
        assert_eq!(quote("pr"), "{pr}");
        assert_eq!(quote("_x"), "{_x}");
        assert_eq!(quote("a{b}\\"), "{a\\{b\\}\\\\}");
    }

    #[test]
    fn clashes_and_line_breaks_are_renamed() {
        let mut names = Names::default();
        assert_eq!(names.take("a.b"), "{a.b}");
        assert_eq!(names.take("a.b"), "{a.b_2}");
        assert_eq!(names.take("x\ny"), "x_y");
        assert_eq!(names.renamed.len(), 2);
    }
}
