//! `genom-check budget` (cargo feature `smt`): every budget it prints is
//! re-checked through the library, independently of the budget search: the
//! file's text is edited to give the codel that WCET (or every WCET scaled
//! by the factor) and checked as `genom-check check` does. Clean at the
//! budget, an error one nanosecond above it (one step of 1/1000 above the
//! scale factor).
//!
//! Built without `smt`, the subcommand exits with status 2 and says why.

#![allow(clippy::expect_used)] // test support code outside #[test] functions

use assert_cmd::Command;

/// Without z3, `budget` is refused with a message (status 2).
#[cfg(not(feature = "smt"))]
#[test]
fn without_smt_budget_exits_2_and_says_why() {
    let out = Command::cargo_bin("genom-check")
        .expect("binary")
        .args(["budget", "specs/battery.gen"])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("without the `smt` feature"), "{stderr}");
    assert!(out.stdout.is_empty());
}

#[cfg(feature = "smt")]
mod with_smt {
    use std::path::Path;

    use gen_frontend::FsLoader;
    use genom_check::CheckOptions;
    use genom_model::Severity;
    use genom_model::component::Component;
    use serde_json::Value;

    use super::Command;

    /// Clean fixtures and specs with WCETs, small enough to search in a test.
    const CLEAN: &[&str] = &[
        "tests/fixtures/valid/control-codel-fits-the-period.gen",
        "tests/fixtures/valid/three-codels-in-30ms.gen",
        "tests/fixtures/valid/worst-case-equals-max-time.gen",
        "tests/fixtures/valid/bounded-service-with-max-time.gen",
        "tests/fixtures/timing/wcet-equals-period.gen",
        "specs/battery.gen",
    ];

