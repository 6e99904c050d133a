//! The `uppaal` and `tchecker` exports: snapshots for every file of
//! `specs/`, the structure of the UPPAAL XML (parsed with `roxmltree`) and
//! of the TChecker text, for the specs and for generated timed components,
//! keyword renaming, and the timed rules of the network they print.
//!
//! With `TIMED_EXPORT_DIR` set, every model exported here is also written
//! to that directory (to try `verifyta` or `tck-reach` on them).

#![allow(clippy::expect_used)] // test support code outside #[test] functions

mod common;

use common::stem;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use genom_checker::CheckOptions;
use genom_export::{ExportInput, Exported, Format, Verification};
use genom_generate::{GeneratorConfig, generate};
use genom_model::behaviour::Behaviour;
use genom_model::component::Component;
use genom_model::kinds::CodelKind;
use genom_model::timed_automata::{CmpOp, LabelKind, Network, ProcessKind};
use genom_translate::timed_automata::BuildNetwork;

/// The resolved component of a file (static checks only).
fn component_of(path: &Path) -> Component {
    let options = CheckOptions::new().behaviour(false);
    let result = common::check_with(path, &options);
    result.component.expect("spec has a component")
}

/// The resolved component of a text.
fn component_of_text(name: &str, text: &str) -> Component {
    let options = CheckOptions::new().behaviour(false);
    let result = common::check_text(Path::new(name), text.to_owned(), &options);
    result
        .component
        .unwrap_or_else(|| panic!("{name} has a component: {:?}", result.diagnostics))
}

fn export(format: Format, c: &Component, name: &str) -> Exported {
    let sources = genom_model::SourceMap::default();
    let verification = Verification {
        verified: true,
        ..Verification::default()
    };
    let input = ExportInput {
        component: c,
        sources: &sources,
        verification: &verification,
    };
    let out = genom_export::export(format, &input).expect("the export succeeds");
    if let Some(dir) = std::env::var_os("TIMED_EXPORT_DIR") {
        let dir = PathBuf::from(dir);
        std::fs::create_dir_all(&dir).expect("export directory");
        let base = dir.join(format!("{name}.{}", format.extension()));
        std::fs::write(&base, &out.main).expect("write the model");
        for (suffix, text) in &out.extra {
            std::fs::write(base.with_extension(suffix.trim_start_matches('.')), text)
                .expect("write the companion file");
        }
    }
    out
}

fn network(c: &Component) -> Network {
    Network::build(c, &Behaviour::new(c))
}

/// Small timed components of the generator.
fn generated() -> Vec<(String, Component)> {
    (0..12u64)
        .map(|seed| {
            let mut cfg = GeneratorConfig::small(seed);
            cfg.timed = seed % 4 != 3;
            let text = generate(&cfg);
            let name = format!("gen-{seed}");
            let c = component_of_text(&format!("{name}.gen"), &text);
            (name, c)
        })
        .collect()
}

/// Codels that a thread or the control thread can run: each has a label.
fn runnable_codels(c: &Component, net: &Network) -> usize {
    let b = Behaviour::new(c);
    let mut set = BTreeSet::new();
    for s in c.services.ids() {
        let svc = &c.services[s];
        if let Some(k) = svc.control {
            set.insert(k);
        }
        if svc.thread.is_none() {
            continue;
        }
        for p in &b.machine(s).positions {
            if let Some(k) = p.codel().filter(|_| p.is_running()) {
                set.insert(k);
            }
        }
    }
    let labelled: BTreeSet<_> = net
        .labels
        .iter()
        .filter_map(|l| match l.kind {
            LabelKind::Codel(k) => Some(k),
            _ => None,
        })
        .collect();
    assert_eq!(set, labelled, "every runnable codel has one label");
    set.len()
}

// ---------------------------------------------------------------------------
// UPPAAL
// ---------------------------------------------------------------------------

