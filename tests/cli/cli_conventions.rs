//! Command-line conventions users expect from rustc, cargo and ruff: `-`
//! reads standard input, global options before the subcommand, `explain`
//! suggesting the closest code and listing the codes one a line, shell
//! completions and a manual page generated from the options, `export`
//! saying what it wrote and the verdict it rests on.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

use assert_cmd::Command;

fn genom_check() -> Command {
    let mut cmd = Command::cargo_bin("genom-check").expect("binary is built");
    cmd.env("NO_COLOR", "1").env_remove("GENOM_INCLUDE_PATH");
    cmd
}

const SELF_CONTAINED: &str = "tests/fixtures/valid/looping-watchdog-fires-early.gen";
const INVALID: &str = "tests/fixtures/invalid/syntax.several-errors.gen";

fn run(cmd: &mut Command) -> (i32, String, String) {
    let out = cmd.output().expect("runs");
    (
        out.status.code().expect("exited"),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn a_dash_reads_standard_input_checked_as_stdin() {
    let text = std::fs::read_to_string(SELF_CONTAINED).expect("fixture");
    let (status, stdout, _) = run(genom_check().arg("-").write_stdin(text));
    assert_eq!(status, 0, "{stdout}");
    assert!(stdout.contains("<stdin>: 0 errors"), "{stdout}");
    // Diagnostics point into `<stdin>`.
    let bad = std::fs::read_to_string(INVALID).expect("fixture");
    let (status, stdout, _) = run(genom_check()
        .args(["--format", "json", "-"])
        .write_stdin(bad));
    assert_eq!(status, 1);
    let doc: serde_json::Value = serde_json::from_str(&stdout).expect("JSON");
    assert_eq!(doc["files"][0]["path"], "<stdin>");
    assert_eq!(doc["files"][0]["diagnostics"][0]["file"], "<stdin>");
}

#[test]
fn global_options_go_before_or_after_the_subcommand() {
    let before = run(genom_check().args(["--format", "json", "check", INVALID]));
    let after = run(genom_check().args(["check", INVALID, "--format", "json"]));
    assert_eq!((before.0, after.0), (1, 1));
    let diagnostics = |stdout: &str| {
        let doc: serde_json::Value = serde_json::from_str(stdout).expect("JSON");
        doc["files"][0]["diagnostics"].clone()
    };
    assert_eq!(diagnostics(&before.1), diagnostics(&after.1));
    assert!(
        diagnostics(&before.1)
            .as_array()
            .is_some_and(|d| !d.is_empty())
    );
}

#[test]
fn explain_suggests_the_closest_code_and_lists_them_one_a_line() {
    let (status, _, stderr) = run(genom_check().args(["explain", "deadlok"]));
    assert_eq!(status, 2);
    assert!(stderr.contains("did you mean `deadlock`?"), "{stderr}");
    let listed: Vec<&str> = stderr.lines().skip(1).map(str::trim).collect();
    assert!(
        listed.contains(&"deadlock") && listed.contains(&"syntax"),
        "{stderr}"
    );
    assert!(
        listed.iter().all(|l| !l.contains(' ') && !l.contains(',')),
        "{stderr}"
    );
}

#[test]
fn completions_and_the_manual_page_come_from_the_options() {
    let (status, script, _) = run(genom_check().args(["completions", "bash"]));
    assert_eq!(status, 0);
    assert!(
        script.contains("genom-check") && script.contains("--max-memory"),
        "{script}"
    );
    let (status, script, _) = run(genom_check().args(["completions", "zsh"]));
    assert_eq!(status, 0);
    assert!(script.starts_with("#compdef genom-check"), "{script}");
    let (status, page, _) = run(genom_check().arg("manpage"));
    assert_eq!(status, 0);
    assert!(page.contains(".TH genom-check 1"), "{page}");
    assert!(page.contains("max\\-memory"), "the options are documented");
    let (status, _, stderr) = run(genom_check().args(["completions", "tcsh"]));
    assert_eq!(status, 2, "{stderr}");
}

#[test]
fn export_says_what_it_wrote_and_the_verdict() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("model.xml");
    let out_arg = out.to_str().expect("UTF-8 path");
    let (status, stdout, stderr) =
        run(genom_check().args(["export", "uppaal", SELF_CONTAINED, "-o", out_arg]));
    assert_eq!(status, 0, "{stderr}");
    assert!(stdout.is_empty(), "{stdout}");
    let companion = dir.path().join("model.q");
    assert!(out.is_file() && companion.is_file());
    assert!(
        stderr.contains(&format!(
            "wrote `{}` and `{}`",
            out.display(),
            companion.display()
        )),
        "{stderr}"
    );
    assert!(
        stderr.contains(&format!("{SELF_CONTAINED}: 0 errors")),
        "{stderr}"
    );
    // To stdout: the export alone on stdout, the verdict on stderr.
    let (status, stdout, stderr) = run(genom_check().args(["export", "config", SELF_CONTAINED]));
    assert_eq!(status, 0);
    assert!(stdout.starts_with('{'), "{stdout}");
    assert!(
        stderr.contains("0 errors") && !stderr.contains("wrote"),
        "{stderr}"
    );
    // `--quiet` says nothing.
    let (_, _, stderr) = run(genom_check().args(["export", "config", "--quiet", SELF_CONTAINED]));
    assert!(stderr.is_empty(), "{stderr}");
}

#[test]
fn human_reports_say_once_how_to_learn_more_about_a_code() {
    let (status, stdout, _) = run(genom_check().args([
        "--static-only",
        INVALID,
        "tests/fixtures/invalid/duplicate-definition.two-services.gen",
    ]));
    assert_eq!(status, 1);
    let hints: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("For more information"))
        .collect();
    assert_eq!(
        hints,
        [
            "For more information about a code, run `genom-check explain CODE`, e.g. `genom-check explain syntax`."
        ],
        "{stdout}"
    );
    // One code only: named; --quiet: none.
    let (_, stdout, _) = run(genom_check().args(["--static-only", INVALID]));
    assert!(
        stdout.contains("For more information about `syntax`, run `genom-check explain syntax`."),
        "{stdout}"
    );
    let (_, stdout, _) = run(genom_check().args(["--quiet", "--static-only", INVALID]));
    assert!(!stdout.contains("For more information"), "{stdout}");
}

