//! The `uppaal` and `tchecker` exports of GenoM3 components (the GenoM3
//! network, `Network::build_genom3`), on every timing fixture of
//! `tests/fixtures/genom3/timing/` with its WCET file: deterministic
//! output, well-formed files (the UPPAAL XML parses, every template and
//! process has one initial location, every edge joins declared locations
//! with a declared event, every integer starts within its range), urgent
//! edges without clock guards, and the UPPAAL queries (XML and `.q` file)
//! ask exactly the labels of the TChecker export.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use genom_checker::CheckOptions;
use genom_export::{ExportInput, Exported, Format, Verification};
use genom_model::component::Component;
use genom_model::timed_automata::{LabelKind, Network};
use genom_translate::timed_automata::BuildNetwork;

const TIMING: &str = "../tests/fixtures/genom3/timing";

/// Every timing fixture's component, read with its WCET file.
fn fixtures() -> Vec<(String, Component)> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(TIMING)
        .expect("the timing fixtures")
        .map(|e| e.expect("an entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "gen"))
        .collect();
    paths.sort();
    assert!(paths.len() >= 10, "the timing fixtures are there");
    paths
        .into_iter()
        .map(|path| {
            let wcet = path.with_extension("wcet");
            let r = common::check_genom3(&path, &[], Some(&wcet), &CheckOptions::new());
            let name = path
                .file_stem()
                .expect("a name")
                .to_string_lossy()
                .into_owned();
            (name, r.component.expect("a component"))
        })
        .collect()
}

fn export(format: Format, c: &Component) -> Exported {
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
    genom_export::export(format, &input).expect("the export succeeds")
}

#[test]
fn both_exports_are_deterministic() {
    for (name, c) in fixtures() {
        for format in [Format::Tchecker, Format::Uppaal] {
            let a = export(format, &c);
            let b = export(format, &c);
            assert_eq!(a, b, "{name}: {format:?} differs between two runs");
        }
        let net = Network::build_genom3(&c).expect("a GenoM3 network");
        assert_eq!(
            net,
            Network::build_genom3(&c).expect("a GenoM3 network"),
            "{name}"
        );
    }
}

#[test]
fn the_network_is_well_formed() {
    for (name, c) in fixtures() {
        let net = Network::build_genom3(&c).expect("a GenoM3 network");
        for v in &net.vars {
            assert!(v.min <= v.init && v.init <= v.max, "{name}: {}", v.name);
        }
        for p in &net.processes {
            let initial = p.locations.iter().filter(|l| l.initial).count();
            assert_eq!(initial, 1, "{name}: {} has one initial location", p.name);
            for e in &p.edges {
                assert!((e.from.0 as usize) < p.locations.len(), "{name}");
                assert!((e.to.0 as usize) < p.locations.len(), "{name}");
                assert!((e.event.0 as usize) < net.events.len(), "{name}");
                assert!(
                    !e.urgent || e.clock_guard.is_empty(),
                    "{name}: urgent edge with a clock guard: {}",
                    e.description
                );
            }
        }
        let overruns = net
            .labels
            .iter()
            .filter(|l| matches!(l.kind, LabelKind::Overrun(_)))
            .count();
        let periodic = c.threads.values().filter(|t| t.period.is_some()).count();
        assert_eq!(
            overruns, periodic,
            "{name}: one overrun label per periodic task"
        );
        // Labels name activities' codels (f9_fifo has only permanent ones).
        let activities = c
            .services
            .values()
            .any(|s| !s.codels.is_empty() && s.thread.is_some());
        assert_eq!(
            net.labels
                .iter()
                .any(|l| matches!(l.kind, LabelKind::Codel(_))),
            activities,
            "{name}: codel labels"
        );
    }
}

/// The labels of a TChecker file (checking its structure on the way; a
/// label may mark several locations of one process, a GenoM3 activity's
/// codel in each of its slots, never twice the same location).
fn tck_labels(text: &str) -> BTreeSet<String> {
    let mut events = BTreeSet::new();
    let mut locations: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut initial: BTreeMap<String, usize> = BTreeMap::new();
    let mut labels = BTreeSet::new();
    for line in text
        .lines()
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
    {
        let (head, attrs) = line.split_once('{').unwrap_or((line, ""));
        let head = head.split(" #").next().unwrap_or(head);
        let fields: Vec<&str> = head.trim().split(':').collect();
        match fields[0] {
            "event" => {
                events.insert(fields[1].to_owned());
            }
            "process" => {
                locations.insert(fields[1].to_owned(), BTreeSet::new());
            }
            "location" => {
                let set = locations.get_mut(fields[1]).expect("a declared process");
                assert!(set.insert(fields[2].to_owned()), "{line}");
                if attrs.contains("initial:") {
                    *initial.entry(fields[1].to_owned()).or_default() += 1;
                }
                if let Some(l) = attrs.split(" : ").find_map(|a| {
                    a.trim_start_matches('{')
                        .trim_end_matches('}')
                        .strip_prefix("labels: ")
                }) {
                    let mine: Vec<&str> = l.split(',').collect();
                    let distinct: BTreeSet<&str> = mine.iter().copied().collect();
                    assert_eq!(distinct.len(), mine.len(), "a label twice: {line}");
                    labels.extend(mine.into_iter().map(str::to_owned));
                }
            }
            "edge" => {
                let set = locations.get(fields[1]).expect("a declared process");
                assert!(set.contains(fields[2]) && set.contains(fields[3]), "{line}");
                assert!(events.contains(fields[4]), "{line}");
            }
            "system" | "clock" | "int" | "sync" => {}
            other => panic!("unknown declaration {other}: {line}"),
        }
    }
    for p in locations.keys() {
        assert_eq!(initial.get(p), Some(&1), "{p}: one initial location");
    }
    labels
}

fn parse_xml(xml: &str) -> roxmltree::Document<'_> {
    let options = roxmltree::ParsingOptions {
        allow_dtd: true,
        ..roxmltree::ParsingOptions::default()
    };
    roxmltree::Document::parse_with_options(xml, options).expect("well-formed XML")
}