/// Parses XML with its DOCTYPE (UPPAAL's).
fn parse_xml(xml: &str) -> roxmltree::Document<'_> {
    let options = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..roxmltree::ParsingOptions::default()
    };
    roxmltree::Document::parse_with_options(xml, options).expect("well-formed XML")
}

/// Checks the structure of an UPPAAL model; returns its queries.
fn check_uppaal(xml: &str, net: &Network) -> Vec<String> {
    let doc = parse_xml(xml);
    let nta = doc.root_element();
    assert_eq!(nta.tag_name().name(), "nta");
    let children: Vec<&str> = nta
        .children()
        .filter(|n| n.is_element())
        .map(|n| n.tag_name().name())
        .collect();
    let templates = children.iter().filter(|&&n| n == "template").count();
    assert_eq!(templates, net.processes.len(), "one template per process");
    let mut expected = vec!["declaration"];
    expected.extend(std::iter::repeat_n("template", templates));
    expected.extend(["instantiation", "system", "queries"]);
    assert_eq!(children, expected, "the elements of <nta>, in order");
    let mut ids = BTreeSet::new();
    for t in nta.children().filter(|n| n.has_tag_name("template")) {
        check_template(t, &mut ids);
    }
    let system = child_text(nta, "system");
    assert!(system.trim_start().starts_with("system "), "{system}");
    nta.children()
        .filter(|n| n.has_tag_name("queries"))
        .flat_map(|q| q.children().filter(|n| n.has_tag_name("query")))
        .map(|q| child_text(q, "formula"))
        .collect()
}

fn child_text(node: roxmltree::Node<'_, '_>, tag: &str) -> String {
    node.children()
        .find(|n| n.has_tag_name(tag))
        .and_then(|n| n.text())
        .unwrap_or_default()
        .to_owned()
}

/// A template: named locations with unique ids, an initial location, and
/// transitions between its own locations.
fn check_template(t: roxmltree::Node<'_, '_>, all_ids: &mut BTreeSet<String>) {
    let name = child_text(t, "name");
    let mut ids = BTreeSet::new();
    for l in t.children().filter(|n| n.has_tag_name("location")) {
        let id = l.attribute("id").expect("location id").to_owned();
        assert!(all_ids.insert(id.clone()), "duplicate id {id}");
        ids.insert(id);
        assert!(
            !child_text(l, "name").is_empty(),
            "a location of {name} has no name"
        );
    }
    let init = t
        .children()
        .find(|n| n.has_tag_name("init"))
        .and_then(|n| n.attribute("ref"))
        .expect("an initial location");
    assert!(ids.contains(init), "{name}: init {init}");
    for tr in t.children().filter(|n| n.has_tag_name("transition")) {
        for end in ["source", "target"] {
            let r = tr
                .children()
                .find(|n| n.has_tag_name(end))
                .and_then(|n| n.attribute("ref"))
                .expect("transition end");
            assert!(ids.contains(r), "{name}: {end} {r}");
        }
        let urgent = tr
            .children()
            .any(|n| n.attribute("kind") == Some("synchronisation") && n.text() == Some("hurry!"));
        let guard = tr
            .children()
            .find(|n| n.attribute("kind") == Some("guard"))
            .and_then(|n| n.text())
            .unwrap_or_default();
        assert!(
            !urgent || !guard.contains("_period") && !guard.contains("_watch "),
            "{name}: an urgent edge has a clock guard: {guard}"
        );
    }
}

