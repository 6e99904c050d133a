//! `--max-memory` bounds the process's real memory: the binary is spawned
//! on hostile inputs and on a 10 MB component, and its peak resident size
//! (`VmHWM` of `/proc/PID/status`, read while it runs) is checked against
//! the limit, with its exit status and its message. Linux only (`/proc`).
//! A timed exploration is run under `--max-memory 1G`, a symbolic one
//! under `--max-memory 100M` (issue 14). Each
//! child's own peak is read, so the two tests may run at once.

#![cfg(target_os = "linux")]
#![allow(clippy::expect_used, clippy::unwrap_used)] // test support code

use std::fs::File;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::high_water_mark;

use crate::common;

const MIB: u64 = 1 << 20;

/// What one run of the binary did.
struct Run {
    status: i32,
    stdout: String,
    stderr: String,
    /// Peak resident size in bytes, as last seen before the process ended.
    peak: u64,
    took: Duration,
}

/// Runs the binary with `args`, watching its peak resident size.
fn run(dir: &Path, args: &[&str]) -> Run {
    let (out, err) = (dir.join("stdout"), dir.join("stderr"));
    let started = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_genom-check"))
        .args(args)
        .env("NO_COLOR", "1")
        .env_remove("GENOM_INCLUDE_PATH")
        .stdout(Stdio::from(File::create(&out).unwrap()))
        .stderr(Stdio::from(File::create(&err).unwrap()))
        .spawn()
        .unwrap();
    let mut peak = 0;
    let status = loop {
        if let Some(hwm) = high_water_mark(child.id()) {
            peak = peak.max(hwm);
        }
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        std::thread::sleep(Duration::from_millis(2));
    };
    Run {
        status: status.code().expect("exited, not killed"),
        stdout: std::fs::read_to_string(out).unwrap(),
        stderr: std::fs::read_to_string(err).unwrap(),
        peak,
        took: started.elapsed(),
    }
}

/// Writes the 10 MB component (1000 services of 100 codels, dense
/// rules, timed) into `dir`.
fn huge_component(dir: &Path) -> String {
    let path = dir.join("big.gen");
    let args = "generate --seed 1 --services 1000 --codels 100 --threads 100 --density 5 \
                --timed --autos 10 --init --loops 1 --self-stops 1";
    let out = Command::new(env!("CARGO_BIN_EXE_genom-check"))
        .args(args.split_whitespace())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert!(out.stdout.len() > 5_000_000, "{} bytes", out.stdout.len());
    std::fs::write(&path, &out.stdout).unwrap();
    path.to_string_lossy().into_owned()
}

/// Runs the binary with `args` and checks its exit `status`, that `needle`
/// is in its stdout or stderr, and that its peak resident size stayed
/// within `limit_mib`.
fn expect(dir: &Path, args: &[&str], status: i32, needle: &str, limit_mib: u64) {
    let what = args.join(" ");
    let r = run(dir, args);
    assert_eq!(r.status, status, "{what}: {}{}", r.stdout, r.stderr);
    assert!(
        r.stdout.contains(needle) || r.stderr.contains(needle),
        "{what}: `{needle}` not in\n{}{}",
        r.stdout,
        r.stderr
    );
    assert!(
        r.peak > 0 && r.peak <= limit_mib * MIB,
        "{what}: peak resident size {} MiB, limit {limit_mib} MiB",
        r.peak / MIB
    );
    // A generous bound: the limits stop every phase well before this.
    assert!(r.took < Duration::from_secs(300), "{what}: {:?}", r.took);
}

#[test]
fn the_process_stays_within_max_memory_on_hostile_and_huge_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    fn with_limits(file: &str) -> Vec<&str> {
        vec!["--timeout", "2s", "--max-memory", "200M", file]
    }

    // A device: refused at once.
    expect(d, &with_limits("/dev/zero"), 2, "not a regular file", 200);

    // A FIFO: refused at once, never opened for reading (that would block).
    let fifo = d.join("f.gen");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if made.is_ok_and(|s| s.success()) {
        let args = with_limits(fifo.to_str().unwrap());
        expect(d, &args, 2, "not a regular file", 200);
    }

    // The 10 MB component: time and memory stop it, with `incomplete`.
    let big = huge_component(d);
    expect(d, &with_limits(&big), 1, "verification is incomplete", 200);

    // Without a time limit, the memory limit alone stops it, by name.
    let args = ["--max-memory", "100M", big.as_str()];
    expect(
        d,
        &args,
        1,
        "the memory limit (--max-memory) was reached",
        100,
    );

    // One step larger than the whole limit (reading a 120 MB file under
    // 100M): no phase can stop cleanly, the process ends at once.
    let wide = d.join("wide.gen");
    std::fs::write(&wide, vec![b' '; 120 << 20]).unwrap();
    let args = ["--max-memory", "100M", wide.to_str().unwrap()];
    expect(d, &args, 1, "memory limit (--max-memory)", 100);
}

