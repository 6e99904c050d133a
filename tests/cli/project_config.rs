//! `genom-check.toml` and inline allows (issue 16, docs/configuration.md):
//! found by walking up from the checked file, `--config`, levels per code,
//! defaults that the command line overrides, inline
//! `genom-check: allow(...)` on one item, and errors pointing at the TOML.

#![allow(clippy::expect_used, clippy::unwrap_used)] // test support code

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use serde_json::Value;

fn genom_check() -> Command {
    let mut cmd = Command::cargo_bin("genom-check").expect("binary is built");
    cmd.env_remove("GENOM_INCLUDE_PATH").env("NO_COLOR", "1");
    cmd
}

/// A project folder holding `specs/pilot.gen` (as `sub/pilot.gen`) and,
/// when given, a `genom-check.toml` at its root.
fn project(config: Option<&str>, pilot: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("sub");
    std::fs::create_dir(&sub).unwrap();
    let file = sub.join("pilot.gen");
    std::fs::write(&file, pilot).unwrap();
    std::fs::copy("specs/demoStruct.idl", sub.join("demoStruct.idl")).unwrap();
    if let Some(c) = config {
        std::fs::write(dir.path().join("genom-check.toml"), c).unwrap();
    }
    (dir, file)
}

fn pilot() -> String {
    std::fs::read_to_string("specs/pilot.gen").unwrap()
}

/// Exit status and the one file's JSON entry.
fn json(args: &[&str], file: &Path) -> (i32, Value) {
    let out = genom_check()
        .args(["--format", "json"])
        .args(args)
        .arg(file)
        .output()
        .unwrap();
    let doc: Value = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stderr)));
    (out.status.code().unwrap(), doc["files"][0].clone())
}

fn codes(file: &Value) -> Vec<String> {
    file["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d["code"].as_str().unwrap().to_owned())
        .collect()
}

#[test]
fn without_configuration_pilot_reports_missing_wcet() {
    let (_dir, file) = project(None, &pilot());
    let (status, f) = json(&[], &file);
    assert_eq!(status, 0);
    assert_eq!(codes(&f), ["missing-wcet"]);
}

#[test]
fn a_configuration_above_the_file_that_allows_missing_wcet_silences_pilot() {
    let (_dir, file) = project(Some("[levels]\nmissing-wcet = \"allow\"\n"), &pilot());
    let (status, f) = json(&[], &file);
    assert_eq!(status, 0);
    assert!(codes(&f).is_empty(), "{f:#}");
}

#[test]
fn deny_makes_an_advice_an_error() {
    let (_dir, file) = project(Some("[levels]\nmissing-wcet = \"deny\"\n"), &pilot());
    let (status, f) = json(&[], &file);
    assert_eq!(status, 1);
    assert_eq!(f["diagnostics"][0]["severity"], "error");
}

#[test]
fn an_inline_allow_silences_one_item_only() {
    let text = pilot().replacen(
        "service moveDistance",
        "// genom-check: allow(missing-wcet)\nservice moveDistance",
        1,
    );
    assert_ne!(text, pilot(), "pilot.gen has a service moveDistance");
    let (_dir, file) = project(None, &text);
    let (status, f) = json(&[], &file);
    assert_eq!(status, 0);
    assert!(codes(&f).is_empty(), "{f:#}");
    // On another item (the thread), the same allow leaves the diagnostic.
    let elsewhere = pilot().replacen(
        "thread motionTask",
        "// genom-check: allow(missing-wcet)\nthread motionTask",
        1,
    );
    assert_ne!(elsewhere, pilot(), "pilot.gen has a thread motionTask");
    let (_d2, file2) = project(None, &elsewhere);
    assert_eq!(codes(&json(&[], &file2).1), ["missing-wcet"]);
}

#[test]
fn explicit_config_and_limits_with_the_command_line_winning() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("other.toml");
    std::fs::write(&cfg, "[limits]\nmax-states = 3\n").unwrap();
    let cfg_arg = cfg.to_str().unwrap();
    let pilot_path = Path::new("specs/pilot.gen");
    // `--engine explicit`: by default the symbolic engine would finish
    // what the state limit stopped.
    let explicit = ["--engine", "explicit", "--config", cfg_arg];
    let (_, f) = json(&explicit, pilot_path);
    assert!(codes(&f).contains(&"incomplete".to_owned()), "{f:#}");
    let (_, f) = json(
        &[&explicit[..], &["--max-states", "1000"]].concat(),
        pilot_path,
    );
    assert!(!codes(&f).contains(&"incomplete".to_owned()), "{f:#}");
}

#[test]
fn unknown_keys_codes_and_levels_are_errors_pointing_at_the_toml() {
    for (toml, expect, line) in [
        ("[limit]\nmax-states = 3\n", "unknown field `limit`", "1:2"),
        (
            "[levels]\nmissing-wcett = \"allow\"\n",
            "did you mean `missing-wcet`?",
            "2:1",
        ),
        (
            "[levels]\nmissing-wcet = \"off\"\n",
            "unknown level `off`",
            "2:16",
        ),
        (
            "[levels]\nincomplete = \"allow\"\n",
            "`incomplete` cannot be lowered",
            "2:1",
        ),
        ("dialect = \"genom4\"\n", "unknown dialect `genom4`", "1:11"),
        (
            "[limits]\ntimeout = \"soon\"\n",
            "is not a duration",
            "2:11",
        ),
    ] {
        let (_dir, file) = project(Some(toml), &pilot());
        let out = genom_check().arg(&file).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{toml}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(expect), "{toml}: {err}");
        assert!(
            err.contains(&format!("genom-check.toml:{line}")),
            "{toml}: {err}"
        );
    }
}

#[test]
fn an_unknown_code_in_an_inline_allow_is_an_error() {
    let text = format!("// genom-check: allow(missing-wcett)\n{}", pilot());
    let (_dir, file) = project(None, &text);
    let out = genom_check().arg(&file).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown code `missing-wcett`"));
}

#[test]
fn genom3_defaults_come_from_the_configuration() {
    // The dialect, the include folder and the WCET file of a GenoM3
    // component, all from the configuration (paths from its folder).
    let root = std::fs::canonicalize(".").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let gen_file = dir.path().join("r1.gen");
    std::fs::copy(
        "tests/fixtures/genom3/response/r1_paused_chain.gen",
        &gen_file,
    )
    .unwrap();
    let wcet = root.join("tests/fixtures/genom3/response/r1_paused_chain.wcet");
    let include = root.join("tests/fixtures/genom3/include");
    std::fs::write(
        dir.path().join("genom-check.toml"),
        format!(
            "dialect = \"genom3\"\ninclude = [{:?}]\n[wcet]\n\"r1.gen\" = {:?}\n",
            include.to_str().unwrap(),
            wcet.to_str().unwrap()
        ),
    )
    .unwrap();
    let (status, f) = json(&["--response-times"], &gen_file);
    assert_eq!(status, 0, "{f:#}");
    assert_eq!(f["dialect"], "genom3");
    // With the WCET file, no `missing-wcet`, and a response time.
    assert!(codes(&f).is_empty(), "{f:#}");
    assert_eq!(f["response_times"][0]["service"], "go", "{f:#}");
}