/// The queries: deadlock, one `E<>` per codel, one bounded response per
/// clocked watchdog, one per periodic thread.
fn check_queries(queries: &[String], net: &Network, q_file: &str) {
    assert_eq!(queries[0], "A[] not deadlock");
    let codels = net
        .labels
        .iter()
        .filter(|l| matches!(l.kind, LabelKind::Codel(_)))
        .count();
    let reach = queries.iter().filter(|q| q.starts_with("E<> ")).count();
    assert_eq!(reach, codels, "one E<> query per codel");
    let watchdogs: Vec<&str> = net
        .processes
        .iter()
        .filter(|p| matches!(p.kind, ProcessKind::Watchdog(_)) && p.location("late").is_some())
        .map(|p| p.name.as_str())
        .collect();
    for w in &watchdogs {
        let q = format!("A[] not {w}.late");
        assert!(queries.contains(&q), "missing {q}");
    }
    for q in queries {
        assert!(q_file.contains(q.as_str()), "{q} is not in the .q file");
    }
}

#[test]
fn uppaal_of_every_spec() {
    for path in common::specs() {
        let c = component_of(&path);
        let net = network(&c);
        let out = export(Format::Uppaal, &c, &stem(&path));
        assert_eq!(out.extra.len(), 1, "the query file");
        assert_eq!(out.extra[0].0, ".q");
        let queries = check_uppaal(&out.main, &net);
        check_queries(&queries, &net, &out.extra[0].1);
        insta::assert_snapshot!(format!("uppaal__{}", stem(&path)), out.main);
        insta::assert_snapshot!(format!("uppaal_queries__{}", stem(&path)), out.extra[0].1);
    }
}

#[test]
fn uppaal_of_generated_components() {
    for (name, c) in generated() {
        let net = network(&c);
        runnable_codels(&c, &net);
        let out = export(Format::Uppaal, &c, &name);
        let queries = check_uppaal(&out.main, &net);
        check_queries(&queries, &net, &out.extra[0].1);
    }
}

#[test]
fn the_uppaal_export_is_deterministic() {
    let path = common::specs().into_iter().next().expect("a spec");
    let c = component_of(&path);
    assert_eq!(
        export(Format::Uppaal, &c, "a"),
        export(Format::Uppaal, &c, "b")
    );
    assert_eq!(
        export(Format::Tchecker, &c, "a"),
        export(Format::Tchecker, &c, "b")
    );
}

// ---------------------------------------------------------------------------
// TChecker
// ---------------------------------------------------------------------------

/// What a TChecker file declares.
#[derive(Debug, Default)]
struct Tck {
    system: Option<String>,
    events: BTreeSet<String>,
    processes: Vec<String>,
    /// Locations by process: name → labels.
    locations: BTreeMap<String, BTreeMap<String, Vec<String>>>,
    initial: BTreeMap<String, usize>,
    edges: usize,
    syncs: usize,
}

/// Reads a TChecker file, checking that every item is declared before
/// use, every process has exactly one initial location, and every edge's
/// locations and event exist.
fn parse_tck(text: &str) -> Tck {
    let mut t = Tck::default();
    for line in text.lines() {
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let (head, attrs) = match line.find('{') {
            Some(i) => (&line[..i], &line[i..]),
            None => (line.split(" #").next().unwrap_or(line), ""),
        };
        let fields: Vec<&str> = head.trim().split(':').collect();
        match fields[0] {
            "system" => t.system = Some(fields[1].to_owned()),
            "event" => assert!(t.events.insert(fields[1].to_owned()), "{line}"),
            "clock" | "int" => {}
            "process" => {
                t.processes.push(fields[1].to_owned());
                t.locations.insert(fields[1].to_owned(), BTreeMap::new());
            }
            "location" => tck_location(&mut t, &fields, attrs, line),
            "edge" => {
                let locs = t
                    .locations
                    .get(fields[1])
                    .expect("edge of a declared process");
                assert!(locs.contains_key(fields[2]), "{line}: source");
                assert!(locs.contains_key(fields[3]), "{line}: target");
                assert!(t.events.contains(fields[4]), "{line}: event");
                assert!(attrs.starts_with('{') && attrs.ends_with('}'), "{line}");
                assert!(
                    !attrs[1..attrs.len() - 1].contains(['{', '}', '#']),
                    "{line}"
                );
                t.edges += 1;
            }
            "sync" => {
                for part in &fields[1..] {
                    let (p, e) = part.split_once('@').expect("p@e");
                    assert!(t.locations.contains_key(p), "{line}: process");
                    assert!(t.events.contains(e.trim_end_matches('?')), "{line}: event");
                }
                t.syncs += 1;
            }
            other => panic!("unknown declaration {other}: {line}"),
        }
    }
    for p in &t.processes {
        assert_eq!(t.initial.get(p), Some(&1), "{p}: one initial location");
    }
    t
}

