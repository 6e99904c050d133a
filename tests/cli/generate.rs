//! The hidden `generate` subcommand: deterministic output, hidden from
//! `--help`, and generated components that check without static problems
//! (exit 1 only for behavioural verdicts, which are printed).

#![allow(clippy::expect_used, clippy::print_stderr)] // test support code

use assert_cmd::Command;
use predicates::prelude::*;
use serde_json::Value;

use crate::common;

fn genom_check() -> Command {
    let mut cmd = Command::cargo_bin("genom-check").expect("binary is built");
    cmd.env("NO_COLOR", "1");
    cmd
}

fn generated(args: &[&str]) -> String {
    let out = genom_check()
        .arg("generate")
        .args(args)
        .output()
        .expect("runs");
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("UTF-8")
}

/// Behavioural and timing verdicts (and `incomplete`, when a limit
/// stops the exploration): the only errors a generated component may get.
const BEHAVIOURAL: [&str; 9] = [
    "deadlock",
    "starvation",
    "dead-service",
    "unbounded-interrupt",
    "codel-overrun",
    "thread-overrun",
    "max-time-infeasible",
    "max-time-exceeded",
    "incomplete",
];

#[test]
fn output_is_deterministic_and_depends_on_the_seed() {
    let args = [
        "--seed",
        "17",
        "--services",
        "8",
        "--codels",
        "4",
        "--threads",
        "2",
        "--init",
        "--autos",
        "1",
    ];
    let a = generated(&args);
    let b = generated(&args);
    assert_eq!(a, b);
    assert!(a.contains("init service"), "{a}");
    assert!(a.contains("auto service"), "{a}");
    let other = generated(&[
        "--seed",
        "18",
        "--services",
        "8",
        "--codels",
        "4",
        "--threads",
        "2",
        "--init",
        "--autos",
        "1",
    ]);
    assert_ne!(a, other);
}

#[test]
fn generate_is_hidden_from_help() {
    genom_check().arg("--help").assert().code(0).stdout(
        predicate::str::contains("explain").and(predicate::str::contains("generate").not()),
    );
}

#[test]
fn bad_generator_arguments_are_usage_errors() {
    genom_check()
        .args(["generate", "--density", "-1"])
        .assert()
        .code(2);
    genom_check()
        .args(["generate", "--services", "0"])
        .assert()
        .code(2);
    genom_check()
        .args(["generate", "--loops", "1.5"])
        .assert()
        .code(2);
}

#[test]
fn generated_components_check_with_behavioural_verdicts_only() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let cases = [
        "--services 5 --codels 3",
        "--services 6 --codels 3 --threads 2 --density 0.5 --init",
        "--services 6 --codels 4 --threads 2 --autos 1 --timed",
        "--services 8 --codels 2 --threads 3 --density 0.3 --init --autos 2 --timed",
        "--services 5 --codels 3 --density 2 --setters 0.3",
        "--services 6 --codels 3 --threads 2 --density 0.3 --self-stops 0.5 --init",
        "--services 10 --codels 5 --threads 2 --density 0.3",
    ];
    for (i, case) in cases.iter().enumerate() {
        for seed in 0..3 {
            let seed = seed.to_string();
            let mut args = vec!["--seed", seed.as_str()];
            args.extend(case.split_whitespace());
            let path = dir.path().join(format!("g{i}-{seed}.gen"));
            std::fs::write(&path, generated(&args)).expect("written");

            // No static error nor warning.
            genom_check()
                .arg("--static-only")
                .args(["--deny", "warnings"])
                .arg(&path)
                .assert()
                .code(0);

            // The whole check: exit 1 only for behavioural verdicts.
            let out = genom_check()
                .args([
                    "--format",
                    "json",
                    "--max-states",
                    "200000",
                    "--timeout",
                    "30s",
                ])
                .arg(&path)
                .output()
                .expect("runs");
            let json: Value = serde_json::from_slice(&out.stdout).expect("one JSON document");
            let file = &json["files"][0];
            let errors = common::error_codes(file);
            let stats = &file["statistics"];
            eprintln!(
                "generate --seed {seed} {}: exit {:?}, errors {errors:?}, {} states",
                case,
                out.status.code(),
                stats["states"]
            );
            assert!(stats.is_object(), "the engine ran: {json}");
            match out.status.code() {
                Some(0) => assert!(errors.is_empty()),
                Some(1) => assert!(
                    !errors.is_empty() && errors.iter().all(|c| BEHAVIOURAL.contains(c)),
                    "non-behavioural error: {errors:?}"
                ),
                other => panic!("exit {other:?}: {}", String::from_utf8_lossy(&out.stderr)),
            }
        }
    }
}

/// `generate --dialect genom3`: deterministic, GenoM3 text, the WCET file
/// written by `--wcet-out`, and a check of the pair that raises only
/// verdicts (dead services, overruns...), never a front-end error.
#[test]
fn genom3_components_and_their_wcet_files() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let wcet = dir.path().join("c.wcet");
    let wcet_arg = wcet.to_str().expect("UTF-8 path");
    let args = [
        "--dialect",
        "genom3",
        "--seed",
        "5",
        "--services",
        "3",
        "--threads",
        "2",
        "--codels",
        "2",
        "--permanent",
        "--timed",
        "--wcet-out",
        wcet_arg,
    ];
    let text = generated(&args);
    assert_eq!(text, generated(&args));
    assert!(
        text.contains("component rnd") && text.contains("  activity a2("),
        "{text}"
    );
    let wcet_text = std::fs::read_to_string(&wcet).expect("the WCET file is written");
    assert!(wcet_text.contains("a0.start "), "{wcet_text}");
    let path = dir.path().join("c.gen");
    std::fs::write(&path, &text).expect("written");
    let out = genom_check()
        .args([
            "--format",
            "json",
            "--max-states",
            "100000",
            "--timeout",
            "20s",
        ])
        .arg("--wcet")
        .arg(&wcet)
        .arg(&path)
        .output()
        .expect("runs");
    let json: Value = serde_json::from_slice(&out.stdout).expect("one JSON document");
    let file = &json["files"][0];
    assert_eq!(file["dialect"], "genom3");
    let errors = common::error_codes(file);
    let genom3_verdicts = ["dead-service", "thread-overrun", "incomplete"];
    assert!(
        errors.iter().all(|c| genom3_verdicts.contains(c)),
        "{errors:?}"
    );
    let codes: Vec<&str> = file["diagnostics"]
        .as_array()
        .expect("diagnostics")
        .iter()
        .filter_map(|d| d["code"].as_str())
        .collect();
    assert!(!codes.contains(&"missing-wcet"), "{codes:?}");
    // Without --dialect, the LANGUAGE.md generator as before.
    assert!(!generated(&["--seed", "5"]).contains("activity"));
}

#[test]
fn dialect_specific_generator_flags_are_usage_errors() {
    for args in [
        &["generate", "--dialect", "genom3", "--init"][..],
        &["generate", "--dialect", "genom3", "--wcet-out", "x.wcet"],
        &["generate", "--permanent"],
        &["generate", "--dialect", "genom3", "--pauses", "2"],
    ] {
        genom_check().args(args).assert().code(2);
    }
}