#[test]
fn genom3_users_read_explanations_in_genom3_words_first() {
    const LONG: &str = "tests/fixtures/genom3/timing/f11_permanent_long";
    let source = format!("{LONG}.gen");
    let wcet = format!("{LONG}.wcet");
    let (status, stdout, _) = run(genom_check().args(["check", &source, "--wcet", &wcet]));
    assert_eq!(status, 1, "{stdout}");
    assert!(
        stdout.contains(
            "For more information about `codel-overrun`, run `genom-check explain --dialect genom3 codel-overrun`."
        ),
        "{stdout}"
    );
    // The codel-overrun of a GenoM3 task: the period is a label of the
    // report, not an advice of its own.
    assert!(!stdout.contains("Advice"), "{stdout}");
    let (status, text, _) =
        run(genom_check().args(["explain", "--dialect", "genom3", "codel-overrun"]));
    assert_eq!(status, 0);
    let genom3 = text.find("GenoM3 components").expect("a GenoM3 section");
    let dialect = text
        .find("## In the LANGUAGE.md dialect")
        .expect("the LANGUAGE.md section after it");
    assert!(genom3 < dialect, "{text}");
    assert!(text[..dialect].contains("yield pause::"), "{text}");
    assert!(!text[..dialect].contains("max-time"), "{text}");
    // SARIF of a GenoM3 file: the rules' help reads the same way.
    let (_, sarif, _) =
        run(genom_check().args(["check", &source, "--wcet", &wcet, "--format", "sarif"]));
    let doc: serde_json::Value = serde_json::from_str(&sarif).expect("SARIF is JSON");
    let help = doc["runs"][0]["tool"]["driver"]["rules"][0]["help"]["text"]
        .as_str()
        .unwrap_or_default();
    assert!(help.contains("GenoM3 components"), "{help}");
    assert!(
        help.find("GenoM3 components") < help.find("## In the LANGUAGE.md dialect"),
        "{help}"
    );
}

#[test]
fn sizes_and_durations_accept_the_usual_units() {
    for (option, value) in [
        ("--max-memory", "4GB"),
        ("--max-memory", "1.5G"),
        ("--max-memory", "512MiB"),
        ("--timeout", "1h"),
        ("--timeout", "1h 30m"),
    ] {
        let (status, stdout, stderr) =
            run(genom_check().args(["--static-only", option, value, SELF_CONTAINED]));
        assert_eq!(status, 0, "{option} {value}: {stdout}{stderr}");
    }
    let (status, _, stderr) = run(genom_check().args(["--max-memory", "lots", SELF_CONTAINED]));
    assert_eq!(status, 2);
    assert!(stderr.contains("is not a size such as"), "{stderr}");
}
