//! The Petri-net exports (`pnml`, `tina`) and the `fiacre` export:
//! snapshots for every file in `specs/`, and structural checks against the
//! component's net (`PetriNet::build`): PNML parsed with `roxmltree`, every
//! TINA place declared and every inhibitor arc present, codel WCETs as
//! intervals, every Fiacre process in the root `par` and every name
//! declared.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

mod common;

use common::stem;

use common::nets::{check_pnml, tina_name, tr_parts};

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use common::CheckResult;
use genom_export::{ExportInput, Format, Verification};
use genom_model::behaviour::Behaviour;
use genom_model::component::Idx;
use genom_model::kinds::CodelKind;
use genom_model::petri::{PRIORITY_STEP, PetriNet, TransitionKind};
use genom_translate::petri::BuildPetriNet;
use genom_translate::timed_automata::BuildNetwork;

/// Exports `path` in `format` with a fixed verification record.
fn export(result: &CheckResult, format: Format) -> String {
    let component = result.component.as_ref().expect("spec has a component");
    let verification = Verification {
        verified: true,
        complete: true,
        properties: vec!["deadlock-freedom".to_owned()],
        tool_version: "0.0.0-test".to_owned(),
        ..Verification::default()
    };
    let input = ExportInput {
        component,
        sources: &result.sources,
        verification: &verification,
    };
    let exported = genom_export::export(format, &input).expect("export succeeds");
    assert!(exported.extra.is_empty(), "no companion file");
    exported.main
}

fn net_of(result: &CheckResult) -> PetriNet {
    let c = result.component.as_ref().expect("component");
    PetriNet::build(c, &Behaviour::new(c))
}

#[test]
fn pnml_of_every_spec() {
    for path in common::specs() {
        let result = common::check(&path);
        let text = export(&result, Format::Pnml);
        insta::assert_snapshot!(format!("pnml__{}", stem(&path)), text);
        check_pnml(&text, &net_of(&result), &path);
    }
}

#[test]
fn tina_of_every_spec() {
    for path in common::specs() {
        let result = common::check(&path);
        let text = export(&result, Format::Tina);
        insta::assert_snapshot!(format!("tina__{}", stem(&path)), text);
        check_tina(&text, &result, &path);
    }
}

fn check_tina(text: &str, result: &CheckResult, path: &Path) {
    let c = result.component.as_ref().expect("component");
    let behaviour = Behaviour::new(c);
    let net = PetriNet::build(c, &behaviour);
    let declared: BTreeSet<&str> = text
        .lines()
        .filter_map(|l| l.strip_prefix("pl "))
        .map(|l| l.split(' ').next().expect("place name"))
        .collect();
    assert_eq!(declared.len(), net.places.len(), "{}", path.display());
    let trs: Vec<&str> = text.lines().filter(|l| l.starts_with("tr ")).collect();
    assert_eq!(trs.len(), net.transitions.len(), "{}", path.display());
    let mut inhibitors = 0;
    for (line, t) in trs.iter().zip(&net.transitions) {
        let (name, interval, inputs, outputs) = tr_parts(line);
        assert_eq!(name, tina_name(&t.name));
        // Every place of the transition is declared.
        for arc in inputs.iter().chain(&outputs) {
            let place = arc.split(['?', '*']).next().expect("place");
            assert!(declared.contains(place), "{line}: {place} not declared");
        }
        // The inhibitor arcs of the net, and only those, are `?-1`.
        let inh: Vec<String> = inputs
            .iter()
            .filter_map(|a| a.strip_suffix("?-1"))
            .map(str::to_owned)
            .collect();
        let expected: Vec<String> = t
            .inhibit
            .iter()
            .map(|&(p, _)| tina_name(&net.places[p.index()].name))
            .collect();
        assert_eq!(inh, expected, "{line}");
        inhibitors += inh.len();
        let reads = inputs.iter().filter(|a| a.ends_with("?1")).count();
        assert_eq!(reads, t.read.len(), "{line}");
        // Intervals: urgent above priority 0, [0,w] for a codel's WCET.
        let expected = if t.priority > PRIORITY_STEP {
            "[0,0]".to_owned()
        } else {
            match wcet_of_finish(c, &behaviour, t.kind) {
                Some(units) => format!("[0,{units}]"),
                None => "[0,w[".to_owned(),
            }
        };
        assert_eq!(interval, expected, "{line}");
    }
    let total: usize = net.transitions.iter().map(|t| t.inhibit.len()).sum();
    assert_eq!(inhibitors, total);
    assert!(
        total > 0,
        "{}: every spec has inhibitor arcs",
        path.display()
    );
    // One `pr` line per level that has a higher level.
    let levels: BTreeSet<u8> = net.transitions.iter().map(|t| t.priority).collect();
    let pr = text.lines().filter(|l| l.starts_with("pr ")).count();
    assert_eq!(pr, levels.len().saturating_sub(1), "{}", path.display());
}

