//! Build script of the root crate: tells the differential tests which
//! reference tools this machine has, so that a test whose tool is missing
//! shows as `ignored` with its reason instead of passing without running.
//! `cfg(genom_spin)`: `spin` and `gcc` answer (or `GENOM_REQUIRE_SPIN=1`,
//! which makes their absence a failure); `cfg(genom_tchecker)`: `TCK_REACH`
//! names a file; `cfg(genom_divine)`: `DIVINE` names a file (DIVINE 3.3.2,
//! docs/testing/divine.md); `cfg(genom_sarif_schema)`: `SARIF_SCHEMA` names
//! the SARIF 2.1.0 JSON schema file.

use std::path::Path;
use std::process::{Command, Stdio};

fn answers(tool: &str, arg: &str) -> bool {
    Command::new(tool)
        .arg(arg)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

fn main() {
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-env-changed=PATH");
    println!("cargo::rerun-if-env-changed=GENOM_REQUIRE_SPIN");
    println!("cargo::rerun-if-env-changed=TCK_REACH");
    println!("cargo::rustc-check-cfg=cfg(genom_spin)");
    println!("cargo::rustc-check-cfg=cfg(genom_tchecker)");
    println!("cargo::rerun-if-env-changed=DIVINE");
    println!("cargo::rustc-check-cfg=cfg(genom_divine)");
    println!("cargo::rerun-if-env-changed=SARIF_SCHEMA");
    println!("cargo::rustc-check-cfg=cfg(genom_sarif_schema)");
    if std::env::var_os("SARIF_SCHEMA").is_some_and(|p| Path::new(&p).is_file()) {
        println!("cargo::rustc-cfg=genom_sarif_schema");
    }
    let required = std::env::var("GENOM_REQUIRE_SPIN").is_ok_and(|v| v == "1");
    if required || (answers("spin", "-V") && answers("gcc", "--version")) {
        println!("cargo::rustc-cfg=genom_spin");
    }
    if std::env::var_os("TCK_REACH").is_some_and(|p| Path::new(&p).is_file()) {
        println!("cargo::rustc-cfg=genom_tchecker");
    }
    if std::env::var_os("DIVINE").is_some_and(|p| Path::new(&p).is_file()) {
        println!("cargo::rustc-cfg=genom_divine");
    }
}
