//! Hostile input: paths that are not regular files (devices, FIFOs) given
//! on the command line or included, in both dialects. Each must end at
//! once with a clear message and exit 2 (the file itself) or 1 (an include),
//! never block or grow without bound.

#![allow(clippy::expect_used, clippy::unwrap_used)] // test support code

use std::path::Path;

use assert_cmd::Command;

fn genom_check() -> Command {
    let mut cmd = Command::cargo_bin("genom-check").expect("binary is built");
    cmd.env_remove("GENOM_INCLUDE_PATH").env("NO_COLOR", "1");
    cmd
}

/// Runs `args`; returns exit status, stdout and stderr.
fn run(args: &[&str]) -> (i32, String, String) {
    let out = genom_check().args(args).output().unwrap();
    (
        out.status.code().unwrap(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A FIFO in `dir` (created with `mkfifo`), or `None` where there is none.
fn fifo(dir: &Path, name: &str) -> Option<String> {
    let path = dir.join(name);
    let made = std::process::Command::new("mkfifo")
        .arg(&path)
        .status()
        .is_ok_and(|s| s.success());
    made.then(|| path.to_string_lossy().into_owned())
}

const NOT_REGULAR: &str = "it is not a regular file (a device, FIFO or socket)";

#[test]
fn a_device_given_as_the_file_is_refused_with_exit_2() {
    if !Path::new("/dev/zero").exists() {
        return;
    }
    let (status, stdout, stderr) = run(&["/dev/zero"]);
    assert_eq!(status, 2);
    assert!(stdout.is_empty());
    assert!(stderr.contains(&format!("cannot read `/dev/zero`: {NOT_REGULAR}")), "{stderr}");
    let (status, _, stderr) = run(&["export", "config", "/dev/urandom"]);
    assert_eq!(status, 2, "{stderr}");
}

#[test]
fn a_fifo_given_as_the_file_is_refused_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let Some(path) = fifo(dir.path(), "f.gen") else {
        return;
    };
    let (status, _, stderr) = run(&[&path]);
    assert_eq!(status, 2);
    assert!(stderr.contains(NOT_REGULAR), "{stderr}");
}

#[test]
fn including_a_device_or_a_fifo_is_an_include_error() {
    let dir = tempfile::tempdir().unwrap();
    let Some(pipe) = fifo(dir.path(), "types.idl") else {
        return;
    };
    for target in ["/dev/zero", pipe.as_str()] {
        let main = dir.path().join("c.gen");
        let text = format!("include \"{target}\";\ncomponent c {{ lang: C; }}\n");
        std::fs::write(&main, text).unwrap();
        let args = ["--static-only", "--format", "json", main.to_str().unwrap()];
        let (status, stdout, _) = run(&args);
        assert_eq!(status, 1, "{stdout}");
        let doc: serde_json::Value = serde_json::from_str(&stdout).unwrap();
        let d = &doc["files"][0]["diagnostics"][0];
        assert_eq!(d["code"], "include-not-found", "{stdout}");
        assert!(d["message"].as_str().unwrap().ends_with(NOT_REGULAR), "{stdout}");
    }
    // GenoM3: such a path is not a file to include; the search goes on and
    // ends with `include-not-found`.
    let main = dir.path().join("g.gen");
    let text = "#include \"types.idl\"\ncomponent g {\n  version \"1\";\n};\n";
    std::fs::write(&main, text).unwrap();
    let (status, stdout, _) = run(&["--static-only", main.to_str().unwrap()]);
    assert_eq!(status, 1, "{stdout}");
    assert!(stdout.contains("include-not-found"), "{stdout}");
}
