//! Shared by the Petri-net cross-check tests: load a component, explore it
//! both with the explorer of `engine::system` and with the token game of
//! its Petri net, and compare the stable markings (projected onto the
//! explorer's configuration) and the steps between them.

#![allow(dead_code)]

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::Path;

use gen_frontend::{FsLoader, MemoryLoader};
use genom_check::{CheckOptions, check_file, check_source};
use genom_checker::dialect::system::{Config, System};
use genom_checker::kernel::explore::{Limits, Model, explore};
use genom_model::Severity;
use genom_model::behaviour::Behaviour;
use genom_model::component::{Component, Idx, ServiceId};
use genom_model::petri::{PRIORITY_STEP, PetriNet, PlaceKind};
use genom_oracles::petri::{StableGraph, is_stable, stable_graph};
use genom_translate::petri::BuildPetriNet;

/// A configuration as both sides can express it: `init_done`, then per
/// service its position and its pending instance's wait bits.
pub type Cfg = (bool, Vec<(u16, Option<u64>)>);

/// What one cross-check found.
#[derive(Debug, Clone, Copy)]
pub struct Sizes {
    /// Places of the net.
    pub places: usize,
    /// Transitions of the net.
    pub transitions: usize,
    /// Configurations of the explorer (= stable markings of the net).
    pub configs: usize,
    /// Steps between them.
    pub edges: usize,
    /// Urgent transitions fired by the net's cascades.
    pub urgent_firings: u64,
}

/// The component of a file, when it has no static error.
pub fn load(path: &Path) -> Result<Component, Vec<String>> {
    let options = CheckOptions::new().behaviour(false);
    let result = check_file(path, &FsLoader, &options).map_err(|e| vec![format!("{e:?}")])?;
    component_of(result)
}

/// The component of a source text (`test.gen`), when it has no static
/// error.
pub fn parse(src: &str) -> Result<Component, Vec<String>> {
    let options = CheckOptions::new().behaviour(false);
    let result = check_source(
        Path::new("test.gen"),
        src.to_owned(),
        &MemoryLoader::new(),
        &options,
    );
    component_of(result)
}

fn component_of(result: genom_check::CheckResult) -> Result<Component, Vec<String>> {
    let errors: Vec<String> = result
        .diagnostics
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .map(|d| format!("{}: {}", d.code.as_str(), d.message))
        .collect();
    match result.component {
        Some(c) if errors.is_empty() => Ok(c),
        _ => Err(errors),
    }
}

fn project_config(cfg: &Config) -> Cfg {
    let services = cfg
        .main
        .iter()
        .zip(&cfg.pending)
        .map(|(&p, &q)| (p, q))
        .collect();
    (cfg.init_done, services)
}

fn project_marking(net: &PetriNet, c: &Component, m: &[u32]) -> Cfg {
    let services = c
        .services
        .ids()
        .map(|s| (net.position(m, s).unwrap_or(u16::MAX), net.pending(m, s)))
        .collect();
    (net.is_init_done(m), services)
}

/// Configurations and steps of one exploration.
type Side = (BTreeSet<Cfg>, BTreeSet<(Cfg, Cfg)>);

/// The initial configuration, the configurations and the steps.
type Explored = (Cfg, BTreeSet<Cfg>, BTreeSet<(Cfg, Cfg)>);

/// Explores the system of every service, before initialisation
/// (`pre_init`: states where init has completed are reached but not
/// expanded) or from the post-init state. Returns the initial
/// configuration, the configurations and the steps of expanded ones.
fn explore_phase(
    c: &Component,
    b: &Behaviour,
    pre_init: bool,
    limit: usize,
) -> Option<(Cfg, Side)> {
    let all: Vec<ServiceId> = c.services.ids().collect();
    let sys = System::new(c, b, &all, pre_init);
    let mut configs: Vec<Config> = Vec::new();
    let limits = Limits {
        max_states: limit,
        ..Limits::default()
    };
    let e = explore(&sys, limits, |_, cfg| configs.push(cfg.clone()));
    if e.stopped.is_some() {
        return None;
    }
    let init = project_config(sys.init_states().first()?);
    let mut edges = BTreeSet::new();
    let mut actions = Vec::new();
    for cfg in configs.iter().filter(|cfg| sys.expand(cfg)) {
        actions.clear();
        sys.actions(cfg, &mut actions);
        for &a in &actions {
            if let Some(next) = sys.next_state(cfg, a) {
                edges.insert((project_config(cfg), project_config(&next)));
            }
        }
    }
    Some((init, (configs.iter().map(project_config).collect(), edges)))
}

/// The explorer's configurations and steps over the whole life of the
/// component, as `engine::analysis` splits it: the pre-init phase (when
/// there is an init service), then, if initialisation can complete,
/// everything from the unique post-init configuration (`System::new(..,
/// false)` alone starts *after* initialisation).
fn explorer_side(c: &Component, b: &Behaviour, limit: usize) -> Option<Explored> {
    if c.init_service().is_none() {
        let (init, (configs, edges)) = explore_phase(c, b, false, limit)?;
        return Some((init, configs, edges));
    }
    let (init, (mut configs, mut edges)) = explore_phase(c, b, true, limit)?;
    if configs.iter().any(|cfg| cfg.0) {
        let (_, (post_configs, post_edges)) = explore_phase(c, b, false, limit)?;
        configs.extend(post_configs);
        edges.extend(post_edges);
    }
    Some((init, configs, edges))
}