/// The query formulas of an UPPAAL model (checking its templates).
fn uppaal_queries(xml: &str, net: &Network) -> Vec<String> {
    let doc = parse_xml(xml);
    let nta = doc.root_element();
    let templates: Vec<_> = nta
        .children()
        .filter(|n| n.has_tag_name("template"))
        .collect();
    assert_eq!(templates.len(), net.processes.len());
    for t in templates {
        let ids: BTreeSet<&str> = t
            .children()
            .filter(|n| n.has_tag_name("location"))
            .filter_map(|n| n.attribute("id"))
            .collect();
        let init = t
            .children()
            .find(|n| n.has_tag_name("init"))
            .and_then(|n| n.attribute("ref"))
            .expect("an initial location");
        assert!(ids.contains(init));
    }
    nta.descendants()
        .filter(|n| n.has_tag_name("formula"))
        .filter_map(|n| n.text())
        .map(str::to_owned)
        .collect()
}

#[test]
fn uppaal_queries_ask_the_labels_of_the_tchecker_export() {
    for (name, c) in fixtures() {
        let net = Network::build_genom3(&c).expect("a GenoM3 network");
        let tck = export(Format::Tchecker, &c).main;
        assert!(tck.contains("GenoM3's timed semantics"), "{name}: header");
        let labels = tck_labels(&tck);
        let expected: BTreeSet<String> = net.labels.iter().map(|l| l.name.clone()).collect();
        assert_eq!(labels, expected, "{name}: the TChecker labels");
        let uppaal = export(Format::Uppaal, &c);
        assert!(uppaal.main.contains("GenoM3's timed semantics"), "{name}");
        let queries = uppaal_queries(&uppaal.main, &net);
        // A GenoM3 component may stop for good without fault: no
        // deadlock query.
        assert!(
            !queries.iter().any(|q| q.contains("deadlock")),
            "{name}: {queries:?}"
        );
        // One query per label, over every location it marks.
        let mut places: BTreeMap<&str, Vec<String>> = BTreeMap::new();
        for l in &net.labels {
            let p = &net.processes[l.process.0 as usize];
            let at = format!("{}.{}", p.name, p.locations[l.location.0 as usize].name);
            places.entry(&l.name).or_default().push(at);
        }
        let mut asked = BTreeSet::new();
        for l in &net.labels {
            let at = match places[l.name.as_str()].as_slice() {
                [one] => one.clone(),
                many => format!("({})", many.join(" || ")),
            };
            let q = match l.kind {
                LabelKind::Codel(_) => format!("E<> {at}"),
                _ => format!("A[] not {at}"),
            };
            assert!(queries.contains(&q), "{name}: {q} for {}", l.name);
            asked.insert(l.name.clone());
        }
        assert_eq!(queries.len(), places.len(), "{name}: one query per label");
        assert_eq!(asked, labels, "{name}");
        let (suffix, q_file) = &uppaal.extra[0];
        assert_eq!(suffix, ".q");
        let in_file: Vec<&str> = q_file
            .lines()
            .filter(|l| !l.is_empty() && !l.starts_with("//") && !l.starts_with("/*"))
            .collect();
        assert_eq!(
            in_file, queries,
            "{name}: the .q file asks the same queries"
        );
    }
}

#[test]
fn an_activity_that_interrupts_itself_has_a_second_slot() {
    let all = fixtures();
    let get = |n: &str| {
        all.iter()
            .find(|(name, _)| name == n)
            .map(|(_, c)| c)
            .expect("the fixture")
    };
    let has_var = |net: &Network, v: &str| net.vars.iter().any(|x| x.name == v);
    // `move` does not interrupt itself: one slot.
    let one = Network::build_genom3(get("f4_instances")).expect("a GenoM3 network");
    assert!(has_var(&one, "st_move") && !has_var(&one, "st_move_2"));
    let two = Network::build_genom3(get("f10_restart")).expect("a GenoM3 network");
    assert!(has_var(&two, "st_track") && has_var(&two, "st_track_2"));
    assert!(has_var(&two, "st_plan") && !has_var(&two, "st_plan_2"));
    // Each of `track`'s codel labels marks its location in both slots.
    let mut places: BTreeMap<&str, Vec<String>> = BTreeMap::new();
    for l in &two.labels {
        let p = &two.processes[l.process.0 as usize];
        let at = format!("{}.{}", p.name, p.locations[l.location.0 as usize].name);
        places.entry(&l.name).or_default().push(at);
    }
    for state in ["start", "run"] {
        assert_eq!(
            places[format!("codel_track_{state}").as_str()],
            [
                format!("task_driver.track_{state}"),
                format!("task_driver.track_2_{state}")
            ]
        );
    }
    assert_eq!(places["codel_plan_start"].len(), 1);
    let uppaal = export(Format::Uppaal, get("f10_restart"));
    let queries = uppaal_queries(&uppaal.main, &two);
    assert!(
        queries.contains(&"E<> (task_driver.track_run || task_driver.track_2_run)".to_owned()),
        "{queries:?}"
    );
}

#[test]
fn a_language_md_component_keeps_the_zone_engine_network() {
    let path = Path::new("../specs/pilot.gen");
    let r = common::check_with(path, &CheckOptions::new().behaviour(false));
    let c = r.component.expect("a component");
    assert!(Network::build_genom3(&c).is_err());
    let tck = export(Format::Tchecker, &c).main;
    assert!(tck.contains("the timed automata of the zone engine"));
}
