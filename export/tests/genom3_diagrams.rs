//! The `dot` and `svg` exports of GenoM3 components, drawn in GenoM3's
//! words: snapshots of the fixtures of `common::GENOM3_DIAGRAM_FIXTURES`;
//! every task's permanent states and every activity's states drawn, the
//! `pause::` yields dashed and labelled `pause`, the immediate ones solid,
//! the functions and attributes listed in the control task's table (no
//! machine of their own); `uavatt` (when the corpus is there) shows its
//! `main` task machine and the `servo` activity with its `pause::` edges.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

mod common;

use common::stem;

use std::collections::BTreeSet;
use std::path::Path;

use common::{CheckResult, GENOM3_DIAGRAM_FIXTURES, export};
use genom_export::Format;
use genom_model::component::Component;
use genom_model::component::genom3::{FsmCodel, Genom3Info};

fn genom3(c: &Component) -> &Genom3Info {
    c.genom3.as_ref().expect("a GenoM3 component")
}

/// Every machine (`task-T` or the activity's name) and its FSM codels.
fn machines(c: &Component) -> Vec<(String, Vec<FsmCodel>)> {
    let g = genom3(c);
    let mut out = Vec::new();
    for t in g.tasks.iter().filter(|t| !t.codels.is_empty()) {
        let name = format!("task-{}", c.threads[t.thread].name.name);
        out.push((name, t.codels.clone()));
    }
    for info in g.services.iter().filter(|i| i.kind == "activity") {
        let s = &c.services[info.service];
        let mut fsm: Vec<FsmCodel> = Vec::new();
        for i in g.codels.iter().filter(|i| s.codels.contains(&i.codel)) {
            let known = fsm.iter().any(|f| f.span == i.fsm.span);
            if Some(i.codel) != s.control && !i.fsm.states.is_empty() && !known {
                fsm.push(i.fsm.clone());
            }
        }
        out.push((s.name.name.clone(), fsm));
    }
    out
}

/// The DOT edge of `machine` from state `from` to `to` (`ether` ends).
fn dot_edge(machine: &str, from: &str, to: &str) -> String {
    let to = if to == "ether" {
        format!("\"ether.{machine}\"")
    } else {
        format!("\"state.{machine}.{to}\"")
    };
    format!("\"state.{machine}.{from}\" -> {to} [")
}

/// The functions and attributes (the built-in `genom` ones included).
fn control_services(c: &Component) -> Vec<String> {
    genom3(c)
        .services
        .iter()
        .filter(|i| i.kind != "activity")
        .map(|i| c.services[i.service].name.name.clone())
        .collect()
}

fn check_dot(name: &str, c: &Component, text: &str) {
    for (m, fsm) in machines(c) {
        for f in &fsm {
            for st in &f.states {
                let node = format!("\"state.{m}.{}\" [", st.name);
                assert!(text.contains(&node), "{name}: {node} missing");
                for y in &f.yields {
                    let edge = dot_edge(&m, &st.name, &y.state.name);
                    let line = text
                        .lines()
                        .find(|l| l.contains(&edge))
                        .unwrap_or_else(|| panic!("{name}: {edge} missing"));
                    assert_eq!(line.contains("style=dashed"), y.pause, "{line}");
                    assert_eq!(line.contains("label=\"pause\""), y.pause, "{line}");
                }
            }
        }
    }
    for s in control_services(c) {
        assert!(text.contains(&s), "{name}: {s} not in the table");
        assert!(
            !text.contains(&format!("cluster_machine.{s}\"")),
            "{name}: {s} has a machine"
        );
    }
    assert!(text.contains("\"table.control\" [shape=plaintext, label=<<table"));
    assert!(text.contains("label=\"GenoM3 component "));
}

fn check_svg(name: &str, c: &Component, text: &str) {
    let doc = roxmltree::Document::parse(text).expect("well-formed XML");
    let ids: BTreeSet<&str> = doc
        .descendants()
        .filter_map(|n| n.attribute("id"))
        .collect();
    let texts: BTreeSet<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("tspan"))
        .filter_map(|n| n.text())
        .collect();
    let mut pauses = 0;
    for (m, fsm) in machines(c) {
        assert!(ids.contains(format!("machine.{m}").as_str()), "{name}: {m}");
        let mut edges = BTreeSet::new();
        for f in &fsm {
            for st in &f.states {
                let id = format!("state.{m}.{}", st.name);
                assert!(ids.contains(id.as_str()), "{name}: no node {id}");
                for y in f.yields.iter().filter(|y| y.pause) {
                    edges.insert((st.name.clone(), y.state.name.clone()));
                }
            }
        }
        pauses += edges.len();
    }
    let dashed: Vec<roxmltree::Node<'_, '_>> = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("edge pause"))
        .collect();
    assert_eq!(dashed.len(), pauses, "{name}: one dashed edge per pause::");
    for p in &dashed {
        assert!(p.attribute("stroke-dasharray").is_some(), "{name}");
    }
    for p in doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("edge yield"))
    {
        assert!(p.attribute("stroke-dasharray").is_none(), "{name}");
    }
    if pauses > 0 {
        assert!(texts.contains("pause"), "{name}: no pause label");
    }
    for s in control_services(c) {
        assert!(
            texts.iter().any(|t| t.split(", ").any(|w| w == s)),
            "{name}: {s} not in the table"
        );
        assert!(
            !ids.contains(format!("machine.{s}").as_str()),
            "{name}: {s}"
        );
    }
    assert!(ids.contains("table.control") && ids.contains("cluster.control"));
}