/// Checks the structural invariants of every stable marking of the net.
fn check_net(name: &str, net: &PetriNet, c: &Component, g: &StableGraph) {
    assert!(!g.stopped, "{name}: the net's exploration stopped early");
    assert!(
        !g.urgent_cycle,
        "{name}: an urgent cascade can fire forever"
    );
    assert_eq!(
        g.nondeterministic, 0,
        "{name}: some urgent cascade has several stable ends"
    );
    assert!(
        g.max_tokens <= 1,
        "{name}: the net is not safe ({} tokens)",
        g.max_tokens
    );
    assert_eq!(
        g.initial.len(),
        1,
        "{name}: the initial cascade is not deterministic"
    );
    for m in &g.markings {
        assert!(is_stable(net, m));
        for s in c.services.ids() {
            let sp = &net.services[s.index()];
            let tokens: u32 = sp.positions.iter().map(|p| m[p.index()]).sum();
            assert_eq!(
                tokens, 1,
                "{name}: service {} is not in exactly one position",
                s.0
            );
        }
        let busy = net.places.iter().enumerate().any(|(i, p)| {
            m[i] > 0 && matches!(p.kind, PlaceKind::Request(..) | PlaceKind::Dropping(_))
        });
        assert!(
            !busy,
            "{name}: a stable marking is inside a request or a drop"
        );
        let done = m[net.init_done.index()] + m[net.init_not_done.index()];
        assert_eq!(
            done, 1,
            "{name}: init_done/init_not_done is not a single token"
        );
    }
    let names: BTreeSet<&str> = net.places.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(
        names.len(),
        net.places.len(),
        "{name}: two places share a name"
    );
    let names: BTreeSet<&str> = net.transitions.iter().map(|t| t.name.as_str()).collect();
    assert_eq!(
        names.len(),
        net.transitions.len(),
        "{name}: two transitions share a name"
    );
    for t in &net.transitions {
        if t.priority > PRIORITY_STEP {
            assert!(!matches!(
                t.kind,
                genom_model::petri::TransitionKind::Request(_)
            ));
        }
    }
}

/// Describes a configuration with service names and position labels.
pub fn describe(c: &Component, b: &Behaviour, cfg: &Cfg) -> String {
    let mut out = format!("init_done={}", cfg.0);
    for (s, &(p, q)) in c.services.ids().zip(&cfg.1) {
        let pos = b.machine(s).positions.get(usize::from(p));
        let _ = write!(out, "; {} {:?}", c.services[s].name.name, pos);
        if let Some(mask) = q {
            let _ = write!(out, " pending(wait {mask:#b})");
        }
    }
    out
}

/// Explores `c` both ways and asserts that the projected stable markings
/// and steps are exactly the explorer's configurations and steps. `None`
/// when the explorer needs more than `limit` states (not compared).
pub fn cross_check(name: &str, c: &Component, limit: usize) -> Option<Sizes> {
    let b = Behaviour::new(c);
    let (init, configs, edges) = explorer_side(c, &b, limit)?;
    let net = PetriNet::build(c, &b);
    let g = stable_graph(&net, limit * 40);
    check_net(name, &net, c, &g);
    let project = |i: usize| project_marking(&net, c, &g.markings[i]);
    let stable: BTreeSet<Cfg> = (0..g.markings.len()).map(project).collect();
    let steps: BTreeSet<(Cfg, Cfg)> = g
        .edges
        .iter()
        .map(|&(i, _, j)| (project(i), project(j)))
        .collect();
    let net_init = project(g.initial[0]);
    let mut report = String::new();
    if net_init != init {
        let _ = writeln!(
            report,
            "initial: explorer {} / net {}",
            describe(c, &b, &init),
            describe(c, &b, &net_init)
        );
    }
    for x in configs.difference(&stable) {
        let _ = writeln!(report, "only the explorer reaches {}", describe(c, &b, x));
    }
    for x in stable.difference(&configs) {
        let _ = writeln!(report, "only the net reaches {}", describe(c, &b, x));
    }
    for (x, y) in edges.symmetric_difference(&steps) {
        let side = if edges.contains(&(x.clone(), y.clone())) {
            "explorer"
        } else {
            "net"
        };
        let _ = writeln!(
            report,
            "only the {side} steps {}\n    -> {}",
            describe(c, &b, x),
            describe(c, &b, y)
        );
    }
    assert!(
        report.is_empty(),
        "{name}: the net and the explorer disagree:\n{report}"
    );
    assert_eq!(
        stable.len(),
        g.markings.len(),
        "{name}: two stable markings project to one configuration"
    );
    Some(Sizes {
        places: net.places.len(),
        transitions: net.transitions.len(),
        configs: configs.len(),
        edges: edges.len(),
        urgent_firings: g.urgent_firings,
    })
}
