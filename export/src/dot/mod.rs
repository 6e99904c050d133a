//! The `dot` export: Graphviz pictures of the component, for people.
//!
//! The file is **one** `digraph` (so that `dot -Tsvg file.dot -o file.svg`
//! gives one SVG document) made of clusters:
//!
//! - `cluster_overview`: the component overview. One cluster per thread
//!   (label: name, period or `aperiodic`, priority) holding the services
//!   whose codels it runs, and one for the control thread holding the
//!   services without a start codel (they run entirely in the control
//!   thread). Edges between services: `stops` (solid red, filled arrow),
//!   `delays` (dashed orange, open arrow), `forbids` (dotted blue, bar
//!   head), each labelled, with a legend cluster;
//! - `cluster_machine_S` for each service `S`: its codel state machine. The
//!   request (black dot) goes to the control codel (if any), which accepts
//!   into the start codel; start, exec and inter codels are boxes (green,
//!   blue, orange) labelled with their kind and WCET; `end` (double circle)
//!   and each report (red octagon) are terminal nodes; `next` edges are
//!   solid, `on-inter` edges dashed. A service without start codel goes
//!   from its request straight to `end` ("completes at once");
//! - `cluster_machine_legend`: the node and edge styles of the machines.
//!
//! Invisible edges from the overview to each machine put the machines under
//! the overview. The same [`Diagrams`] model feeds the `svg` export, so both
//! pictures show the same things.
//!
//! A GenoM3 component is drawn in GenoM3's words instead (tasks, permanent
//! codels, activities, `pause::`, `ether`, the control task's functions and
//! attributes): see [`genom3`].

use std::fmt::Write as _;

use genom_model::component::{CodelId, Component, Outcome, Service, ServiceId};
use genom_model::kinds::{CodelKind, ServiceKind};

use crate::{ExportError, ExportInput, Exported};

pub(crate) mod genom3;
mod text;

use text::*;

/// Exports the component's diagrams as one Graphviz digraph.
pub fn export(input: &ExportInput<'_>) -> Result<Exported, ExportError> {
    let version = crate::pnml::tool_version(input);
    let text = match &input.component.genom3 {
        Some(g) => genom3::render(&genom3::G3Diagrams::build(input.component, g), &version),
        None => render(&Diagrams::build(input.component), &version),
    };
    let verified = input.verification.verified;
    Ok(Exported::single(crate::mark_unverified(
        text,
        verified,
        ("// ", ""),
    )))
}

// ------------------------------------------------------------------------
// The model shared with the SVG export.

/// Everything drawn: the overview and one machine per service.
#[derive(Debug, Clone)]
pub(crate) struct Diagrams {
    /// The component's name.
    pub component: String,
    /// The component overview.
    pub overview: Overview,
    /// One machine per service, in source order.
    pub machines: Vec<Machine>,
}

/// The component overview.
#[derive(Debug, Clone)]
pub(crate) struct Overview {
    /// Thread groups: the control thread first, then the threads in source
    /// order.
    pub groups: Vec<Group>,
    /// Services in source order.
    pub services: Vec<ServiceBox>,
    /// `stops`, `delays` and `forbids` edges, by service then rule then
    /// target, in source order.
    pub edges: Vec<RuleEdge>,
}

/// A thread and the services it runs.
#[derive(Debug, Clone)]
pub(crate) struct Group {
    /// A unique identifier (`thread.motionTask`, `thread.control`).
    pub id: String,
    /// `thread motionTask` or `control thread`.
    pub title: String,
    /// `period 1 s, priority 0`, `aperiodic, priority 0`, or what the control
    /// thread does.
    pub detail: String,
    /// Fill colour of its services.
    pub color: &'static str,
    /// Indices in [`Overview::services`].
    pub services: Vec<usize>,
}

/// A service in the overview.
#[derive(Debug, Clone)]
pub(crate) struct ServiceBox {
    /// A unique identifier (`service.moveDistance`).
    pub id: String,
    /// The service's name.
    pub name: String,
    /// Lines under the name (kind, thread, max-time).
    pub details: Vec<String>,
    /// Index in [`Overview::groups`].
    pub group: usize,
}

/// A `stops`, `delays` or `forbids` rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Rule {
    /// A request of the source interrupts the target.
    Stops,
    /// The target waits to start while the source has an instance.
    Delays,
    /// The target is rejected while the source has an instance.
    Forbids,
}