/// Writes the component `genom-check generate ARGS` prints into `dir`.
fn generated(dir: &Path, name: &str, args: &str) -> String {
    let path = dir.join(name);
    let out = Command::new(env!("CARGO_BIN_EXE_genom-check"))
        .args(args.split_whitespace())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    std::fs::write(&path, &out.stdout).unwrap();
    path.to_string_lossy().into_owned()
}

/// Issue 14: a timed exploration that outgrows `--max-memory 1G` (30
/// services, timed; about 2 GB without a limit) stops with `incomplete`,
/// naming the memory limit, at about 1.1 GB resident at most.
#[test]
fn a_timed_exploration_stops_within_one_gigabyte() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = "generate --seed 1 --services 30 --codels 5 --threads 4 --init --autos 1 --timed";
    let path = generated(d, "t30.gen", args);
    let args = ["--max-memory", "1G", path.as_str()];
    expect(
        d,
        &args,
        1,
        "the memory limit (--max-memory) was reached",
        1126,
    );
}

/// Issue 14: the symbolic engine's BDDs count against `--max-memory` too
/// (20 services at density 1: about 260 MB after 30 s without a limit).
#[test]
fn a_symbolic_exploration_stops_within_its_limit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args =
        "generate --seed 1 --services 20 --codels 5 --threads 3 --density 1 --init --autos 1";
    let path = generated(d, "d1.gen", args);
    let args = [
        "--engine",
        "symbolic",
        "--max-memory",
        "100M",
        path.as_str(),
    ];
    expect(
        d,
        &args,
        1,
        "the memory limit (--max-memory) was reached",
        110,
    );
}

/// Issue 28, items 16 and 18: nesting is bounded before any recursive step
/// sees it (1024 levels in GenoM3, 64 in the dialect), so 10 000 nested
/// modules or structs (1.4 GB and 4 s before) and 300 000 nested
/// parentheses (155 MB of stack under `--max-memory 100M` before) are a
/// `syntax` error within the limit; 1 000 levels are still read.
#[test]
fn deep_nesting_is_an_error_within_the_memory_limit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let levels = |open: &str, inner: &str, close: &str, n: usize| {
        format!("{}{inner}{}", open.repeat(n), close.repeat(n))
    };
    let modules = |n| {
        let body = (0..n)
            .map(|i| format!("module m{i} {{\n"))
            .collect::<String>();
        format!(
            "#pragma once\n{body}const long k = 1;\n{}component c {{}};\n",
            "};\n".repeat(n)
        )
    };
    let structs = format!(
        "#pragma once\nstruct s {{\n{}long x;\n{}}};\ncomponent c {{}};\n",
        "struct s {\n".repeat(9_999),
        "} f;\n".repeat(9_999)
    );
    let parens = format!(
        "#pragma once\ncomponent c {{ const long k = {}; }};\n",
        levels("(", "1", ")", 300_000)
    );
    let dialect = format!(
        "component c {{ category: default; lang: C; }}\nconst long k = {};\n",
        levels("(", "1", ")", 300_000)
    );
    let cases = [
        ("modules.gen", modules(10_000), "1024"),
        ("structs.gen", structs, "1024"),
        ("parens.gen", parens, "1024"),
        ("dialect.gen", dialect, "64"),
    ];
    for (name, text, limit) in cases {
        let path = d.join(name);
        std::fs::write(&path, text).unwrap();
        let args = [
            "--max-memory",
            "100M",
            "--timeout",
            "60s",
            path.to_str().unwrap(),
        ];
        let needle = format!("nesting deeper than {limit} levels");
        expect(d, &args, 1, &needle, 100);
    }
    // Deep but within the bound: read and checked, within the limit.
    let path = d.join("deep.gen");
    std::fs::write(&path, modules(1_000)).unwrap();
    let args = ["--max-memory", "100M", path.to_str().unwrap()];
    expect(d, &args, 0, "0 errors", 100);
}
