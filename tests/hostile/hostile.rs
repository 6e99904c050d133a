//! Hostile input: paths that are not regular files (devices, FIFOs) given
//! on the command line or included, in both dialects. Each must end at
//! once with a clear message and exit 2 (the file itself) or 1 (an include),
//! never block or grow without bound. A standard output that cannot be
//! written is exit 2 (a closed pipe ends quietly), and no file name forges
//! a CI annotation or writes escape sequences to the terminal.

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
    assert!(
        stderr.contains(&format!("cannot read `/dev/zero`: {NOT_REGULAR}")),
        "{stderr}"
    );
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
        assert!(
            d["message"].as_str().unwrap().ends_with(NOT_REGULAR),
            "{stdout}"
        );
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

#[test]
fn json_reports_carry_the_files_that_could_not_be_read() {
    let (status, stdout, stderr) = run(&[
        "--format",
        "json",
        "--static-only",
        "no/such.gen",
        "specs/pilot.gen",
        "/dev/null",
    ]);
    assert_eq!(status, 2, "{stderr}");
    let doc: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(doc["files"][0]["path"], "specs/pilot.gen");
    assert_eq!(doc["files"].as_array().unwrap().len(), 1);
    let unread: Vec<(&str, &str)> = doc["unread"]
        .as_array()
        .unwrap()
        .iter()
        .map(|u| (u["path"].as_str().unwrap(), u["error"].as_str().unwrap()))
        .collect();
    assert_eq!(
        unread,
        [
            ("no/such.gen", "cannot read `no/such.gen`: no such file"),
            (
                "/dev/null",
                "cannot read `/dev/null`: it is not a regular file (a device, FIFO or socket)"
            ),
        ]
    );
    assert_eq!(doc["summary"]["unread"], 2);
}

/// Writes `text` to `name` in a fresh folder; returns the folder (kept
/// alive by the caller) and the path.
fn file(name: &str, text: &[u8]) -> (tempfile::TempDir, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    let shown = path.to_string_lossy().into_owned();
    (dir, shown)
}

/// `field` of every diagnostic of the first file of a JSON report.
fn diagnostic_fields(stdout: &str, field: &str) -> Vec<String> {
    let doc: serde_json::Value = serde_json::from_str(stdout).unwrap();
    doc["files"][0]["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| d[field].as_str().unwrap().to_owned())
        .collect()
}

#[test]
fn a_nul_byte_is_escaped_in_messages_and_snippets() {
    let (_dir, path) = file("nul.gen", b"component c { lang: C; }\0\n");
    let out = genom_check()
        .args(["--color", "never", &path])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(!out.stdout.contains(&0), "a raw NUL reached the terminal");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("found `\\0`"), "{stdout}");
}

#[test]
fn a_duration_written_with_a_space_gets_a_hint() {
    let text = b"component c { lang: C; }\nthread t { period: 10 ms; }\n";
    let (_dir, path) = file("d.gen", text);
    let (status, stdout, _) = run(&["--color", "never", &path]);
    assert_eq!(status, 1);
    assert!(
        stdout.contains("write the number and its unit together: `10ms`"),
        "{stdout}"
    );
}

#[test]
fn an_idl_file_given_alone_is_checked_as_idl() {
    let (status, stdout, _) = run(&["--color", "never", "specs/geometry.idl"]);
    assert_eq!(status, 0, "{stdout}");
    assert!(!stdout.contains("missing-component"), "{stdout}");
    let (_dir, path) = file("bad.idl", b"struct p { unknown_t x; };\n");
    let (status, stdout, _) = run(&["--color", "never", &path]);
    assert_eq!(status, 1, "{stdout}");
    assert!(stdout.contains("unknown-type"), "{stdout}");
    // A `.gen` file without component still misses it.
    let (_dir, path) = file("empty.gen", b"struct p { long x; };\n");
    let (status, stdout, _) = run(&["--color", "never", &path]);
    assert_eq!(status, 1);
    assert!(stdout.contains("missing-component"), "{stdout}");
}

#[test]
fn recursive_types_are_errors_and_block_the_export() {
    let text = b"component c { lang: C; }\ntypedef T T;\ntypedef struct X { X x; } X;\nids d { X a; T b; }\n";
    let (_dir, path) = file("r.gen", text);
    let (status, stdout, _) = run(&["--format", "json", &path]);
    assert_eq!(status, 1);
    let codes = diagnostic_fields(&stdout, "code");
    assert_eq!(codes, ["recursive-type", "recursive-type"]);
    let (status, stdout, _) = run(&["export", "config", &path]);
    assert_eq!(status, 1);
    assert!(!stdout.contains("\"verified\": true"), "{stdout}");
}