impl Rule {
    /// All rules, in legend order.
    pub const ALL: [Rule; 3] = [Rule::Stops, Rule::Delays, Rule::Forbids];

    /// The attribute's name.
    pub fn keyword(self) -> &'static str {
        match self {
            Rule::Stops => "stops",
            Rule::Delays => "delays",
            Rule::Forbids => "forbids",
        }
    }

    /// What an edge `A -> B` means.
    pub fn meaning(self) -> &'static str {
        match self {
            Rule::Stops => "a request of A interrupts B",
            Rule::Delays => "B waits to start while A has an instance",
            Rule::Forbids => "B is rejected while A has an instance",
        }
    }

    /// The edge colour.
    pub fn color(self) -> &'static str {
        match self {
            Rule::Stops => "#c0392b",
            Rule::Delays => "#d68910",
            Rule::Forbids => "#2874a6",
        }
    }
}

/// An edge of the overview.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct RuleEdge {
    /// Source index in [`Overview::services`].
    pub from: usize,
    /// Target index.
    pub to: usize,
    /// The rule.
    pub rule: Rule,
}

/// One service's codel state machine.
#[derive(Debug, Clone)]
pub(crate) struct Machine {
    /// A unique identifier (`machine.moveDistance`).
    pub id: String,
    /// The service's name.
    pub service: String,
    /// `service moveDistance` (with `init`/`auto`).
    pub title: String,
    /// Thread, max-time.
    pub detail: String,
    /// Nodes: the request first, then codels in source order, then the
    /// terminal nodes (`end`, then reports in declaration order).
    pub nodes: Vec<MachineNode>,
    /// Edges.
    pub edges: Vec<MachineEdge>,
}

/// What a machine node is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum NodeKind {
    /// The request arriving.
    Request,
    /// A codel.
    Codel(CodelKind),
    /// `end`: the service ends (success, or `INTERRUPTED`/`TIMEOUT` after
    /// an interrupt).
    End,
    /// A report.
    Report,
}

impl NodeKind {
    /// A stable word for classes and legends.
    pub fn class(self) -> &'static str {
        match self {
            NodeKind::Request => "request",
            NodeKind::Codel(k) => k.keyword(),
            NodeKind::End => "end",
            NodeKind::Report => "report",
        }
    }

    /// Fill colour.
    pub fn fill(self) -> &'static str {
        match self {
            NodeKind::Request => "#000000",
            NodeKind::Codel(CodelKind::Control) => "#eaecee",
            NodeKind::Codel(CodelKind::Start) => "#d5f5e3",
            NodeKind::Codel(CodelKind::Exec) => "#d6eaf8",
            NodeKind::Codel(CodelKind::Inter) => "#fdebd0",
            NodeKind::End => "#ffffff",
            NodeKind::Report => "#fadbd8",
        }
    }
}

/// A node of a machine.
#[derive(Debug, Clone)]
pub(crate) struct MachineNode {
    /// A unique identifier in the whole picture (`codel.moveDistance.goto`,
    /// `end.moveDistance`, `report.moveDistance.TOO_FAR_AWAY`,
    /// `request.moveDistance`).
    pub id: String,
    /// Its kind.
    pub kind: NodeKind,
    /// The codel, report or `end`.
    pub name: String,
    /// Lines under the name: the kind, the WCET.
    pub details: Vec<String>,
}

/// What a machine edge is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum EdgeKind {
    /// The request reaches the control codel, or the accepted request
    /// starts the service.
    Request,
    /// A `next` outcome.
    Next,
    /// An `on-inter` link.
    OnInter,
}

impl EdgeKind {
    /// A stable word for classes and legends.
    pub fn class(self) -> &'static str {
        match self {
            EdgeKind::Request => "request",
            EdgeKind::Next => "next",
            EdgeKind::OnInter => "on-inter",
        }
    }

    /// Colour.
    pub fn color(self) -> &'static str {
        match self {
            EdgeKind::Request => "#7f8c8d",
            EdgeKind::Next => "#1c2833",
            EdgeKind::OnInter => "#b9770e",
        }
    }
}

/// An edge of a machine.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct MachineEdge {
    /// Source index in [`Machine::nodes`].
    pub from: usize,
    /// Target index.
    pub to: usize,
    /// Its kind.
    pub kind: EdgeKind,
    /// A label (`accept`, `completes at once`), often empty.
    pub label: String,
}

