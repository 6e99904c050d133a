//! genom-system: a robot's functional layer, several GenoM3 components
//! wired by their ports and verified together (docs/functional-layer.md).
//!
//! - [`description`] reads the system file (TOML, with spans);
//! - [`ports`] checks its names and connections;
//! - [`timing`] asks the timed engine which tasks of each component never
//!   overrun;
//! - [`flow`] follows data through each component's codels;
//! - [`chains`] composes them into the cause-effect chains' worst-case
//!   data age and reaction time, each with a timeline that reaches it.
//!
//! Loading the `.gen` files is the caller's; this crate reads the model.

pub mod chains;
pub mod description;
mod explain;
pub mod flow;
pub mod ports;
pub mod timing;

use std::collections::{BTreeMap, BTreeSet};

use genom_model::component::{Component, ServiceId};
use genom_model::duration::format_ns;
use genom_model::{Code, Diagnostic, Severity, Span};
use serde::Serialize;

pub use explain::explanation;
pub use genom_engine::kernel::explore::Limits;

use chains::{ChainReport, Feed, Graph, Node, Source};
use description::{ChainSpec, SystemFile};
use timing::ComponentTiming;

/// The answer to one chain request.
#[derive(Debug, Clone, Serialize)]
pub struct ChainRequest {
    /// The request as written (`from->to`).
    pub request: String,
    /// Its deadline.
    pub deadline_ns: Option<u64>,
    /// Every chain it covers.
    pub chains: Vec<ChainReport>,
}

/// What the analysis of a system found besides its diagnostics.
#[derive(Debug, Clone, Default, Serialize)]
pub struct SystemReport {
    /// Each component's tasks' timing (when chains were asked for).
    pub components: Vec<ComponentTiming>,
    /// The chain requests, in order (the file's, then the command line's).
    pub requests: Vec<ChainRequest>,
    /// What the figures rest on besides the `.gen` files.
    pub assumptions: Vec<String>,
}

/// Checks the system `file` whose components are `comps` (by their names
/// in the file), and bounds its chains (the file's and `extra`); `span`
/// stands for the command line's chains in diagnostics.
pub fn analyse(
    file: &SystemFile,
    extra: &[ChainSpec],
    comps: &BTreeMap<String, Component>,
    limits: Limits,
    span: Span,
) -> (Vec<Diagnostic>, SystemReport) {
    let mut diags = ports::check(file, comps);
    let mut report = SystemReport::default();
    let mut steady: BTreeMap<String, BTreeSet<ServiceId>> = BTreeMap::new();
    for entry in &file.components {
        let (Some(c), Some(list)) = (comps.get(&entry.name), &entry.steady) else {
            continue;
        };
        match timing::services_named(c, list.iter().map(|(n, _)| n.as_str())) {
            Ok(s) => {
                steady.insert(entry.name.clone(), s);
            }
            Err(unknown) => {
                for (n, at) in list.iter().filter(|(n, _)| unknown.contains(&n.as_str())) {
                    diags.push(Diagnostic::new(
                        Code::UnknownSystemName,
                        format!("component `{}` has no service `{n}`", entry.name),
                        *at,
                        "no such service",
                    ));
                }
            }
        }
    }
    let requests: Vec<ChainSpec> = file.chains.iter().chain(extra).cloned().collect();
    if requests.is_empty() || diags.iter().any(|d| d.severity == Severity::Error) {
        return (diags, report);
    }
    report.assumptions = assumptions(file);
    // Each component's timing and codels.
    let mut nodes = BTreeMap::new();
    for (name, c) in comps {
        let s = steady.get(name);
        let t = timing::component_timing(name, c, s, limits);
        report.components.push(t.clone());
        let inputs = c
            .genom3
            .as_deref()
            .map(|g| {
                g.ports
                    .iter()
                    .filter(|p| !p.is_out)
                    .map(|p| p.name.name.clone())
                    .collect()
            })
            .unwrap_or_default();
        nodes.insert(
            name.clone(),
            Node {
                sites: flow::sites(c, s),
                timing: t,
                inputs,
            },
        );
    }
    let mut feeds = BTreeMap::new();
    for conn in &file.connections {
        if let (Some(fp), Some(tp)) = (&conn.from.port, &conn.to.port) {
            feeds.insert(
                (conn.to.component.clone(), tp.clone()),
                Feed::Port(conn.from.component.clone(), fp.clone()),
            );
        }
    }
    for ext in &file.externals {
        for e in &ext.feeds {
            if let Some(p) = &e.port {
                feeds.insert(
                    (e.component.clone(), p.clone()),
                    Feed::External(ext.name.clone(), ext.period_ns),
                );
            }
        }
    }
    let graph = Graph {
        nodes: &nodes,
        feeds: &feeds,
    };
    for spec in &requests {
        let at = if spec.span == Span::default() {
            span
        } else {
            spec.span
        };
        match request(&graph, file, comps, spec) {
            Ok(r) => {
                diags.extend(verdicts(&r, at));
                report.requests.push(r);
            }
            Err(d) => diags.push(Diagnostic {
                labels: relabel(d.labels, at),
                ..d
            }),
        }
    }
    (diags, report)
}