fn fixtures() -> Vec<(String, CheckResult)> {
    GENOM3_DIAGRAM_FIXTURES
        .iter()
        .map(|p| {
            let path = Path::new(p);
            (stem(path), common::check_genom3_fixture(path))
        })
        .collect()
}

#[test]
fn genom3_dot_of_the_fixtures() {
    for (name, result) in fixtures() {
        let c = result.component.as_ref().expect("component");
        let text = export(&result, Format::Dot);
        insta::assert_snapshot!(format!("dot__{name}"), text);
        check_dot(&name, c, &text);
        common::graphviz_accepts(&text, Path::new(&name));
    }
}

#[test]
fn genom3_svg_of_the_fixtures() {
    for (name, result) in fixtures() {
        let c = result.component.as_ref().expect("component");
        let text = export(&result, Format::Svg);
        insta::assert_snapshot!(format!("svg__{name}"), text);
        check_svg(&name, c, &text);
    }
}

#[test]
fn genom3_diagrams_are_deterministic() {
    for (_, result) in fixtures() {
        for format in [Format::Dot, Format::Svg] {
            assert_eq!(export(&result, format), export(&result, format));
        }
    }
}

/// The permanent task and the paused activity of the fixtures: `t`'s
/// states start, main, stop (`f3_permanent_lock`) and `servo`'s
/// `pause::main` edges (`f6_interrupt_stop`), with `kill` and the
/// interrupt leading to `stop`.
#[test]
fn the_permanent_task_and_the_paused_servo_are_drawn() {
    let f3 = common::check_genom3_fixture(Path::new(GENOM3_DIAGRAM_FIXTURES[0]));
    let dot = export(&f3, Format::Dot);
    for st in ["start", "main", "stop"] {
        assert!(dot.contains(&format!("\"state.task-t.{st}\" [")), "{st}");
    }
    assert!(dot.contains("label=\"main\\ncodel f3_main\\nWCET 9 ms\""));
    assert!(dot.contains("\"event.task-t.kill\" -> \"state.task-t.stop\" ["));
    let line = dot
        .lines()
        .find(|l| l.contains(&dot_edge("task-t", "main", "main")))
        .expect("main pauses into main");
    assert!(line.contains("style=dashed") && line.contains("label=\"pause\""));
    let f6 = common::check_genom3_fixture(Path::new(GENOM3_DIAGRAM_FIXTURES[3]));
    let dot = export(&f6, Format::Dot);
    for (from, to) in [("start", "main"), ("main", "main"), ("stop", "stop")] {
        let line = dot
            .lines()
            .find(|l| l.contains(&dot_edge("servo", from, to)))
            .unwrap_or_else(|| panic!("servo {from} -> {to}"));
        assert!(line.contains("label=\"pause\""), "{line}");
    }
    assert!(dot.contains("\"event.servo.interrupt\" -> \"state.servo.stop\" ["));
    let svg = export(&f6, Format::Svg);
    let doc = roxmltree::Document::parse(&svg).expect("XML");
    let servo = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("machine.servo"))
        .expect("the servo machine");
    let pauses = servo
        .descendants()
        .filter(|n| n.attribute("class") == Some("edge pause"))
        .count();
    assert_eq!(pauses, 3, "start -> main, main -> main, stop -> stop");
}

/// `uavatt` (skipped without the corpus): the `main` task's machine with
/// its four states and `measure`'s `pause::control`, the `servo` activity
/// with its `pause::start` loop, its functions and attributes in the table.
#[test]
fn uavatt_shows_main_and_the_paused_servo() {
    let Some(result) = common::check_uavatt() else {
        return;
    };
    let c = result.component.as_ref().expect("component");
    let dot = export(&result, Format::Dot);
    check_dot("uavatt", c, &dot);
    for st in ["start", "control", "measure", "stop"] {
        assert!(dot.contains(&format!("\"state.task-main.{st}\" [")), "{st}");
    }
    let line = dot
        .lines()
        .find(|l| l.contains(&dot_edge("task-main", "measure", "control")))
        .expect("measure pauses into control");
    assert!(line.contains("label=\"pause\""), "{line}");
    let line = dot
        .lines()
        .find(|l| l.contains(&dot_edge("servo", "start", "start")))
        .expect("servo's start pauses into start");
    assert!(line.contains("label=\"pause\""), "{line}");
    let svg = export(&result, Format::Svg);
    check_svg("uavatt", c, &svg);
    for id in [
        "machine.task-main",
        "machine.servo",
        "state.task-main.measure",
    ] {
        assert!(svg.contains(&format!("id=\"{id}\"")), "{id}");
    }
}