    /// Runs `budget --format json` and returns its status and document.
    fn budget(path: &str, extra: &[&str]) -> (i32, Value) {
        let out = Command::cargo_bin("genom-check")
            .expect("binary")
            .args(["budget", "--format", "json", path])
            .args(extra)
            .output()
            .expect("runs");
        let doc = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
            panic!(
                "{path}: not JSON ({e}): {}{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            )
        });
        (out.status.code().unwrap_or(-1), doc)
    }

    fn component(path: &str, text: &str) -> Component {
        let r = genom_check::check_source(
            Path::new(path),
            text.to_owned(),
            &FsLoader,
            &CheckOptions::new().behaviour(false),
        );
        r.component.expect("a component")
    }

    /// `text` with codel `label`'s WCET set to `ns` (written in the file:
    /// its `max-time` replaced, or one added at the top of the codel).
    fn with_wcet(c: &Component, text: &str, label: &str, ns: u64) -> String {
        let (s, k) = label.split_once("::").expect("SERVICE::CODEL");
        let id = c
            .service_named(s)
            .and_then(|s| c.codel_named(s, k))
            .expect("codel");
        let codel = &c.codels[id];
        let mut out = text.to_owned();
        match codel.wcet {
            Some(w) => out.replace_range(
                w.span.start as usize..w.span.end as usize,
                &format!("{ns}ns"),
            ),
            None => {
                let brace = text[codel.name.span.end as usize..]
                    .find('{')
                    .expect("codel body")
                    + codel.name.span.end as usize;
                out.insert_str(brace + 1, &format!(" max-time: {ns}ns; "));
            }
        }
        out
    }

    /// `text` with every WCET scaled by `steps`/1000, rounded down.
    fn scaled(c: &Component, text: &str, steps: u64) -> String {
        let mut spans: Vec<_> = c.codels.values().filter_map(|k| k.wcet).collect();
        spans.sort_by_key(|w| std::cmp::Reverse(w.span.start));
        let mut out = text.to_owned();
        for w in spans {
            let ns = u128::from(w.ns) * u128::from(steps) / 1000;
            out.replace_range(
                w.span.start as usize..w.span.end as usize,
                &format!("{ns}ns"),
            );
        }
        out
    }

    /// The error codes of `text`, checked as `genom-check check` does.
    fn errors(path: &str, text: &str) -> Vec<String> {
        let r = genom_check::check_source(
            Path::new(path),
            text.to_owned(),
            &FsLoader,
            &CheckOptions::new(),
        );
        r.diagnostics
            .iter()
            .filter(|d| d.severity == Severity::Error)
            .map(|d| d.code.to_string())
            .collect()
    }

    fn codes(v: &Value) -> Vec<String> {
        v.as_array()
            .expect("codes")
            .iter()
            .map(|c| c.as_str().expect("code").to_owned())
            .collect()
    }

    /// Every exact budget of `path` is clean at its value and has the
    /// reported errors 1 ns above; the scale factor likewise.
    fn verify(path: &str, doc: &Value) -> usize {
        let text = std::fs::read_to_string(path).expect("readable");
        let c = component(path, &text);
        let mut checked = 0;
        for b in doc["codels"].as_array().expect("codels") {
            let label = b["codel"].as_str().expect("label");
            let status = b["status"].as_str().expect("status");
            let ns = b["budget_ns"].as_u64().expect("a budget");
            assert!(
                status == "exact" || status == "unbounded",
                "{path} {label}: {b}"
            );
            // `max-time: 0ns` is not writable (a duration is positive): a
            // budget of 0 for a codel without WCET is the file as it is.
            let at_budget = if ns == 0 && b["wcet_ns"].is_null() {
                text.clone()
            } else {
                with_wcet(&c, &text, label, ns)
            };
            let at = errors(path, &at_budget);
            assert!(at.is_empty(), "{path} {label} at {ns} ns: {at:?}");
            if status == "exact" {
                let above = errors(path, &with_wcet(&c, &text, label, ns + 1));
                assert!(!above.is_empty(), "{path} {label} at {ns} + 1 ns is clean");
                for code in codes(&b["limited_by"]) {
                    assert!(
                        above.contains(&code),
                        "{path} {label}: {code} not in {above:?}"
                    );
                }
                checked += 1;
            }
        }
        if let Some(steps) = doc["scale"]["steps"].as_u64() {
            assert_eq!(doc["scale"]["status"], "exact", "{path}: {}", doc["scale"]);
            assert!(
                errors(path, &scaled(&c, &text, steps)).is_empty(),
                "{path} ×{steps}/1000"
            );
            let above = errors(path, &scaled(&c, &text, steps + 1));
            assert!(!above.is_empty(), "{path}: clean at ×({steps} + 1)/1000");
            checked += 1;
        }
        checked
    }

    #[test]
    fn every_budget_is_clean_at_its_value_and_not_one_unit_above() {
        for path in CLEAN {
            let (status, doc) = budget(path, &[]);
            assert_eq!(status, 0, "{path}: {doc}");
            assert_eq!(doc["clean_as_given"], true, "{path}");
            assert_eq!(doc["unit_ns"], 1);
            let n = doc["codels"].as_array().map_or(0, Vec::len);
            assert!(n > 0, "{path}: no codel");
            let checked = verify(path, &doc);
            assert!(checked > 0, "{path}: nothing exact");
        }
    }

    #[test]
    fn the_documented_budgets_of_the_shared_period() {
        // docs/timing.md, "WCET budgets": Servo 6 ms and SetGain's control
        // codel 3 ms in a 10 ms period, where SetGain can take the lock just
        // before a wake-up.
        let (status, doc) = budget(
            "tests/fixtures/valid/control-codel-fits-the-period.gen",
            &[],
        );
        assert_eq!(status, 0);
        let row = |label: &str| {
            doc["codels"]
                .as_array()
                .and_then(|a| a.iter().find(|b| b["codel"] == label))
                .cloned()
                .expect(label)
        };
        assert_eq!(row("Servo::start")["budget_ns"], 7_000_000);
        assert_eq!(row("SetGain::control")["budget_ns"], 4_000_000);
        assert_eq!(
            codes(&row("Servo::start")["limited_by"]),
            ["thread-overrun"]
        );
        assert_eq!(doc["scale"]["steps"], 1111);
        // The exact margin: no WCET, and clean only at 0.
        let (_, doc) = budget(
            "tests/fixtures/valid/three-codels-in-30ms.gen",
            &["--codel", "Move::c"],
        );
        let rows = doc["codels"].as_array().expect("codels");
        assert_eq!(rows.len(), 1);
        assert_eq!(rows[0]["wcet_ns"], Value::Null);
        assert_eq!(rows[0]["budget_ns"], 0);
        assert_eq!(codes(&rows[0]["limited_by"]), ["max-time-exceeded"]);
        assert_eq!(doc["scale"], Value::Null, "no WCET to scale");
    }

    #[test]
    fn a_component_with_errors_still_gets_budgets_and_exits_1() {
        let path = "tests/fixtures/invalid/thread-overrun.two-services-share-a-period.gen";
        let (status, doc) = budget(path, &[]);
        assert_eq!(status, 1);
        assert_eq!(doc["clean_as_given"], false);
        assert_eq!(codes(&doc["errors_as_given"]), ["thread-overrun"]);
        assert!(verify(path, &doc) > 0);
    }

    #[test]
    fn the_table_lists_every_codel_and_the_factor() {
        let out = Command::cargo_bin("genom-check")
            .expect("binary")
            .args([
                "budget",
                "tests/fixtures/valid/control-codel-fits-the-period.gen",
            ])
            .output()
            .expect("runs");
        assert_eq!(out.status.code(), Some(0));
        let text = String::from_utf8_lossy(&out.stdout);
        let servo = text
            .lines()
            .find(|l| l.contains("Servo::start"))
            .expect("a row");
        let cells: Vec<&str> = servo.split_whitespace().collect();
        assert_eq!(
            cells,
            ["Servo::start", "6ms", "7ms", "7ms", "thread-overrun"]
        );
        assert!(
            text.contains("×1.111 (clean at ×1.111, thread-overrun at ×1.112)"),
            "{text}"
        );
    }

    #[test]
    fn an_unknown_codel_is_a_usage_error() {
        let out = Command::cargo_bin("genom-check")
            .expect("binary")
            .args(["budget", "specs/battery.gen", "--codel", "Monitor::nope"])
            .output()
            .expect("runs");
        assert_eq!(out.status.code(), Some(2));
        assert!(String::from_utf8_lossy(&out.stderr).contains("no codel `Monitor::nope`"));
    }

    #[test]
    fn a_genom3_component_is_refused_until_its_semantics_are_modelled() {
        let out = Command::cargo_bin("genom-check")
            .expect("binary")
            .args([
                "budget",
                "genom3-frontend/tests/fixtures/valid/demo.gen",
                "--wcet",
                "genom3-frontend/tests/fixtures/valid/demo.wcet",
            ])
            .output()
            .expect("runs");
        assert_eq!(out.status.code(), Some(1));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains("GenoM3's execution semantics"), "{stderr}");
    }
}
