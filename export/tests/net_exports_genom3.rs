//! The Petri-net exports (`pnml`, `tina`) of GenoM3 components: the net of
//! GenoM3's untimed semantics (`PetriNet::build_genom3`). Snapshots of two
//! fixtures, the PNML document checked against the net (places,
//! transitions, arcs, inhibitor arcs, priorities, initial marking), and
//! the TINA file's declarations against the net. The net's behaviour is
//! compared with the engine's verdicts, through the `.net` text read back
//! by a reader of TINA's format, in `tests/differential/petri_genom3.rs`.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

mod common;

use std::path::{Path, PathBuf};

use common::nets::{check_pnml, tina_name, tr_parts};
use genom_checker::CheckOptions;
use genom_model::component::Idx;
use genom_model::petri::{G3_PRIORITY_STEP, PetriNet};
use genom_translate::petri_genom3::BuildGenom3PetriNet;

const FIXTURES: [&str; 2] = ["f6_interrupt_stop", "f5_after_cycle"];

fn fixture(name: &str) -> PathBuf {
    Path::new("../tests/fixtures/genom3/semantics").join(format!("{name}.gen"))
}

fn checked(name: &str) -> common::CheckResult {
    common::check_genom3(&fixture(name), &[], None, &CheckOptions::new())
}

fn net(result: &common::CheckResult) -> PetriNet {
    let c = result.component.as_ref().expect("a component");
    PetriNet::build_genom3(c).expect("a GenoM3 component")
}

#[test]
fn pnml_of_genom3_fixtures() {
    for name in FIXTURES {
        let result = checked(name);
        let text = common::export(&result, genom_export::Format::Pnml);
        assert!(text.contains("Untimed semantics of GenoM3"), "{name}");
        insta::assert_snapshot!(format!("pnml_genom3__{name}"), text);
        check_pnml(&text, &net(&result), &fixture(name));
    }
}

#[test]
fn tina_of_genom3_fixtures() {
    for name in FIXTURES {
        let result = checked(name);
        let text = common::export(&result, genom_export::Format::Tina);
        insta::assert_snapshot!(format!("tina_genom3__{name}"), text);
        let net = net(&result);
        let declared: Vec<&str> = text
            .lines()
            .filter_map(|l| l.strip_prefix("pl "))
            .map(|l| l.split(' ').next().expect("place name"))
            .collect();
        let expected: Vec<String> = net.places.iter().map(|p| tina_name(&p.name)).collect();
        assert_eq!(declared, expected, "{name}: places in order");
        let trs: Vec<&str> = text.lines().filter(|l| l.starts_with("tr ")).collect();
        assert_eq!(trs.len(), net.transitions.len(), "{name}");
        for (line, t) in trs.iter().zip(&net.transitions) {
            let (tr, interval, inputs, outputs) = tr_parts(line);
            assert_eq!(tr, tina_name(&t.name));
            let urgent = if t.priority > G3_PRIORITY_STEP {
                "[0,0]"
            } else {
                "[0,w["
            };
            assert_eq!(interval, urgent, "{line}");
            let inhibitors: Vec<String> = inputs
                .iter()
                .filter_map(|a| a.strip_suffix("?-1"))
                .map(str::to_owned)
                .collect();
            let want: Vec<String> = t
                .inhibit
                .iter()
                .map(|&(p, _)| tina_name(&net.places[p.index()].name))
                .collect();
            assert_eq!(inhibitors, want, "{line}");
            assert_eq!(outputs.len(), t.post.len(), "{line}");
        }
        // Four levels: three `pr` lines.
        let pr = text.lines().filter(|l| l.starts_with("pr ")).count();
        assert_eq!(pr, 3, "{name}");
    }
}
