//! What a result says besides its verdicts (issue 32): an unfinished
//! exploration's `incomplete` names what it decided and what it spent, and
//! a timed LANGUAGE.md result states what it rests on in every format.

use std::path::Path;

use assert_cmd::Command;
use genom_check::CheckOptions;
use genom_checker::Engine;
use genom_model::Code;
use serde_json::Value;

use crate::common;

/// Two services on two threads that share nothing: two clusters, explored
/// one after the other (timed: they share no lock either); `Small`'s is
/// tiny, `Large`'s loops.
const TWO_CLUSTERS: &str = r#"component two { category: default; lang: C; }
ids d { double a; }
ids e { double b; }
thread small { priority: 10; PERIOD }
thread large { priority: 20; PERIOD }
service Small {
  thread: small;
  start codel { exec: f0(d.a); MAX next: end; }
}
service Large {
  thread: large;
  report: FAIL;
  start codel { exec: f1(e.b); MAX next: e1, e2; }
  exec codel e1 { exec: f2(e.b); MAX next: e2, e3, end; }
  exec codel e2 { exec: f3(e.b); MAX next: e1, e3, FAIL; }
  exec codel e3 { exec: f4(e.b); MAX next: e1, end; }
}
"#;

/// The `incomplete` help of `text` checked by the explicit engine with at
/// most `states` states.
fn incomplete_help(text: &str, states: usize) -> String {
    let result = genom_check::check_source(
        Path::new("two.gen"),
        text.to_owned(),
        &genom_model::loader::MemoryLoader::default(),
        &CheckOptions::new()
            .max_states(states)
            .engine(Engine::Explicit),
    );
    let helps: Vec<String> = result
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::Incomplete)
        .filter_map(|d| d.help.clone())
        .collect();
    assert_eq!(helps.len(), 1, "{:#?}", result.diagnostics);
    helps.into_iter().next().unwrap_or_default()
}

#[test]
fn an_unfinished_exploration_says_which_clusters_it_decided_and_what_it_spent() {
    let untimed = TWO_CLUSTERS.replace("PERIOD ", "").replace("MAX ", "");
    let help = incomplete_help(&untimed, 8);
    assert!(
        help.contains("codel reachability for service `Large`; raise the limit"),
        "{help}"
    );
    assert!(
        help.contains(". Proven: the verdicts of service `Small` (explored to the end)"),
        "{help}"
    );
    assert!(!help.contains("thread"), "untimed: no timing named: {help}");
    let spent = help.split(". Stopped after ").nth(1).unwrap_or_default();
    assert!(
        spent.contains(" states in ") && spent.ends_with(" s"),
        "{help}"
    );

    // With durations, the threads are named too: `small`'s timing is
    // decided, `large`'s is not.
    let timed = TWO_CLUSTERS
        .replace("PERIOD ", "period: 10ms; ")
        .replace("MAX ", "max-time: 1ms; ");
    let help = incomplete_help(&timed, 12);
    assert!(
        help.contains(
            "whether thread `large` can overrun and its services end within their `max-time`"
        ),
        "{help}"
    );
    assert!(
        help.contains("the timing of thread `small` (`thread-overrun`, `max-time`)"),
        "{help}"
    );
}

/// A LANGUAGE.md timed result says what it rests on, in the human summary,
/// JSON and SARIF: the codels' `max-time`s (there is no WCET file, and no
/// instance bound: the language allows one instance per service); an
/// untimed one rests on nothing.
#[test]
fn timed_dialect_verdicts_state_their_assumption_in_every_format() {
    let run = |args: &[&str]| {
        let out = Command::cargo_bin("genom-check")
            .expect("binary")
            .args(["--color", "never"])
            .args(args)
            .output()
            .expect("runs");
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let timed = "specs/battery.gen";
    let human = run(&[timed]);
    let line = human
        .lines()
        .find(|l| l.trim_start().starts_with("assuming "))
        .unwrap_or_else(|| panic!("{human}"));
    assert!(
        line.contains("every codel takes at most its `max-time`"),
        "{line}"
    );
    let doc: Value = serde_json::from_str(&run(&["--format", "json", timed])).expect("JSON");
    let all = doc["files"][0]["assumptions"].as_array().expect("a list");
    assert_eq!(all.len(), 1, "{doc:#}");
    assert_eq!(all[0]["kind"], "wcet");
    assert!(all[0].get("file").is_none(), "{doc:#}");
    let sarif: Value = serde_json::from_str(&run(&["--format", "sarif", timed])).expect("SARIF");
    let notes = &sarif["runs"][0]["invocations"][0]["toolExecutionNotifications"];
    assert_eq!(notes[0]["descriptor"]["id"], "assumption/wcet", "{sarif:#}");
    // Untimed: nothing assumed.
    let untimed = common::valid("minimal.gen");
    let doc: Value = serde_json::from_str(&run(&[
        "--format",
        "json",
        untimed.to_str().expect("UTF-8"),
    ]))
    .expect("JSON");
    assert_eq!(
        doc["files"][0]["assumptions"].as_array().map(Vec::len),
        Some(0),
        "{doc:#}"
    );
}
