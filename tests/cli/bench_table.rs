//! The benchmark table's script (`scripts/bench-table`, docs/performance.md
//! "Side by side"): its `--small --stdout` run must print a table whose
//! genom-check rows carry the states and verdict figures that genom-check's
//! own JSON report gives for the same components, and whose SPIN rows (when
//! `spin` and `gcc` are installed) give the same deadlock, dead-service and
//! unreachable-codel figures as genom-check on the untimed components,
//! which both explore completely.
//!
//! Ignored by default (it runs SPIN, TChecker when `TCK_REACH` is set, and
//! takes a minute or two): `cargo test --release --test cli bench_table:: --
//! --ignored --nocapture`. Needs bash, awk and GNU time (`/usr/bin/time`).

#![allow(clippy::expect_used, clippy::print_stderr)] // test harness

use std::path::Path;
use std::process::Command;

/// One row of the table: component, tool, states, verdict.
struct Row {
    component: String,
    tool: String,
    states: String,
    verdict: String,
}

fn rows(table: &str) -> Vec<Row> {
    table
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| component"))
        .map(|l| {
            let cells: Vec<&str> = l
                .trim()
                .trim_matches('|')
                .split('|')
                .map(str::trim)
                .collect();
            assert_eq!(cells.len(), 6, "a row of six cells: {l}");
            Row {
                component: cells[0].to_owned(),
                tool: cells[1].to_owned(),
                states: cells[2].replace(' ', ""),
                verdict: cells[5].to_owned(),
            }
        })
        .collect()
}

/// genom-check's own report on a generated component: states and the
/// counts of the verdict's first three figures.
fn report(gc: &str, dir: &Path, args: &str, extra: &[&str]) -> (String, String) {
    let gen_out = Command::new(gc)
        .arg("generate")
        .args(args.split_whitespace())
        .output()
        .expect("generate runs");
    let file = dir.join("c.gen");
    std::fs::write(&file, &gen_out.stdout).expect("written");
    let out = Command::new(gc)
        .args(["check", "--format", "json"])
        .args(extra)
        .arg(&file)
        .output()
        .expect("check runs");
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON report");
    let f = &json["files"][0];
    let states = f["statistics"]["states"].as_u64().expect("states");
    let count = |code: &str| {
        f["diagnostics"]
            .as_array()
            .expect("diagnostics")
            .iter()
            .filter(|d| d["code"] == code)
            .count()
    };
    let deadlock = if count("deadlock") > 0 {
        "deadlock"
    } else {
        "no deadlock"
    };
    let verdict = format!(
        "{deadlock}, {} dead, {} unreachable",
        count("dead-service"),
        count("unreachable-codel")
    );
    (states.to_string(), verdict)
}

#[test]
#[ignore = "runs scripts/bench-table --small (SPIN, TChecker when TCK_REACH is set): a minute or two"]
fn the_small_table_reports_what_the_tools_say() {
    let gc = env!("CARGO_BIN_EXE_genom-check");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = Command::new("bash")
        .arg(root.join("scripts/bench-table"))
        .args(["--small", "--stdout"])
        .env("GENOM_CHECK", gc)
        .env("BENCH_TIMEOUT", "60")
        .output()
        .expect("the script runs");
    let table = String::from_utf8_lossy(&out.stdout);
    eprintln!("{table}");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(table.contains("<!-- bench-table:begin") && table.contains("<!-- bench-table:end -->"));
    let rows = rows(&table);
    let temp = tempfile::tempdir().expect("temporary directory");
    // The script's small components (the first argument of each case).
    let cases = [
        (
            "3×2×1 d1",
            "--seed 1 --services 3 --codels 2 --threads 1 --density 1 --init --autos 1",
        ),
        (
            "5×3×1 d1",
            "--seed 1 --services 5 --codels 3 --threads 1 --density 1 --init --autos 1",
        ),
    ];
    for (name, args) in cases {
        for (label, extra) in [
            ("default", &[][..]),
            ("no-reduction", &["--no-reduction"][..]),
        ] {
            let row = rows
                .iter()
                .find(|r| r.component == name && r.tool == format!("genom-check {label}"))
                .unwrap_or_else(|| panic!("no row for {name}, {label}"));
            let (states, verdict) = report(gc, temp.path(), args, extra);
            assert_eq!(row.states, states, "{name} {label}: states");
            assert!(
                row.verdict == verdict || row.verdict.starts_with(&format!("{verdict}; ")),
                "{name} {label}: verdict `{}`, genom-check says `{verdict}`",
                row.verdict
            );
        }
        let spin = rows
            .iter()
            .find(|r| r.component == name && r.tool.starts_with("SPIN"))
            .expect("a SPIN row");
        if spin.states != "notrun" {
            let ours = report(gc, temp.path(), args, &[]).1;
            assert_eq!(spin.verdict, ours, "{name}: SPIN's verdict");
            assert!(
                spin.states.parse::<u64>().is_ok_and(|n| n > 0),
                "{name}: SPIN states"
            );
        }
    }
}