/// The WCET, in the unit of the header, of the codel a finish transition
/// ends.
fn wcet_of_finish(
    c: &genom_model::component::Component,
    b: &Behaviour,
    kind: TransitionKind,
) -> Option<u64> {
    let TransitionKind::Finish(s, p, _) = kind else {
        return None;
    };
    let codel = b.machine(s).positions[usize::from(p)].codel()?;
    let unit = genom_model::timed_automata::Network::build(c, b).unit_ns;
    c.codels[codel].wcet.map(|w| w.ns / unit)
}

#[test]
fn tina_gives_the_camera_codels_their_wcet() {
    // camera.gen has a WCET on every codel; the unit is 10 us and Open's
    // start codel has a WCET of 500 ms.
    let result = common::check(Path::new("../specs/camera.gen"));
    let text = export(&result, Format::Tina);
    assert!(
        text.contains("# Time: 1 unit = 10 µs (10000 ns)."),
        "the unit is stated"
    );
    let finishes: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with("tr ") && l.contains(".finish."))
        .collect();
    assert!(!finishes.is_empty());
    for line in &finishes {
        assert!(!line.contains("[0,w["), "untimed finish: {line}");
    }
    assert!(
        text.contains("tr {Open.finish.run.start.0} [0,50000] {Open.run.start} ->"),
        "Open's start codel ends within 500 ms"
    );
}

#[test]
fn fiacre_of_every_spec() {
    for path in common::specs() {
        let result = common::check(&path);
        let text = export(&result, Format::Fiacre);
        insta::assert_snapshot!(format!("fiacre__{}", stem(&path)), text);
        check_fiacre(&text, &result, &path);
    }
}

/// Removes `/* */` comments.
fn strip_comments(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(start) = rest.find("/*") {
        out.push_str(&rest[..start]);
        let end = rest[start..].find("*/").expect("closed comment");
        rest = &rest[start + end + 2..];
    }
    out.push_str(rest);
    out
}

/// Structural checks of the Fiacre text.
fn check_fiacre(text: &str, result: &CheckResult, path: &Path) {
    let code = strip_comments(text);
    let c = result.component.as_ref().expect("component");
    let net = net_of(result);
    let words: Vec<&str> = code.split_whitespace().collect();
    let after = |kw: &str| -> Vec<&str> {
        words
            .windows(2)
            .filter(|w| w[0] == kw)
            .map(|w| w[1])
            .collect()
    };
    // Processes and the root par.
    let processes = after("process");
    assert_eq!(processes, vec![genom_export::fiacre::PROCESS]);
    let par_start = code.find("par * in").expect("a par");
    let par_end = par_start + code[par_start..].find("end").expect("par end");
    let par = &code[par_start + "par * in".len()..par_end];
    let instances: BTreeSet<&str> = par.split("||").map(str::trim).collect();
    for p in &processes {
        assert!(
            instances.contains(p),
            "{}: {p} not in the root par",
            path.display()
        );
    }
    // The root component is declared and named after the component list.
    let components = after("component");
    assert_eq!(components.len(), 1);
    let root = components[0];
    assert!(
        code.lines().any(|l| l.trim() == root),
        "{}: the root component is instantiated",
        path.display()
    );
    // Every state referenced exists.
    let states: BTreeSet<&str> = after("states").into_iter().collect();
    for s in after("to").into_iter().chain(after("from")) {
        assert!(
            states.contains(s),
            "{}: state {s} is not declared",
            path.display()
        );
    }
    // Every place constant used is declared, once per place.
    let consts: BTreeSet<&str> = after("const").into_iter().collect();
    assert_eq!(consts.len(), net.places.len());
    for used in code.split("m[").skip(1) {
        let name = used.split(']').next().expect("index");
        assert!(
            consts.contains(name),
            "{}: {name} not declared",
            path.display()
        );
    }
    // One alternative per transition, and the marking's size.
    let loops = code.lines().filter(|l| l.trim() == "loop").count();
    assert_eq!(loops, net.transitions.len());
    assert!(code.contains(&format!("array {} of bool", net.places.len())));
    // Every level function used is declared.
    let functions: BTreeSet<&str> = after("function").into_iter().collect();
    for level in 1..=4 {
        assert!(functions.contains(format!("level_{level}").as_str()));
    }
    // Properties: every assert names a property; one reachability property
    // per start, exec and inter codel; paths name the root component.
    let properties: BTreeSet<&str> = after("property").into_iter().collect();
    let asserts = after("assert");
    for a in &asserts {
        assert!(
            properties.contains(a),
            "{}: assert {a} without property",
            path.display()
        );
    }
    assert!(properties.contains("deadlock_free"));
    let codels = c
        .codels
        .iter()
        .filter(|(_, k)| k.kind != CodelKind::Control)
        .count();
    let reach = properties
        .iter()
        .filter(|p| p.starts_with("reach_"))
        .count();
    let dead = text.matches("(it is dead by construction)").count();
    assert_eq!(reach + dead, codels, "{}", path.display());
    for line in code.lines().filter(|l| l.starts_with("property reach_")) {
        assert!(
            line.contains(&format!("[] not ({root}/1/value (")),
            "{line}"
        );
    }
}