/// Thread colours (the control thread's is [`CONTROL_COLOR`]).
const PALETTE: [&str; 8] = [
    "#d6eaf8", "#d5f5e3", "#fcf3cf", "#f5eef8", "#d1f2eb", "#fdebd0", "#ebdef0", "#e8f8f5",
];

/// The control thread's colour.
const CONTROL_COLOR: &str = "#eaecee";

impl Diagrams {
    /// Builds the diagrams of a component.
    pub(crate) fn build(c: &Component) -> Diagrams {
        Diagrams {
            component: c.name.name.clone(),
            overview: overview(c),
            machines: c.services.iter().map(|(s, _)| machine(c, s)).collect(),
        }
    }
}

fn overview(c: &Component) -> Overview {
    let mut groups = vec![Group {
        id: "thread.control".to_owned(),
        title: "control thread".to_owned(),
        detail: "requests, control codels, services without start codel".to_owned(),
        color: CONTROL_COLOR,
        services: Vec::new(),
    }];
    for (k, (_, t)) in c.threads.iter().enumerate() {
        let period = t.period.map_or_else(
            || "aperiodic".to_owned(),
            |p| format!("period {}", duration(p.ns)),
        );
        groups.push(Group {
            id: format!("thread.{}", t.name.name),
            title: format!("thread {}", t.name.name),
            detail: format!("{period}, priority {}", t.priority),
            color: PALETTE[k % PALETTE.len()],
            services: Vec::new(),
        });
    }
    let mut services = Vec::new();
    for (k, (_, s)) in c.services.iter().enumerate() {
        let group = match (s.runs_on_thread(), s.thread) {
            (true, Some(t)) => t.id.0 as usize + 1,
            _ => 0,
        };
        if let Some(g) = groups.get_mut(group) {
            g.services.push(k);
        }
        let mut details = Vec::new();
        if s.kind != ServiceKind::Plain {
            details.push(format!("{} service", s.kind.keyword()));
        }
        details.push(match (s.runs_on_thread(), s.thread) {
            (true, Some(t)) => format!("thread {}", c.threads[t.id].name.name),
            _ => "control thread only".to_owned(),
        });
        if let Some(m) = s.max_time {
            details.push(format!("max-time {}", duration(m.ns)));
        }
        services.push(ServiceBox {
            id: format!("service.{}", s.name.name),
            name: s.name.name.clone(),
            details,
            group,
        });
    }
    let mut edges = Vec::new();
    for (k, (_, s)) in c.services.iter().enumerate() {
        for rule in Rule::ALL {
            for r in rule_list(s, rule) {
                let edge = RuleEdge {
                    from: k,
                    to: r.id.0 as usize,
                    rule,
                };
                if !edges.contains(&edge) {
                    edges.push(edge);
                }
            }
        }
    }
    Overview {
        groups,
        services,
        edges,
    }
}

fn rule_list(s: &Service, rule: Rule) -> &[genom_model::component::Ref<ServiceId>] {
    match rule {
        Rule::Stops => &s.stops,
        Rule::Delays => &s.delays,
        Rule::Forbids => &s.forbids,
    }
}

