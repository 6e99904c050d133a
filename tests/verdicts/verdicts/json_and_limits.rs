//! The JSON form of a trace, the `incomplete` verdict when a state limit
//! stops exploration (and complete verdicts without it), and the outcomes
//! that traces name.

use super::support::{claim_of, quoted};
use crate::common;

use assert_cmd::Command;
use gen_frontend::FsLoader;
use genom_check::CheckOptions;
use genom_checker::Engine;
use genom_model::component::Outcome;
use genom_model::{Code, Diagnostic};
use genom_oracles::replay::replay_claim;
use serde_json::Value;
// -------------------------------------------------------------- JSON trace

#[test]
fn the_json_trace_is_a_list_of_step_objects() {
    let out = Command::cargo_bin("genom-check")
        .expect("binary is built")
        .args([
            "--format",
            "json",
            "tests/fixtures/invalid/starvation.behind-endless-loop.gen",
        ])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(1));
    let doc: Value = serde_json::from_slice(&out.stdout).expect("one JSON document");
    let diagnostics = doc["files"][0]["diagnostics"]
        .as_array()
        .expect("diagnostics");
    let d = diagnostics
        .iter()
        .find(|d| d["code"] == "starvation")
        .expect("the starvation verdict");
    assert_eq!(
        d["message"],
        "`Park` can wait forever for `Track`, which may never end"
    );
    assert_eq!(d["line"], 24);
    let trace = d["trace"].as_array().expect("trace is a list");
    assert_eq!(trace.len(), 11);
    let keys = [
        "step",
        "event",
        "time_ns",
        "thread",
        "service",
        "codel",
        "outcome",
        "loop_start",
        "aside",
        "text",
        "location",
    ];
    let mut events = Vec::new();
    for (k, step) in trace.iter().enumerate() {
        let object = step.as_object().expect("each step is an object");
        let mut found: Vec<&str> = object.keys().map(String::as_str).collect();
        found.sort_unstable();
        let mut want = keys.to_vec();
        want.sort_unstable();
        assert_eq!(found, want, "step {k}");
        assert_eq!(step["step"], k + 1);
        assert!(step["time_ns"].is_null(), "untimed trace");
        assert_eq!(step["loop_start"], k == 8, "step {k}");
        assert_eq!(step["aside"], false, "step {k}: no thread set aside");
        assert!(step["text"].as_str().is_some_and(|t| !t.is_empty()));
        let location = &step["location"];
        if location.is_null() {
            assert!(
                matches!(k, 0 | 10),
                "only the start and the violation have no location"
            );
        } else {
            assert!(
                location["file"]
                    .as_str()
                    .is_some_and(|f| f.ends_with("starvation.behind-endless-loop.gen"))
            );
            assert!(location["line"].as_u64().is_some() && location["column"].as_u64().is_some());
            assert!(location["span"]["offset"].as_u64().is_some());
        }
        events.push(step["event"].as_str().expect("event").to_owned());
    }
    assert_eq!(
        events,
        [
            "component-start",
            "request",
            "acknowledge",
            "start",
            "request",
            "acknowledge",
            "codel-start",
            "codel-end",
            "codel-start",
            "codel-end",
            "violation",
        ]
    );
    assert_eq!(trace[1]["thread"], "control");
    assert_eq!(trace[1]["service"], "Track");
    assert!(trace[1]["codel"].is_null());
    assert_eq!(trace[7]["thread"], "servo");
    assert_eq!(trace[7]["codel"], "start");
    assert_eq!(trace[7]["outcome"], "follow");
    assert_eq!(trace[9]["outcome"], "follow");
    assert_eq!(trace[8]["location"]["line"], 21, "`follow` is on line 21");
}

// -------------------------------------------------------------- incomplete

#[test]
fn a_state_limit_gives_incomplete_and_no_negative_claim() {
    for (fixture, services) in [
        (
            "unreachable-codel.inter-only-when-forbidden.gen",
            "`Scan`, `Halt`",
        ),
        ("dead-service.delayed-by-auto.gen", "`Heartbeat`, `Update`"),
    ] {
        let path = common::invalid(fixture);
        let result = genom_check::check_file(
            &common::relative(&path),
            &FsLoader,
            // The explicit engine alone: `auto` would finish symbolically.
            &CheckOptions::new().max_states(3).engine(Engine::Explicit),
        )
        .expect("fixture is readable");
        let report = common::render(&path, &result);
        let incomplete: Vec<&Diagnostic> = result
            .diagnostics
            .iter()
            .filter(|d| d.code == Code::Incomplete)
            .collect();
        assert_eq!(incomplete.len(), 1, "{report}");
        assert_eq!(
            incomplete[0].message,
            "verification is incomplete: the state limit (--max-states) was reached"
        );
        let help = incomplete[0].help.as_deref().unwrap_or_default();
        assert!(
            help.starts_with(&format!(
                "left unproven: deadlock and starvation freedom, unbounded interrupts, dead services and codel reachability for services {services}; raise the limit to finish. "
            )),
            "{report}"
        );
        // What it spent; nothing is proven (one cluster, stopped).
        assert!(help.contains(". Stopped after "), "{report}");
        assert!(help.ends_with(" s"), "{report}");
        assert!(
            !result
                .diagnostics
                .iter()
                .any(|d| matches!(d.code, Code::DeadService | Code::UnreachableCodel)),
            "nothing negative is claimed about what was not explored:\n{report}"
        );
        assert!(result.statistics.as_ref().is_some_and(|s| !s.complete));
        // Whatever was found before the limit comes with a trace that replays.
        for d in result.diagnostics.iter().filter(|d| d.trace.is_some()) {
            let names = quoted(&d.message);
            let trace = d.trace.as_ref().expect("checked");
            replay_claim(common::component(&result), trace, claim_of(d, &names))
                .unwrap_or_else(|e| panic!("{e}"));
        }
    }
}

#[test]
fn without_a_limit_the_same_fixtures_are_complete() {
    for fixture in [
        "unreachable-codel.inter-only-when-forbidden.gen",
        "dead-service.delayed-by-auto.gen",
    ] {
        let result = common::check(&common::invalid(fixture));
        assert!(
            !result
                .diagnostics
                .iter()
                .any(|d| d.code == Code::Incomplete)
        );
        assert!(result.statistics.as_ref().is_some_and(|s| s.complete));
    }
}

#[test]
fn outcomes_named_in_traces_are_outcomes_of_the_model() {
    // A sanity check of the helper the lasso check uses: an interrupted
    // codel leads to its `on-inter`.
    let result = common::check(&common::invalid(
        "unbounded-interrupt.looping-inter-codel.gen",
    ));
    let c = common::component(&result);
    let mv = c.service_named("Move").expect("service exists");
    let start = c.codel_named(mv, "start").expect("codel exists");
    assert_eq!(
        c.codels[start]
            .on_inter
            .map(|r| c.codels[r.id].name.name.clone()),
        Some("brake".to_owned())
    );
    let brake = c.codel_named(mv, "brake").expect("codel exists");
    assert_eq!(c.codels[brake].outcomes(), vec![Outcome::Codel(brake)]);
}