#[test]
fn fiacre_reachability_names_the_running_places() {
    // In the pilot, moveDistance::goto runs at `run.goto` and, interrupted,
    // at `runint.goto`: both are in its property.
    let result = common::check(Path::new("../specs/pilot.gen"));
    let text = export(&result, Format::Fiacre);
    let line = text
        .lines()
        .find(|l| l.starts_with("property reach_moveDistance_goto "))
        .expect("a property for goto");
    assert!(line.contains("m[p_moveDistance_run_goto]"), "{line}");
    assert!(line.contains("m[p_moveDistance_runint_goto]"), "{line}");
}

#[test]
fn exports_are_deterministic() {
    let result = common::check(Path::new("../specs/mobileBase.gen"));
    for format in [Format::Pnml, Format::Tina, Format::Fiacre] {
        assert_eq!(export(&result, format), export(&result, format));
    }
}

/// Counts, for the log: (places, transitions, inhibitor arcs) per spec.
#[test]
fn net_sizes_are_those_of_the_net() {
    let mut sizes = BTreeMap::new();
    for path in common::specs() {
        let result = common::check(&path);
        let net = net_of(&result);
        let inh: usize = net.transitions.iter().map(|t| t.inhibit.len()).sum();
        sizes.insert(stem(&path), (net.places.len(), net.transitions.len(), inh));
        let tina = export(&result, Format::Tina);
        assert!(tina.contains(&format!(
            "# {} places, {} transitions.",
            net.places.len(),
            net.transitions.len()
        )));
    }
    assert_eq!(sizes.len(), common::specs().len());
}

/// A guard atom of the Fiacre text.
#[derive(Debug, Clone, Copy)]
enum Atom {
    /// `m[p]` (true) or `not m[p]` (false).
    Place(usize, bool),
    /// `not level_K (m)`.
    NotLevel(u8),
}

/// One `select` alternative: its guard and its updates.
#[derive(Debug, Clone)]
struct Alternative {
    guard: Vec<Atom>,
    updates: Vec<(usize, bool)>,
}

fn place_atom(word: &str, consts: &BTreeMap<String, usize>) -> usize {
    let name = word
        .trim_start_matches("m[")
        .trim_end_matches([']', ')', ';']);
    *consts
        .get(name)
        .unwrap_or_else(|| panic!("unknown place {name}"))
}

/// Parses a conjunction of `m[p]`, `not m[p]` and `not level_K (m)`.
fn conjunction(text: &str, consts: &BTreeMap<String, usize>) -> Vec<Atom> {
    let text = text.replace('\n', " ").replace("(m)", "");
    let text = text.trim().trim_start_matches('(').trim_end_matches(')');
    text.split(" and ")
        .map(str::trim)
        .map(|a| match a.strip_prefix("not ") {
            Some(rest) if rest.starts_with("level_") => {
                Atom::NotLevel(rest[6..].trim().parse().expect("a level"))
            }
            Some(rest) => Atom::Place(place_atom(rest, consts), false),
            None => Atom::Place(place_atom(a, consts), true),
        })
        .collect()
}