fn tck_location(t: &mut Tck, fields: &[&str], attrs: &str, line: &str) {
    let locs = t
        .locations
        .get_mut(fields[1])
        .expect("location of a declared process");
    let inner = attrs.trim_start_matches('{').trim_end_matches('}');
    let pairs: Vec<&str> = inner.split(" : ").collect();
    let labels = pairs
        .iter()
        .find_map(|a| a.strip_prefix("labels: "))
        .map(|l| l.split(',').map(str::to_owned).collect())
        .unwrap_or_default();
    assert!(
        locs.insert(fields[2].to_owned(), labels).is_none(),
        "{line}: duplicate location"
    );
    if pairs.contains(&"initial:") {
        *t.initial.entry(fields[1].to_owned()).or_default() += 1;
    }
}

fn check_tchecker(text: &str, net: &Network) {
    let t = parse_tck(text);
    assert!(t.system.is_some(), "a system declaration");
    assert_eq!(
        t.processes.len(),
        net.processes.len() + 1,
        "processes and the monitor"
    );
    let mut labels: BTreeSet<String> = BTreeSet::new();
    for locs in t.locations.values() {
        for l in locs.values().flatten() {
            assert!(labels.insert(l.clone()), "label {l} twice");
        }
    }
    for l in &net.labels {
        assert!(labels.contains(&l.name), "label {} is missing", l.name);
    }
    let (_, edges) = net.size();
    assert_eq!(t.edges, edges + 4, "the network's edges and the monitor's");
    assert!(t.syncs > 0, "every step moves the urgency monitor");
}

#[test]
fn tchecker_of_every_spec() {
    for path in common::specs() {
        let c = component_of(&path);
        let net = network(&c);
        runnable_codels(&c, &net);
        let out = export(Format::Tchecker, &c, &stem(&path));
        assert!(out.extra.is_empty());
        check_tchecker(&out.main, &net);
        insta::assert_snapshot!(format!("tchecker__{}", stem(&path)), out.main);
    }
}

#[test]
fn tchecker_of_generated_components() {
    for (name, c) in generated() {
        let net = network(&c);
        let out = export(Format::Tchecker, &c, &name);
        check_tchecker(&out.main, &net);
    }
}

// ---------------------------------------------------------------------------
// Renaming
// ---------------------------------------------------------------------------

const KEYWORDS_COMPONENT: &str = r#"
component clock { category: default; lang: C; }

thread sync { priority: 0; period: 10ms; }

service process {
  thread: sync;
  max-time: 50ms;
  start codel { exec: go(); max-time: 2ms; next: int; }
  exec codel int { exec: step(); max-time: 3ms; next: end; }
}

service system {
  control codel { exec: check(); max-time: 1ms; }
}
"#;

