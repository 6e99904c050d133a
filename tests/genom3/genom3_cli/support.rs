//! Shared helpers of the GenoM3 command-line tests: the fixture and stub
//! folders, the `genom-check` command, a run with `--format json`, the codes
//! of a report, writing a file, and the demo component with its WCET file.

use std::path::{Path, PathBuf};

use assert_cmd::Command;
use serde_json::Value;

pub(crate) const FIXTURES: &str = "genom3-frontend/tests/fixtures";
pub(crate) const STUBS: &str = "tests/fixtures/genom3/include";

pub(crate) fn genom_check() -> Command {
    let mut cmd = Command::cargo_bin("genom-check").expect("binary is built");
    cmd.env_remove("NO_COLOR")
        .env_remove("GENOM_INCLUDE_PATH")
        .env("TERM", "xterm");
    cmd
}

/// Runs with `--format json`; returns the exit status and the one file's
/// entry.
pub(crate) fn json(args: &[&str]) -> (i32, Value) {
    let out = genom_check()
        .args(["--format", "json"])
        .args(args)
        .output()
        .unwrap();
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "{e}: {}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        )
    });
    (out.status.code().unwrap(), doc["files"][0].clone())
}

/// The codes of a JSON file entry's diagnostics with `severity`.
pub(crate) fn codes(file: &Value, severity: &str) -> Vec<String> {
    file["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|d| d["severity"] == severity)
        .map(|d| d["code"].as_str().unwrap().to_owned())
        .collect()
}

pub(crate) fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(&path, text).unwrap();
    path
}

pub(crate) const DEMO: &str = "genom3-frontend/tests/fixtures/valid/demo.gen";
pub(crate) const DEMO_WCET: &str = "genom3-frontend/tests/fixtures/valid/demo.wcet";
