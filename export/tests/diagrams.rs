//! The `dot` and `svg` exports: snapshots for every file in `specs/`; every
//! codel named, `on-inter` edges dashed, the `stops`/`delays`/`forbids`
//! edges of the overview; the SVG parsed with `roxmltree`; the DOT text
//! rendered by Graphviz when it is installed.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

mod common;

use common::stem;

use common::export;

use std::collections::BTreeSet;
use std::path::Path;

use genom_export::Format;
use genom_model::component::Component;
use genom_model::kinds::CodelKind;

/// (service, codel, on-inter target) of every codel with an `on-inter`.
fn on_inters(c: &Component) -> Vec<(String, String, String)> {
    c.codels
        .iter()
        .filter_map(|(_, k)| {
            let to = k.on_inter.as_ref()?;
            Some((
                c.services[k.service].name.name.clone(),
                k.name.name.clone(),
                c.codels[to.id].name.name.clone(),
            ))
        })
        .collect()
}

#[test]
fn dot_of_every_spec() {
    for path in common::specs() {
        let result = common::check(&path);
        let c = result.component.as_ref().expect("component");
        let text = export(&result, Format::Dot);
        insta::assert_snapshot!(format!("dot__{}", stem(&path)), text);
        // Every codel is a node.
        for (_, k) in c.codels.iter() {
            let id = format!(
                "\"codel.{}.{}\" [",
                c.services[k.service].name.name, k.name.name
            );
            assert!(text.contains(&id), "{}: {id} missing", path.display());
        }
        // Every on-inter edge is dashed, and every dashed machine edge is
        // an on-inter edge.
        for (s, from, to) in on_inters(c) {
            let edge = format!("\"codel.{s}.{from}\" -> \"codel.{s}.{to}\" [");
            let line = text
                .lines()
                .find(|l| l.contains(&edge) && l.contains("on-inter"))
                .unwrap_or_else(|| panic!("{}: {edge} missing", path.display()));
            assert!(line.contains("style=dashed"), "{line}");
        }
        for line in text
            .lines()
            .filter(|l| l.contains("\"codel.") && l.contains(" -> "))
        {
            assert_eq!(
                line.contains("style=dashed"),
                line.contains("label=\"on-inter\""),
                "{line}"
            );
        }
        // Every stops/delays/forbids rule is an edge with its style.
        for (_, s) in c.services.iter() {
            for (rule, list, style) in [
                ("stops", &s.stops, "style=solid"),
                ("delays", &s.delays, "style=dashed"),
                ("forbids", &s.forbids, "style=dotted"),
            ] {
                for r in list {
                    let edge = format!(
                        "\"service.{}\" -> \"service.{}\" [",
                        s.name.name, c.services[r.id].name.name
                    );
                    let line = text
                        .lines()
                        .find(|l| l.contains(&edge) && l.contains(&format!("label=\"{rule}\"")))
                        .unwrap_or_else(|| panic!("{}: {rule} {edge}", path.display()));
                    assert!(line.contains(style), "{line}");
                }
            }
        }
        common::graphviz_accepts(&text, &path);
    }
}

/// Every piece of text of an SVG document.
fn svg_texts(doc: &roxmltree::Document<'_>) -> BTreeSet<String> {
    doc.descendants()
        .filter(|n| n.has_tag_name("tspan"))
        .filter_map(|n| n.text())
        .map(str::to_owned)
        .collect()
}

#[test]
fn svg_of_every_spec() {
    for path in common::specs() {
        let result = common::check(&path);
        let c = result.component.as_ref().expect("component");
        let text = export(&result, Format::Svg);
        insta::assert_snapshot!(format!("svg__{}", stem(&path)), text);
        let doc = roxmltree::Document::parse(&text).expect("well-formed XML");
        assert_eq!(doc.root_element().tag_name().name(), "svg");
        let texts = svg_texts(&doc);
        // Every codel and every service is named.
        for (_, k) in c.codels.iter() {
            assert!(
                texts.contains(&k.name.name),
                "{}: codel {} not named",
                path.display(),
                k.name.name
            );
        }
        for (_, s) in c.services.iter() {
            assert!(texts.contains(&s.name.name), "{}", path.display());
            let id = format!("machine.{}", s.name.name);
            assert!(
                doc.descendants()
                    .any(|n| n.attribute("id") == Some(id.as_str())),
                "{}: no diagram {id}",
                path.display()
            );
        }
        // The on-inter edges (legend excluded) are dashed, one per codel
        // with an on-inter.
        let paths: Vec<roxmltree::Node<'_, '_>> = doc
            .descendants()
            .filter(|n| n.has_tag_name("path"))
            .filter(|n| n.attribute("class") == Some("edge on-inter"))
            .collect();
        assert_eq!(paths.len(), on_inters(c).len(), "{}", path.display());
        for p in &paths {
            assert!(p.attribute("stroke-dasharray").is_some());
        }
        // The next edges are solid.
        for p in doc
            .descendants()
            .filter(|n| n.attribute("class") == Some("edge next"))
        {
            assert!(p.attribute("stroke-dasharray").is_none());
        }
        // One rule edge per distinct (service, rule, target).
        let rules: usize = c
            .services
            .iter()
            .map(|(_, s)| {
                [&s.stops, &s.delays, &s.forbids]
                    .iter()
                    .map(|l| l.iter().map(|r| r.id).collect::<BTreeSet<_>>().len())
                    .sum::<usize>()
            })
            .sum();
        let drawn = doc
            .descendants()
            .filter(|n| n.has_tag_name("path"))
            .filter(|n| {
                n.attribute("class")
                    .is_some_and(|c| c.starts_with("edge rule"))
            })
            .count();
        assert_eq!(drawn, rules, "{}", path.display());
    }
}

#[test]
fn svg_names_the_control_and_inter_codels_of_the_pilot() {
    let result = common::check(Path::new("../specs/pilot.gen"));
    let c = result.component.as_ref().expect("component");
    let kinds: BTreeSet<CodelKind> = c.codels.iter().map(|(_, k)| k.kind).collect();
    assert!(
        kinds.contains(&CodelKind::Inter),
        "the pilot has an inter codel"
    );
    let text = export(&result, Format::Svg);
    let doc = roxmltree::Document::parse(&text).expect("well-formed XML");
    let classes: BTreeSet<&str> = doc
        .descendants()
        .filter_map(|n| n.attribute("class"))
        .collect();
    assert!(classes.contains("node inter codel"), "{classes:?}");
    assert!(classes.contains("node end"));
}

#[test]
fn diagrams_are_deterministic() {
    let result = common::check(Path::new("../specs/mobileBase.gen"));
    for format in [Format::Dot, Format::Svg] {
        assert_eq!(export(&result, format), export(&result, format));
    }
}
