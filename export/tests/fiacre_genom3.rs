//! The `fiacre` export of GenoM3 components (scratch).

#![allow(clippy::expect_used)]

mod common;

use std::path::Path;

#[test]
fn scratch() {
    for name in ["f1b_chain_overrun", "f11_hidden", "f3_partial"] {
        let p = Path::new("../tests/fixtures/genom3/timing").join(format!("{name}.gen"));
        let r = common::check_genom3_fixture(&p);
        let c = r.component.as_ref().expect("c");
        let v = genom_export::Verification::default();
        let input = genom_export::ExportInput { component: c, sources: &r.sources, verification: &v };
        match genom_export::export(genom_export::Format::Fiacre, &input) {
            Ok(e) => std::fs::write(format!("/tmp/fc/{name}.fcr"), e.main).expect("w"),
            Err(e) => std::fs::write(format!("/tmp/fc/{name}.err"), e.to_string()).expect("w"),
        }
    }
}
