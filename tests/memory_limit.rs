//! `--max-memory` bounds the process's real memory: the binary is spawned
//! on hostile inputs and on a 10 MB component, and its peak resident size
//! (`VmHWM` of `/proc/PID/status`, read while it runs) is checked against
//! the limit, with its exit status and its message. Linux only (`/proc`).
//! One test per file, run one after the other: the children do not overlap.

#![cfg(target_os = "linux")]
#![allow(clippy::expect_used, clippy::unwrap_used)] // test support code

use std::fs::File;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

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

/// `VmHWM` (peak resident size) of process `pid`, in bytes.
fn high_water_mark(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
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

fn assert_within(run: &Run, limit_mib: u64, what: &str) {
    assert!(
        run.peak > 0 && run.peak <= limit_mib * MIB,
        "{what}: peak resident size {} MiB, limit {limit_mib} MiB",
        run.peak / MIB
    );
    // A generous bound: the limits stop every phase well before this.
    assert!(
        run.took < Duration::from_secs(300),
        "{what}: {:?}",
        run.took
    );
}

#[test]
fn the_process_stays_within_max_memory_on_hostile_and_huge_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let limits = ["--timeout", "2s", "--max-memory", "200M"];

    // A device: refused at once.
    let zero = run(dir.path(), &[&limits[..], &["/dev/zero"]].concat());
    assert_eq!(zero.status, 2, "{}", zero.stderr);
    assert!(
        zero.stderr.contains("not a regular file"),
        "{}",
        zero.stderr
    );
    assert_within(&zero, 200, "/dev/zero");

    // A FIFO: refused at once, never opened for reading (that would block).
    let fifo = dir.path().join("f.gen");
    if Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success())
    {
        let r = run(
            dir.path(),
            &[&limits[..], &[fifo.to_str().unwrap()]].concat(),
        );
        assert_eq!(r.status, 2, "{}", r.stderr);
        assert_within(&r, 200, "a FIFO");
    }

    // The 10 MB component: time and memory stop it, with `incomplete`.
    let big = huge_component(dir.path());
    let r = run(dir.path(), &[&limits[..], &[big.as_str()]].concat());
    assert_eq!(r.status, 1, "{}", r.stderr);
    assert!(
        r.stdout.contains("verification is incomplete"),
        "{}",
        r.stdout
    );
    assert_within(&r, 200, "the 10 MB component, --timeout 2s");

    // Without a time limit, the memory limit alone stops it, by name.
    let r = run(dir.path(), &["--max-memory", "100M", big.as_str()]);
    assert_eq!(r.status, 1, "{}", r.stderr);
    assert!(
        r.stdout
            .contains("the memory limit (--max-memory) was reached"),
        "{}",
        r.stdout
    );
    assert_within(&r, 100, "the 10 MB component, --max-memory 100M");

    // One step larger than the whole limit (reading a 120 MB file under
    // 100M): no phase can stop cleanly, the process ends at once.
    let wide = dir.path().join("wide.gen");
    std::fs::write(&wide, vec![b' '; 120 << 20]).unwrap();
    let r = run(
        dir.path(),
        &["--max-memory", "100M", wide.to_str().unwrap()],
    );
    assert_eq!(r.status, 1, "{}", r.stderr);
    assert!(
        r.stderr.contains("memory limit (--max-memory)"),
        "{}",
        r.stderr
    );
    assert_within(&r, 100, "a 120 MB file under --max-memory 100M");
}
