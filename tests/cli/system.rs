//! `check --system`: a functional layer's port checks, chains and
//! deadlines, on small systems written here and on the drone stack of the
//! corpus (when it is on this machine).

use std::fs;

use assert_cmd::Command;
use predicates::prelude::*;
use serde_json::Value;

use crate::common;

fn genom_check() -> Command {
    let mut cmd = Command::cargo_bin("genom-check").expect("binary is built");
    cmd.env_remove("NO_COLOR").env("TERM", "xterm");
    cmd
}

/// A folder with two one-task components (`a` reads `inp`, writes `outp`;
/// `b` reads `inp`), their WCET files, and `system.toml` = `toml`.
fn layer(toml: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("temp dir");
    let a = "struct sample { double v; };\ncomponent a {\n  port in sample inp;\n  port out sample outp;\n  task t {\n    period 4 ms;\n    codel<start> s() yield k;\n    codel<k> f(port in inp, port out outp) yield pause::k;\n  };\n};\n";
    let b = "struct sample { double v; };\ncomponent b {\n  port in sample inp;\n  task t {\n    period 2 ms;\n    codel<start> s() yield k;\n    codel<k> f(port in inp) yield pause::k;\n  };\n};\n";
    fs::write(dir.path().join("a.gen"), a).expect("write");
    fs::write(dir.path().join("b.gen"), b).expect("write");
    fs::write(dir.path().join("a.wcet"), "t.start 0ms\nt.k 1ms\n").expect("write");
    fs::write(dir.path().join("b.wcet"), "t.start 0ms\nt.k 1ms\n").expect("write");
    fs::write(dir.path().join("system.toml"), toml).expect("write");
    dir
}

const WIRED: &str = "[component.a]\nfile = \"a.gen\"\nwcet = \"a.wcet\"\n\
[component.b]\nfile = \"b.gen\"\nwcet = \"b.wcet\"\n\
[external.src]\nperiod = \"1ms\"\nfeeds = [\"a.inp\"]\n\
[[connect]]\nfrom = \"a.outp\"\nto = \"b.inp\"\n";

/// src (1 ms) -> a (4 ms, its codel ends within 1 ms of its tick) -> b
/// (2 ms, within 1 ms): data age 1 + (4 + 1) + 1 = 7 ms, reaction
/// (4 + 1) + (2 + 1) = 8 ms; within 20 ms, over 5 ms.
#[test]
fn a_chain_within_and_over_its_deadline() {
    let dir = layer(WIRED);
    let system = dir.path().join("system.toml");
    let out = genom_check()
        .args(["--format", "json", "check", "--system"])
        .arg(&system)
        .args(["--chain", "src->b.inp<=20ms"])
        .assert()
        .code(0)
        .get_output()
        .stdout
        .clone();
    let json: Value = serde_json::from_slice(&out).expect("JSON");
    let chain = &json["system"]["requests"][0]["chains"][0];
    assert_eq!(chain["data_age_ns"], 7_000_000);
    assert_eq!(chain["reaction_ns"], 8_000_000);
    let trace = chain["age_trace"].as_array().expect("a timeline");
    assert_eq!(trace.last().expect("steps")["time_ns"], 7_000_000);
    genom_check()
        .args(["check", "--system"])
        .arg(&system)
        .args(["--chain", "src->b.inp<=5ms"])
        .assert()
        .code(1)
        .stdout(predicate::str::contains("chain-deadline-miss"))
        .stdout(predicate::str::contains("data age 7ms"));
}

#[test]
fn port_errors_point_into_the_system_file() {
    let toml = WIRED.replace("from = \"a.outp\"", "from = \"a.outq\"");
    let dir = layer(&toml);
    genom_check()
        .args(["check", "--system"])
        .arg(dir.path().join("system.toml"))
        .assert()
        .code(1)
        .stdout(predicate::str::contains("unknown-system-name"))
        .stdout(predicate::str::contains("did you mean `outp`?"))
        .stdout(predicate::str::contains("system.toml:11:"))
        // `b.inp` is now fed by nothing.
        .stdout(predicate::str::contains("unconnected-input"));
}

#[test]
fn a_system_file_that_does_not_parse_is_bad_system() {
    let dir = layer("[component.a]\nfile = 3\n");
    genom_check()
        .args(["check", "--system"])
        .arg(dir.path().join("system.toml"))
        .assert()
        .code(1)
        .stdout(predicate::str::contains("bad-system"));
    genom_check()
        .args(["explain", "chain-deadline-miss"])
        .assert()
        .code(0)
        .stdout(predicate::str::contains("docs/functional-layer.md"));
}

/// The drone stack: every chain to the motors has a bound, which its
/// stages' periods and windows give again (g0 + sum of P + W, + W of the
/// sink, each window within its period) and its timeline reaches; 30 ms
/// holds for the trajectory chain.
#[test]
fn the_drone_stack() {
    if common::genom3_corpus().is_none() {
        return;
    }
    let out = genom_check()
        .args(["--format", "json", "check", "--system"])
        .arg(common::root().join("tests/fixtures/genom3/system/drone.toml"))
        .args(["-I", "tests/fixtures/genom3/include"])
        .current_dir(common::root())
        .assert()
        .code(0)
        .get_output()
        .stdout
        .clone();
    let json: Value = serde_json::from_slice(&out).expect("JSON");
    let requests = json["system"]["requests"].as_array().expect("requests");
    assert_eq!(requests.len(), 2);
    for r in requests {
        let chains = r["chains"].as_array().expect("chains");
        assert!(!chains.is_empty());
        for ch in chains {
            let age = ch["data_age_ns"].as_u64().expect("bounded");
            let stages = ch["stages"].as_array().expect("stages");
            let w = |s: &Value| s["window_ns"].as_u64().expect("window");
            let p = |s: &Value| s["period_ns"].as_u64().expect("period");
            let (last, before) = stages.split_last().expect("a sink");
            let hops: u64 = before.iter().map(|s| p(s) + w(s)).sum();
            // The source's gap: the pose period, or a period of
            // `maneuver.exec` (5 ms) plus its writers' window.
            let g0 = ch["source_gap_ns"].as_u64().expect("a gap");
            if ch["source"] == "pose" {
                assert_eq!(g0, 1_000_000, "{ch}");
            } else {
                assert!((5_000_000..=10_000_000).contains(&g0), "{ch}");
            }
            assert_eq!(age, g0 + hops + w(last), "{ch}");
            assert!(stages.iter().all(|s| w(s) <= p(s)), "{ch}");
            let steps = ch["age_trace"].as_array().expect("timeline");
            assert_eq!(steps.last().expect("steps")["time_ns"].as_u64(), Some(age));
            assert_eq!(last["component"], "rotorcraft");
        }
    }
    let trajectory = &requests[0]["chains"][0];
    assert_eq!(trajectory["source"], "maneuver.desired");
    assert!(trajectory["data_age_ns"].as_u64().expect("age") <= 30_000_000);
}