#[test]
fn keywords_are_renamed_in_both_exports() {
    let c = component_of_text("keywords.gen", KEYWORDS_COMPONENT);
    let net = network(&c);
    let xml = export(Format::Uppaal, &c, "keywords");
    let doc = parse_xml(&xml.main);
    let comment = doc
        .root_element()
        .children()
        .filter(|n| n.is_comment())
        .filter_map(|n| n.text())
        .find(|t| t.contains("renamed"))
        .expect("a renaming comment");
    for (old, new) in [("clock", "clock_"), ("sync", "sync_")] {
        assert!(comment.contains(&format!("{old} -> {new}")), "{comment}");
    }
    let system = child_text(doc.root_element(), "system");
    assert!(system.contains("sync_"), "{system}");
    assert!(
        !system.split([' ', ',', ';']).any(|w| w == "sync"),
        "{system}"
    );
    let queries = check_uppaal(&xml.main, &net);
    check_queries(&queries, &net, &xml.extra[0].1);
    assert!(queries.contains(&"A[] not process_watchdog.late".to_owned()));
    let tck = export(Format::Tchecker, &c, "keywords");
    check_tchecker(&tck.main, &net);
    assert!(tck.main.contains("\nsystem:clock_\n"), "{}", tck.main);
    assert!(tck.main.contains("\nprocess:sync_\n"));
    assert!(tck.main.contains("# Renamed (keywords): clock -> clock_"));
    assert!(!tck.main.contains("process:sync\n"));
}

// ---------------------------------------------------------------------------
// The network's timed rules
// ---------------------------------------------------------------------------

/// A codel ending exactly at the next wake-up is not an overrun: the
/// overrun edge of a running codel requires its execution clock below the
/// WCET (at the WCET it must end first).
#[test]
fn a_codel_at_its_wcet_ends_before_the_wake_up() {
    let c = component_of(Path::new("../tests/fixtures/timing/wcet-equals-period.gen"));
    let net = network(&c);
    let thread = net
        .processes
        .iter()
        .find(|p| matches!(p.kind, ProcessKind::Thread(_)))
        .expect("the thread");
    let overrun = thread.location("overrun").expect("an overrun location");
    let idle = thread.location("idle").expect("idle");
    let from_running: Vec<_> = thread
        .edges
        .iter()
        .filter(|e| e.to == overrun && e.from != idle)
        .collect();
    assert_eq!(from_running.len(), 1, "one running codel");
    let guard = &from_running[0].clock_guard;
    assert!(
        guard
            .iter()
            .any(|g| g.op == CmpOp::Lt && net.clock(g.clock).name.ends_with("_exec")),
        "{guard:?}"
    );
    let tck = export(Format::Tchecker, &c, "wcet-equals-period");
    assert!(tck.main.contains("servoTask_exec<"), "{}", tck.main);
}

/// Urgent edges have integer guards only, and the network's urgency
/// predicate is false in the initial state (the monitor starts calm).
#[test]
fn urgent_edges_have_no_clock_guard() {
    for path in common::specs() {
        let c = component_of(&path);
        let net = network(&c);
        for p in &net.processes {
            for e in p.edges.iter().filter(|e| e.urgent) {
                assert!(e.clock_guard.is_empty(), "{}: {}", p.name, e.description);
            }
        }
        let count = net.labels.len();
        assert!(count > 0, "{}: labels", stem(&path));
    }
}

/// Every control codel, codel run by a thread, thread overrun and clocked
/// watchdog has its label, named after the service and codel.
#[test]
fn labels_name_services_codels_threads() {
    let c = component_of(Path::new("../specs/pilot.gen"));
    let net = network(&c);
    let names: BTreeSet<&str> = net.labels.iter().map(|l| l.name.as_str()).collect();
    for l in &net.labels {
        match l.kind {
            LabelKind::Codel(k) => {
                let codel = &c.codels[k];
                let svc = &c.services[codel.service].name.name;
                let want = if codel.kind == CodelKind::Control {
                    format!("codel_{svc}_control")
                } else {
                    format!("codel_{svc}_{}", codel.name.name)
                };
                assert_eq!(l.name, want);
            }
            LabelKind::Overrun(t) => {
                assert_eq!(l.name, format!("overrun_{}", c.threads[t].name.name));
            }
            LabelKind::Timeout(s) => {
                assert_eq!(l.name, format!("timeout_{}", c.services[s].name.name));
            }
        }
    }
    assert!(names.contains("codel_moveDistance_goto"), "{names:?}");
    assert!(names.contains("overrun_motionTask"), "{names:?}");
}