fn machine(c: &Component, sid: ServiceId) -> Machine {
    let s = &c.services[sid];
    let name = &s.name.name;
    let mut nodes = vec![MachineNode {
        id: format!("request.{name}"),
        kind: NodeKind::Request,
        name: "request".to_owned(),
        details: Vec::new(),
    }];
    let mut index_of: Vec<(CodelId, usize)> = Vec::new();
    for &k in &s.codels {
        let codel = &c.codels[k];
        let mut details = vec![match codel.kind {
            CodelKind::Control => "control codel (control thread)".to_owned(),
            kind => format!("{} codel", kind.keyword()),
        }];
        details.push(match codel.wcet {
            Some(w) => format!("WCET {}", duration(w.ns)),
            None => "WCET unknown".to_owned(),
        });
        index_of.push((k, nodes.len()));
        nodes.push(MachineNode {
            id: format!("codel.{name}.{}", codel.name.name),
            kind: NodeKind::Codel(codel.kind),
            name: codel.name.name.clone(),
            details,
        });
    }
    let node_of = |k: CodelId| index_of.iter().find(|e| e.0 == k).map(|e| e.1);
    // Terminal nodes, created on demand but ordered: end, then reports.
    let mut uses_end = s.start.is_none();
    let mut reports = vec![false; s.reports.len()];
    for &k in &s.codels {
        let codel = &c.codels[k];
        if codel.kind == CodelKind::Control {
            continue;
        }
        for o in codel.outcomes() {
            match o {
                Outcome::End => uses_end = true,
                Outcome::Report(r) => {
                    if let Some(u) = reports.get_mut(r) {
                        *u = true;
                    }
                }
                Outcome::Codel(_) => {}
            }
        }
    }
    let end = uses_end.then(|| {
        nodes.push(MachineNode {
            id: format!("end.{name}"),
            kind: NodeKind::End,
            name: "end".to_owned(),
            details: Vec::new(),
        });
        nodes.len() - 1
    });
    let mut report_node = vec![None; s.reports.len()];
    for (r, used) in reports.iter().enumerate() {
        if *used {
            report_node[r] = Some(nodes.len());
            nodes.push(MachineNode {
                id: format!("report.{name}.{}", s.reports[r].name),
                kind: NodeKind::Report,
                name: s.reports[r].name.clone(),
                details: Vec::new(),
            });
        }
    }
    let mut edges = Vec::new();
    let mut push = |from: usize, to: usize, kind: EdgeKind, label: &str| {
        let e = MachineEdge {
            from,
            to,
            kind,
            label: label.to_owned(),
        };
        if !edges.contains(&e) {
            edges.push(e);
        }
    };
    // The request path: request -> control -> start (or end).
    let mut at = 0;
    if let Some(control) = s.control.and_then(node_of) {
        push(0, control, EdgeKind::Request, "");
        at = control;
    }
    match (s.start.and_then(node_of), end) {
        (Some(start), _) => push(at, start, EdgeKind::Request, "accept"),
        (None, Some(end)) => push(at, end, EdgeKind::Request, "completes at once"),
        (None, None) => {}
    }
    for &k in &s.codels {
        let codel = &c.codels[k];
        let Some(from) = node_of(k) else { continue };
        if codel.kind == CodelKind::Control {
            continue;
        }
        for o in codel.outcomes() {
            let to = match o {
                Outcome::Codel(t) => node_of(t),
                Outcome::End => end,
                Outcome::Report(r) => report_node.get(r).copied().flatten(),
            };
            if let Some(to) = to {
                push(from, to, EdgeKind::Next, "");
            }
        }
        if let Some(to) = codel.on_inter.and_then(|r| node_of(r.id)) {
            push(from, to, EdgeKind::OnInter, "");
        }
    }
    let mut detail = match (s.runs_on_thread(), s.thread) {
        (true, Some(t)) => format!("thread {}", c.threads[t.id].name.name),
        _ => "control thread only".to_owned(),
    };
    if let Some(m) = s.max_time {
        let _ = write!(detail, ", max-time {}", duration(m.ns));
    }
    let title = match s.kind {
        ServiceKind::Plain => format!("service {name}"),
        kind => format!("{} service {name}", kind.keyword()),
    };
    Machine {
        id: format!("machine.{name}"),
        service: name.clone(),
        title,
        detail,
        nodes,
        edges,
    }
}

/// A duration in the largest unit that divides it (`20 ms`, `1.5 s` is
/// written `1500 ms`).
pub(crate) fn duration(ns: u64) -> String {
    const UNITS: [(u64, &str); 5] = [
        (60_000_000_000, "min"),
        (1_000_000_000, "s"),
        (1_000_000, "ms"),
        (1_000, "µs"),
        (1, "ns"),
    ];
    for (size, unit) in UNITS {
        if ns >= size && ns % size == 0 {
            return format!("{} {unit}", ns / size);
        }
    }
    "0 s".to_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_use_the_largest_exact_unit() {
        assert_eq!(duration(1_000_000_000), "1 s");
        assert_eq!(duration(1_500_000_000), "1500 ms");
        assert_eq!(duration(100_000), "100 µs");
        assert_eq!(duration(90 * 60_000_000_000), "90 min");
        assert_eq!(duration(7), "7 ns");
    }

    #[test]
    fn dot_strings_are_escaped() {
        assert_eq!(q("a\"b\\c\nd"), "\"a\\\"b\\\\c\\nd\"");
    }

    #[test]
    fn lighter_colours() {
        assert_eq!(lighter("#000000"), "#7f7f7f");
        assert_eq!(lighter("#ffffff"), "#ffffff");
    }
}