/// What the bounds rest on: the WCET files, the steady state, one request
/// of each activity at a time, the platform.
fn assumptions(file: &SystemFile) -> Vec<String> {
    let mut out = Vec::new();
    for c in &file.components {
        let wcet = c.wcet.as_ref().map_or_else(
            || "no WCET file (its codels take no time)".to_owned(),
            |w| format!("every codel takes at most its WCET from `{}`", w.display()),
        );
        let steady = c.steady.as_ref().map_or_else(
            || "every service may be requested".to_owned(),
            |list| {
                let names: Vec<&str> = list.iter().map(|(n, _)| n.as_str()).collect();
                format!(
                    "clients request only {} (and GenoM3's built-in services)",
                    names.join(", ")
                )
            },
        );
        out.push(format!(
            "`{}`: {wcet}; {steady}; at most 1 concurrent request of each activity",
            c.name
        ));
    }
    out.push(
        "each component is a process and each task runs on its own core; ticks of different components have any phase; every codel of a chain runs in every wake-up of its task (steady state)"
            .to_owned(),
    );
    out
}

fn relabel(mut labels: Vec<genom_model::Label>, at: Span) -> Vec<genom_model::Label> {
    for l in &mut labels {
        if l.span == Span::default() {
            l.span = at;
        }
    }
    labels
}

/// The chains of one request.
fn request(
    graph: &Graph<'_>,
    file: &SystemFile,
    comps: &BTreeMap<String, Component>,
    spec: &ChainSpec,
) -> Result<ChainRequest, Diagnostic> {
    let sink_comp = &spec.to.component;
    let node = graph.nodes.get(sink_comp).ok_or_else(|| {
        Diagnostic::new(
            Code::UnknownSystemName,
            format!("no component `{sink_comp}` in the system"),
            spec.to.span,
            "the chain's sink",
        )
    })?;
    let sinks: Vec<String> = match &spec.to.port {
        Some(p) => {
            let (_, port, _) = ports::resolve(&spec.to, comps)?;
            if port.is_out {
                return Err(Diagnostic::new(
                    Code::BadConnection,
                    format!("the chain's sink `{}` is an out port", spec.to.text()),
                    spec.to.span,
                    "a sink is an in port (or a component: its every in port)",
                ));
            }
            vec![p.clone()]
        }
        None => node.inputs.clone(),
    };
    let sources: Vec<Source> = match &spec.from {
        Some(e) if e.port.is_none() => {
            let ext = file
                .externals
                .iter()
                .find(|x| x.name == e.component)
                .ok_or_else(|| {
                    Diagnostic::new(
                        Code::UnknownSystemName,
                        format!("no external source `{}` in the system", e.component),
                        e.span,
                        "not an `[external.NAME]` of the file",
                    )
                })?;
            vec![Source::External(ext.name.clone(), ext.period_ns)]
        }
        Some(e) => {
            let (_, port, _) = ports::resolve(e, comps)?;
            if !port.is_out {
                return Err(Diagnostic::new(
                    Code::BadConnection,
                    format!("the chain's source `{}` is an in port", e.text()),
                    e.span,
                    "a source is an out port or an external source",
                ));
            }
            vec![Source::Port(e.component.clone(), port.name.name.clone())]
        }
        None => {
            let mut all: Vec<Source> = file
                .externals
                .iter()
                .map(|x| Source::External(x.name.clone(), x.period_ns))
                .collect();
            for (name, c) in comps {
                let ports = c
                    .genom3
                    .as_deref()
                    .map(|g| g.ports.as_slice())
                    .unwrap_or_default();
                all.extend(
                    ports
                        .iter()
                        .filter(|p| p.is_out)
                        .map(|p| Source::Port(name.clone(), p.name.name.clone())),
                );
            }
            all
        }
    };
    let mut chains = Vec::new();
    for src in &sources {
        for sink in &sinks {
            chains.extend(graph.chains(src, sink_comp, sink));
        }
    }
    Ok(ChainRequest {
        request: format!(
            "{}->{}",
            spec.from
                .as_ref()
                .map_or("*".to_owned(), description::Endpoint::text),
            spec.to.text()
        ),
        deadline_ns: spec.deadline_ns,
        chains,
    })
}

/// The diagnostics of a request: a deadline missed, or chains without a
/// bound.
fn verdicts(r: &ChainRequest, at: Span) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    if r.chains.is_empty() {
        out.push(Diagnostic::new(
            Code::ChainUnbounded,
            format!("no data path goes `{}`", r.request),
            at,
            "no chain",
        ).with_help("no codel on a task reads what the source feeds, on to the sink (check the connections and the codels' parameters)"));
        return out;
    }
    for ch in &r.chains {
        let via = ch
            .stages
            .iter()
            .map(|s| format!("{}.{}", s.component, s.task))
            .collect::<Vec<_>>()
            .join(" -> ");
        match (ch.data_age_ns, ch.reaction_ns, r.deadline_ns) {
            (Some(age), Some(react), Some(d)) if age.max(react) > d => out.push(
                Diagnostic::new(
                    Code::ChainDeadlineMiss,
                    format!(
                        "chain {} -> {} (via {via}) can exceed its deadline {}: data age up to {}, reaction time up to {}",
                        ch.source,
                        ch.sink,
                        format_ns(d),
                        format_ns(age),
                        format_ns(react)
                    ),
                    at,
                    "this chain's deadline",
                )
                .with_trace(ch.trace()),
            ),
            (None, _, deadline) | (_, None, deadline) => {
                let why = ch.unbounded.clone().unwrap_or_default();
                let code = if deadline.is_some() {
                    Code::ChainDeadlineMiss
                } else {
                    Code::ChainUnbounded
                };
                out.push(
                    Diagnostic::new(
                        code,
                        format!("chain {} -> {} (via {via}) has no bound: {why}", ch.source, ch.sink),
                        at,
                        "this chain",
                    )
                    .with_help("list the services clients call in flight (`steady`), give every codel on the chain a WCET, or fix the overrun"),
                );
            }
            _ => {}
        }
    }
    out
}