/// The consts, level functions and alternatives of a Fiacre export.
fn parse_fiacre(text: &str) -> (BTreeMap<u8, Vec<Vec<Atom>>>, Vec<Alternative>) {
    let code = strip_comments(text);
    let mut consts = BTreeMap::new();
    for line in code.lines().filter(|l| l.starts_with("const ")) {
        let words: Vec<&str> = line.split_whitespace().collect();
        consts.insert(
            words[1].to_owned(),
            words[5].parse::<usize>().expect("index"),
        );
    }
    let mut levels = BTreeMap::new();
    for part in code.split("function level_").skip(1) {
        let level: u8 = part[..1].parse().expect("level");
        let body = part
            .split("return")
            .nth(1)
            .and_then(|b| b.split("\n  end").next())
            .expect("body");
        let terms = if body.trim() == "false" {
            Vec::new()
        } else {
            body.split("\n      or ")
                .map(|t| conjunction(t, &consts))
                .collect()
        };
        levels.insert(level, terms);
    }
    let select = code.split("    select\n").nth(1).expect("a select");
    let select = select.split("\n    end").next().expect("select end");
    let alternatives = select
        .split("\n    [] ")
        .map(|alt| {
            let alt = alt.trim_start();
            let (guard, rest) = alt
                .strip_prefix("on ")
                .and_then(|a| a.split_once(';'))
                .expect("a guard");
            let updates = rest
                .split(';')
                .map(str::trim)
                .filter(|s| s.starts_with("m["))
                .map(|s| {
                    let (lhs, rhs) = s.split_once(" := ").expect("assignment");
                    (place_atom(lhs, &consts), rhs == "true")
                })
                .collect();
            Alternative {
                guard: conjunction(guard, &consts),
                updates,
            }
        })
        .collect();
    (levels, alternatives)
}

/// Runs the Fiacre alternatives as written over every reachable marking of
/// the net (up to a bound) and checks that they allow exactly the net's
/// steps under its priority rule.
#[test]
fn fiacre_alternatives_are_the_net_with_priorities() {
    for name in ["pilot", "camera", "battery", "arm"] {
        let result = common::check(Path::new(&format!("../specs/{name}.gen")));
        let net = net_of(&result);
        let (levels, alternatives) = parse_fiacre(&export(&result, Format::Fiacre));
        assert_eq!(alternatives.len(), net.transitions.len());
        let holds = |atoms: &[Atom], m: &[bool], levels: &BTreeMap<u8, Vec<Vec<Atom>>>| {
            atoms.iter().all(|a| match *a {
                Atom::Place(p, v) => m[p] == v,
                Atom::NotLevel(k) => !levels[&k].iter().any(|t| {
                    t.iter()
                        .all(|a| matches!(*a, Atom::Place(p, v) if m[p] == v))
                }),
            })
        };
        let start: Vec<bool> = net.initial.iter().map(|&n| n > 0).collect();
        let mut seen = BTreeSet::from([start.clone()]);
        let mut queue = vec![start];
        while let Some(m) = queue.pop() {
            let counts: Vec<u32> = m.iter().map(|&b| u32::from(b)).collect();
            let enabled: Vec<bool> = net.transitions.iter().map(|t| t.enabled(&counts)).collect();
            let top = net
                .transitions
                .iter()
                .zip(&enabled)
                .filter(|(_, e)| **e)
                .map(|(t, _)| t.priority)
                .max();
            for (k, (t, alt)) in net.transitions.iter().zip(&alternatives).enumerate() {
                let fires = enabled[k] && Some(t.priority) == top;
                assert_eq!(holds(&alt.guard, &m, &levels), fires, "{name}: {}", t.name);
                if !fires {
                    continue;
                }
                let mut next = m.clone();
                for &(p, v) in &alt.updates {
                    next[p] = v;
                }
                let mut expected = counts.clone();
                for &(p, w) in &t.pre {
                    expected[p.index()] -= w;
                }
                for &(p, w) in &t.post {
                    expected[p.index()] += w;
                }
                let expected: Vec<bool> = expected.iter().map(|&n| n > 0).collect();
                assert_eq!(next, expected, "{name}: update of {}", t.name);
                if seen.len() < 20_000 && seen.insert(next.clone()) {
                    queue.push(next);
                }
            }
        }
        assert!(seen.len() > 1, "{name}: the model moves");
    }
}