#[test]
fn floating_point_values_out_of_range_are_errors() {
    let text = b"component c { lang: C; }\nids d { double y := 1e999; float f := 1e300; }\n";
    let (_dir, path) = file("f.gen", text);
    let (status, stdout, _) = run(&["--format", "json", &path]);
    assert_eq!(status, 1, "{stdout}");
    let messages = diagnostic_fields(&stdout, "message");
    assert_eq!(
        messages,
        [
            "`1e999` is out of range for `double`",
            "`1e300` is out of range for `float`"
        ]
    );
}

/// The 10 MB component of the issue (1000 services of 100 codels, dense
/// rules, timed): `--timeout` bounds every phase, parsing included.
#[test]
fn the_time_limit_bounds_every_phase_of_a_huge_component() {
    let out = genom_check()
        .args([
            "generate",
            "--seed",
            "1",
            "--services",
            "1000",
            "--codels",
            "100",
            "--threads",
            "100",
            "--density",
            "5",
            "--timed",
            "--autos",
            "10",
            "--init",
            "--loops",
            "1",
            "--self-stops",
            "1",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert!(out.stdout.len() > 5_000_000, "{} bytes", out.stdout.len());
    let (_dir, path) = file("big.gen", &out.stdout);
    // The static checks alone take about 1.8 s on this file (release, a
    // loaded machine): their limit is well below that, so that a fast
    // machine still reaches it.
    for (extra, limit) in [(&[][..], "2s"), (&["--static-only"][..], "300ms")] {
        let started = std::time::Instant::now();
        let mut args = vec!["--format", "json", "--timeout", limit];
        args.extend(extra);
        args.push(&path);
        let (status, stdout, _) = run(&args);
        let took = started.elapsed();
        assert_eq!(status, 1);
        let codes = diagnostic_fields(&stdout, "code");
        assert!(codes.contains(&"incomplete".to_owned()), "{codes:?}");
        // A generous bound: the limit is 2 s, one item or transition more
        // may run after it.
        assert!(
            took.as_secs() < 120,
            "{took:?} for --timeout {limit} {extra:?}"
        );
    }
}

/// The GenoM3 front-end looks at the clock every 64 KiB too: a file of
/// 200 KB of statements under `--timeout 1us` stops while parsing, with
/// `incomplete` pointing into the file, and nothing is checked.
#[test]
fn the_time_limit_stops_a_genom3_file_while_parsing() {
    let mut text = String::from("component c { lang \"c\"; };\n");
    for i in 0..8000 {
        text.push_str(&format!("const long c_{i} = {i};\n"));
    }
    assert!(text.len() > 150_000);
    let (_dir, path) = file("big3.gen", text.as_bytes());
    let (status, stdout, _) = run(&["--dialect", "genom3", "--timeout", "1us", &path]);
    assert_eq!(status, 1, "{stdout}");
    assert!(
        stdout.contains("the time limit (--timeout) was reached while parsing"),
        "{stdout}"
    );
    assert!(stdout.contains("parsing stopped here"), "{stdout}");
    // Without the limit the same file is clean: the stop came from it.
    let (status, stdout, _) = run(&["--dialect", "genom3", "--static-only", &path]);
    assert_eq!(status, 0, "{stdout}");
}

// ---- Standard output that cannot be written (issue 28, item 8).

/// A clean component and a folder holding it.
fn clean_component() -> (tempfile::TempDir, String) {
    file("c.gen", b"component c { category: default; lang: C; }\n")
}

/// Runs `genom-check ARGS` with stdout into `stdout`; returns exit status
/// and stderr.
fn run_into(stdout: std::fs::File, args: &[&str]) -> (i32, String) {
    let out = std::process::Command::new(assert_cmd::cargo::cargo_bin("genom-check"))
        .args(args)
        .env("NO_COLOR", "1")
        .stdout(stdout)
        .output()
        .unwrap();
    (
        out.status.code().unwrap(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn a_full_standard_output_is_an_error_with_exit_2() {
    if !Path::new("/dev/full").exists() {
        return;
    }
    let (_dir, c) = clean_component();
    let runs: [&[&str]; 6] = [
        &["check", &c],
        &["check", "--format", "json", &c],
        &["check", "--format", "sarif", &c],
        &["export", "config", &c],
        &["explain", "syntax"],
        &["generate"],
    ];
    for args in runs {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let (status, stderr) = run_into(full, args);
        assert_eq!(status, 2, "{args:?}: {stderr}");
        assert!(
            stderr.ends_with(
                "error: cannot write to standard output: No space left on device (os error 28)\n"
            ),
            "{args:?}: {stderr}"
        );
        // Said once, and nothing claims the export was written.
        assert_eq!(stderr.matches("error:").count(), 1, "{args:?}: {stderr}");
    }
}

#[test]
fn standard_output_past_the_file_size_limit_is_an_error_not_a_signal() {
    let dir = tempfile::tempdir().unwrap();
    let out = std::process::Command::new("sh")
        .current_dir(dir.path())
        .arg("-c")
        .arg("ulimit -f 4 && exec \"$0\" generate --services 300 > out.gen")
        .arg(assert_cmd::cargo::cargo_bin("genom-check"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("error: cannot write to standard output: File too large"),
        "{stderr}"
    );
}

#[test]
fn a_closed_pipe_ends_the_output_quietly() {
    // Far more than a pipe holds, read by nobody.
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("genom-check"))
        .args(["generate", "--services", "1000"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(String::from_utf8_lossy(&out.stderr), "");
}

// ---- Names that would forge output (issue 28, item 20).

/// A file name that holds a GitHub workflow command on a line of its own.
const FORGED: &str = "a\n::error file=evil.gen,line=1::x\n.gen";

/// A component with one syntax error (an annotation) under `name`.
fn broken_under(name: &str) -> (tempfile::TempDir, String) {
    file(name, b"component c { lang: C; }\nids { x }\n")
}

/// Runs `genom-check ARGS` in `dir`; returns exit status and stdout.
fn run_in(dir: &Path, args: &[&str]) -> (i32, String) {
    let out = genom_check().current_dir(dir).args(args).output().unwrap();
    (
        out.status.code().unwrap(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
    )
}

#[test]
fn a_file_name_cannot_forge_a_github_annotation() {
    let (dir, _) = broken_under(FORGED);
    let (status, stdout) = run_in(dir.path(), &["--format", "github", FORGED]);
    assert_eq!(status, 1, "{stdout}");
    let lines: Vec<&str> = stdout.lines().collect();
    // The real annotation, the file's summary, the total: nothing more.
    assert_eq!(lines.len(), 3, "{stdout}");
    let commands: Vec<&&str> = lines
        .iter()
        .filter(|l| l.trim_start().starts_with("::") || l.contains("##["))
        .collect();
    assert_eq!(commands.len(), 1, "{stdout}");
    assert!(
        commands[0].starts_with(
            "::error file=a%0A%3A%3Aerror file=evil.gen%2Cline=1%3A%3Ax%0A.gen,line=2,"
        ),
        "{stdout}"
    );
    assert_eq!(
        lines[1],
        "a\\n::error file=evil.gen,line=1::x\\n.gen: 1 error, 0 warnings, 0 advice"
    );
    // A name that starts a line with `::` or holds the older `##[` syntax.
    for name in ["::warning file=w.gen::x.gen", "w##[error]x.gen"] {
        let (dir, _) = broken_under(name);
        let (_, stdout) = run_in(dir.path(), &["--format", "github", name]);
        assert_eq!(stdout.lines().count(), 3, "{stdout}");
        let forged = stdout
            .lines()
            .skip(1)
            .filter(|l| l.trim_start().starts_with("::") || l.contains("##["))
            .count();
        assert_eq!(forged, 0, "{stdout}");
    }
}

#[test]
fn escape_sequences_in_names_never_reach_the_terminal() {
    let name = "b\u{1b}[31mred\u{1b}]0;title\u{7}.gen";
    let (_dir, path) = broken_under(name);
    let shown = "b\\u{1b}[31mred\\u{1b}]0;title\\u{7}.gen";
    let (status, stdout, stderr) = run(&[&path]);
    assert_eq!(status, 1, "{stderr}");
    assert!(
        !stdout.contains('\u{1b}') && !stdout.contains('\u{7}'),
        "{stdout:?}"
    );
    assert!(stdout.contains(&format!("{shown}:2:")), "{stdout}");
    assert!(stdout.contains(&format!("{shown}: 1 error")), "{stdout}");
    // A file that cannot be read is named on stderr, escaped too.
    let missing = format!("{path}.missing");
    let (status, _, stderr) = run(&[&missing]);
    assert_eq!(status, 2);
    assert!(!stderr.contains('\u{1b}'), "{stderr:?}");
    assert!(stderr.contains(&format!("{shown}.missing")), "{stderr}");
    // JSON keeps the name (escaped by JSON itself), SARIF a URI.
    let (_, stdout, _) = run(&["--format", "json", &path]);
    assert!(!stdout.contains('\u{1b}'), "{stdout:?}");
    let doc: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(doc["files"][0]["path"], path.as_str());
    let (_, stdout, _) = run(&["--format", "sarif", &path]);
    let doc: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let uri = doc["runs"][0]["results"][0]["locations"][0]["physicalLocation"]["artifactLocation"]
        ["uri"]
        .as_str()
        .unwrap()
        .to_owned();
    assert!(uri.ends_with("/b%1B%5B31mred%1B%5D0;title%07.gen"), "{uri}");
}
