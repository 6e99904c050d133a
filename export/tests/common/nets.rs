//! Checks shared by the Petri-net export tests of both languages: the
//! PNML document against the net it prints, and the reading of TINA's
//! `.net` lines.

use std::collections::BTreeSet;
use std::path::Path;

use genom_model::component::Idx;
use genom_model::petri::PetriNet;

/// The PNML document is well-formed, a P/T net, and has the net's places,
/// transitions, arcs, read and inhibitor arcs and priorities.
pub fn check_pnml(text: &str, net: &PetriNet, path: &Path) {
    let doc = roxmltree::Document::parse(text).expect("well-formed XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "pnml");
    assert_eq!(
        root.tag_name().namespace(),
        Some(genom_export::pnml::NAMESPACE)
    );
    let net_el = root
        .children()
        .find(|n| n.has_tag_name((genom_export::pnml::NAMESPACE, "net")))
        .expect("a net");
    assert_eq!(net_el.attribute("type"), Some(genom_export::pnml::PTNET));
    let elements = |name: &str| -> Vec<roxmltree::Node<'_, '_>> {
        doc.descendants()
            .filter(|n| n.has_tag_name((genom_export::pnml::NAMESPACE, name)))
            .collect()
    };
    let places: BTreeSet<&str> = elements("place")
        .iter()
        .filter_map(|n| n.attribute("id"))
        .collect();
    let transitions: Vec<&str> = elements("transition")
        .iter()
        .filter_map(|n| n.attribute("id"))
        .collect();
    assert_eq!(places.len(), net.places.len(), "{}", path.display());
    assert_eq!(
        transitions.len(),
        net.transitions.len(),
        "{}",
        path.display()
    );
    for p in &net.places {
        assert!(places.contains(p.name.as_str()), "place {} missing", p.name);
    }
    // Every arc joins a place and a transition.
    let tset: BTreeSet<&str> = transitions.iter().copied().collect();
    for arc in elements("arc") {
        let (s, t) = (
            arc.attribute("source").expect("source"),
            arc.attribute("target").expect("target"),
        );
        assert!(
            (places.contains(s) && tset.contains(t)) || (tset.contains(s) && places.contains(t)),
            "arc {s} -> {t}"
        );
    }
    // Inhibitor arcs and priorities, per transition, as in the net.
    for (t, el) in net.transitions.iter().zip(elements("transition")) {
        assert_eq!(el.attribute("id"), Some(t.name.as_str()));
        let inhibitors: Vec<&str> = el
            .descendants()
            .filter(|n| n.tag_name().name() == "inhibitor")
            .filter_map(|n| n.attribute("place"))
            .collect();
        let expected: Vec<&str> = t
            .inhibit
            .iter()
            .map(|&(p, _)| net.places[p.index()].name.as_str())
            .collect();
        assert_eq!(inhibitors, expected, "inhibitors of {}", t.name);
        let level = el
            .descendants()
            .find(|n| n.tag_name().name() == "priority")
            .and_then(|n| n.attribute("level"));
        assert_eq!(level, Some(t.priority.to_string().as_str()), "{}", t.name);
    }
    // The initial marking.
    for (p, el) in net.places.iter().zip(elements("place")) {
        let k = net
            .places
            .iter()
            .position(|q| q.name == p.name)
            .expect("place");
        let marking = el
            .descendants()
            .find(|n| n.tag_name().name() == "initialMarking")
            .and_then(|n| n.descendants().find(|d| d.is_text()))
            .and_then(|n| n.text())
            .map_or(0, |s| s.parse::<u32>().expect("a count"));
        assert_eq!(marking, net.initial[k], "marking of {}", p.name);
    }
}

/// A TINA name as written (between braces or plain).
pub fn tina_name(name: &str) -> String {
    if name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && name.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
    {
        name.to_owned()
    } else {
        format!("{{{name}}}")
    }
}

/// Splits a `tr` line into (name, interval, inputs, outputs).
pub fn tr_parts(line: &str) -> (String, String, Vec<String>, Vec<String>) {
    let rest = line.strip_prefix("tr ").expect("a tr line");
    let mut words = rest.split(' ');
    let name = words.next().expect("name").to_owned();
    let interval = words.next().expect("interval").to_owned();
    let words: Vec<&str> = words.collect();
    let arrow = words.iter().position(|w| *w == "->").expect("->");
    let inputs = words[..arrow].iter().map(|s| (*s).to_owned()).collect();
    let outputs = words[arrow + 1..].iter().map(|s| (*s).to_owned()).collect();
    (name, interval, inputs, outputs)
}
