//! A GenoM3 file checked through the command line: recognition and static
//! checks, behaviour and timing, how each part was decided, instances, the
//! exports and runtime configuration, `--dialect`, include folders, pragmas
//! in the JSON report, WCET file problems, exceptions thrown from C code.

use serde_json::Value;

use super::support::*;

#[test]
fn a_genom3_file_is_recognised_and_its_static_checks_run() {
    let (status, file) = json(&["--static-only", "--wcet", DEMO_WCET, DEMO]);
    assert_eq!(status, 0, "{file:#}");
    assert_eq!(file["dialect"], "genom3");
    assert!(codes(&file, "error").is_empty(), "{file:#}");
    assert!(file["statistics"].is_null());
    let out = genom_check()
        .args([
            "--static-only",
            "--color",
            "never",
            "--wcet",
            DEMO_WCET,
            DEMO,
        ])
        .output()
        .unwrap();
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(
        stdout.contains(&format!("{DEMO} (GenoM3): 0 errors, 0 warnings")),
        "{stdout}"
    );
    // A LANGUAGE.md file says its dialect in JSON, and nothing in the summary.
    let (status, file) = json(&["--static-only", "specs/pilot.gen"]);
    assert_eq!((status, &file["dialect"]), (0, &Value::from("gen")));
    assert_eq!(file["pragmas"], Value::Array(Vec::new()));
}

#[test]
fn genom3_behaviour_is_explored_and_its_timing_checked() {
    // Without WCETs: the GenoM3 engine explores it and finds nothing.
    let (status, file) = json(&[DEMO]);
    assert_eq!(status, 0, "{file:#}");
    assert_eq!(file["statistics"]["complete"], Value::Bool(true));
    assert!(file["statistics"]["states"].as_u64().unwrap() > 1);
    // With WCETs: the timed GenoM3 engine checks schedulability. Task `io`
    // (period 20 ms) runs an `async` codel, unbounded: it overruns; `main`
    // does not.
    let (status, file) = json(&["--wcet", DEMO_WCET, DEMO]);
    assert_eq!(status, 1);
    assert_eq!(codes(&file, "error"), ["thread-overrun"]);
    let d = file["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .find(|d| d["code"] == "thread-overrun")
        .unwrap();
    assert!(
        d["message"].as_str().unwrap().contains("task `io`"),
        "{d:#}"
    );
    assert_eq!(
        (d["line"].as_u64(), d["file"].as_str()),
        (Some(56), Some(DEMO))
    );
    let steps = d["trace"].as_array().unwrap();
    let last = steps.last().unwrap();
    assert_eq!(last["event"], "violation");
    assert!(last["text"].as_str().unwrap().contains("async"), "{last:#}");
    assert_eq!(last["time_ns"].as_u64(), Some(21_000_000));
    assert_eq!(file["statistics"]["complete"], Value::Bool(true));
    // An export needs a verified model: refused, and allowed only marked.
    let refused = genom_check()
        .args(["export", "uppaal", "--wcet", DEMO_WCET, DEMO])
        .output()
        .unwrap();
    assert_eq!(refused.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(stderr.contains("refusing to export"), "{stderr}");
    assert!(stderr.contains("thread-overrun"), "{stderr}");
}

/// `decided_by` gives one entry per part of the untimed exploration: the
/// permanent activities, then each group of linked services (here `halt`
/// interrupts `move`; `ping` stands alone), with its states; with WCETs,
/// one `zones` entry per group of coupled tasks follows.
#[test]
fn each_part_says_how_it_was_decided() {
    let dir = tempfile::tempdir().unwrap();
    let text = "component p {
  task t { period 10 ms; codel<start> boot() yield pause::start; };
  activity move() { task t; codel<start> go() yield pause::start, ether; };
  activity halt() { task t; interrupts move; codel<start> h() yield ether; };
  function ping() { codel pong(); };
};
";
    let path = write(dir.path(), "p.gen", text);
    let (status, file) = json(&[path.to_str().unwrap()]);
    assert_eq!(status, 0, "{file:#}");
    let decided = file["statistics"]["decided_by"].as_array().unwrap();
    let parts: Vec<(Vec<&str>, &str, bool)> = decided
        .iter()
        .map(|d| {
            let names = d["services"].as_array().unwrap();
            let names = names.iter().map(|n| n.as_str().unwrap()).collect();
            (names, d["engine"].as_str().unwrap(), d["complete"] == true)
        })
        .collect();
    assert_eq!(
        parts,
        [
            (vec!["task t"], "explicit", true),
            (vec!["move", "halt"], "explicit", true),
            (vec!["ping"], "explicit", true),
        ]
    );
    let sum: u64 = decided.iter().map(|d| d["states"].as_u64().unwrap()).sum();
    assert_eq!(Some(sum), file["statistics"]["states"].as_u64());
    assert!(decided[1]["states"].as_u64() > decided[2]["states"].as_u64());
    // With WCETs: then one entry per group of coupled tasks, each naming
    // its tasks first: `zones` when explored, `bound` (no state) when the
    // static bound of each task's wake-up decides it (main's short codels
    // in its 5 ms period; io's `async` codel has no bound); the figures
    // add up to the total.
    let (_, file) = json(&["--wcet", DEMO_WCET, DEMO]);
    let decided = file["statistics"]["decided_by"].as_array().unwrap();
    let timed: Vec<(&str, &str, u64)> = decided
        .iter()
        .filter(|d| d["engine"] == "zones" || d["engine"] == "bound")
        .map(|d| {
            (
                d["services"][0].as_str().unwrap(),
                d["engine"].as_str().unwrap(),
                d["states"].as_u64().unwrap(),
            )
        })
        .collect();
    assert_eq!(timed.len(), 2, "{decided:#?}");
    assert_eq!(
        (timed[0].0, timed[0].1, timed[0].2),
        ("task main", "bound", 0)
    );
    assert_eq!((timed[1].0, timed[1].1), ("task io", "zones"));
    assert!(timed[1].2 > 0);
    let sum: u64 = decided.iter().map(|d| d["states"].as_u64().unwrap()).sum();
    assert_eq!(Some(sum), file["statistics"]["states"].as_u64());
}

#[test]
fn max_instances_explores_more_instances_with_the_same_verdicts() {
    const F6: &str = "tests/fixtures/genom3/semantics/f6_interrupt_stop.gen";
    let (status, one) = json(&[F6]);
    let (status2, three) = json(&["--max-instances", "3", F6]);
    assert_eq!((status, status2), (0, 0));
    let states = |f: &Value| f["statistics"]["states"].as_u64().unwrap();
    assert!(states(&three) > states(&one), "{one:#} {three:#}");
    assert_eq!(one["diagnostics"], three["diagnostics"]);
    let out = genom_check()
        .args(["--max-instances", "32", F6])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("from 1 to 31"));
}

#[test]
fn genom3_exports_fiacre_untimed_without_wcet_and_the_timed_networks_with_it() {
    // Without a WCET file the Fiacre model of a GenoM3 component is its
    // untimed reading, and stderr says so with the remedy.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("demo.fcr");
    let untimed = genom_check()
        .args(["export", "fiacre"])
        .arg(DEMO)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(untimed.status.code(), Some(0));
    let stderr = String::from_utf8_lossy(&untimed.stderr);
    assert!(
        stderr.contains("--wcet") && stderr.contains("untimed reading"),
        "{stderr}"
    );
    assert!(std::fs::read_to_string(&out).unwrap().contains("process"));
    // The timed-automata exports print GenoM3's own timed semantics.
    for (format, file) in [("uppaal", "demo.xml"), ("tchecker", "demo.tck")] {
        let path = dir.path().join(file);
        let done = genom_check()
            .args(["export", format, DEMO, "-o"])
            .arg(&path)
            .output()
            .unwrap();
        assert_eq!(done.status.code(), Some(0), "{format}: {done:?}");
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains("GenoM3's timed semantics"), "{format}");
        assert!(!text.contains(genom_export::UNVERIFIED), "{format}");
    }
    // A diagram draws structure only: exported as verified.
    let dot = dir.path().join("demo.dot");
    let drawn = genom_check()
        .args(["export", "dot", DEMO, "-o"])
        .arg(&dot)
        .output()
        .unwrap();
    assert_eq!(drawn.status.code(), Some(0), "{drawn:?}");
    assert!(std::fs::read_to_string(&dot).unwrap().contains("digraph"));
    // The Promela export models GenoM3's own untimed semantics: verified.
    let pml = dir.path().join("demo.pml");
    let modelled = genom_check()
        .args(["export", "promela", DEMO, "-o"])
        .arg(&pml)
        .output()
        .unwrap();
    assert_eq!(modelled.status.code(), Some(0), "{modelled:?}");
    let text = std::fs::read_to_string(&pml).unwrap();
    assert!(text.starts_with("/* GenoM3's untimed semantics"), "{text}");
    assert!(text.contains("Verification: verified"), "{text}");
}

#[test]
fn the_runtime_configuration_of_a_genom3_component_carries_its_response_times() {
    let dir = tempfile::tempdir().unwrap();
    let fixed = "tests/fixtures/genom3/timing/f10_restart_fixed";
    let out = dir.path().join("fixed.json");
    let wcet = format!("{fixed}.wcet");
    let done = genom_check()
        .args([
            "export",
            "config",
            &format!("{fixed}.gen"),
            "--wcet",
            &wcet,
            "-o",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(done.status.code(), Some(0), "{done:?}");
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(doc["format"], "genom-check/genom3-runtime-config");
    assert_eq!(doc["verified"], Value::Bool(true));
    assert_eq!(doc["assumptions"]["wcet_file"]["path"], Value::String(wcet));
    let timed: Vec<&str> = doc["services"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|s| !s["response_time"].is_null())
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert_eq!(timed, ["plan", "track"]);
    // The broken version overruns: refused, then exported marked.
    let broken = "tests/fixtures/genom3/timing/f10_restart";
    let path = dir.path().join("broken.json");
    let args = |extra: &[&str]| {
        let mut a = vec![
            "export".to_owned(),
            "config".to_owned(),
            format!("{broken}.gen"),
            "--wcet".to_owned(),
            format!("{broken}.wcet"),
        ];
        a.extend(extra.iter().map(|x| (*x).to_owned()));
        a
    };
    let refused = genom_check()
        .args(args(&[]))
        .arg("-o")
        .arg(&path)
        .output()
        .unwrap();
    assert_eq!(refused.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("thread-overrun"));
    assert!(!path.exists());
    let marked = genom_check()
        .args(args(&["--allow-unverified"]))
        .arg("-o")
        .arg(&path)
        .output()
        .unwrap();
    assert_eq!(marked.status.code(), Some(0), "{marked:?}");
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(doc["verified"], Value::Bool(false));
    assert_eq!(
        doc["verification"]["error_codes"],
        serde_json::json!(["thread-overrun"])
    );
}

#[test]
fn the_dialect_can_be_forced() {
    // GenoM3 read as LANGUAGE.md: a syntax error at its first GenoM3 line.
    let (status, file) = json(&["--dialect", "gen", "--static-only", DEMO]);
    assert_eq!(status, 1);
    assert_eq!(file["dialect"], "gen");
    let errors = codes(&file, "error");
    assert!(
        !errors.is_empty() && errors.iter().all(|c| c == "syntax"),
        "{errors:?}"
    );
    // LANGUAGE.md read as GenoM3: rejected by the GenoM3 grammar.
    let (status, file) = json(&["--dialect", "genom3", "--static-only", "specs/pilot.gen"]);
    assert_eq!(status, 1);
    assert_eq!(file["dialect"], "genom3");
    assert!(
        codes(&file, "error").contains(&"syntax".to_owned()),
        "{file:#}"
    );
}

const USES_POSE: &str = "#include \"pose.idl\"\n\
    component c {\n  ids { pose::xyz p; };\n  task t { period 10 ms; };\n\
    activity a() {\n    task t;\n    codel<start> go(in p) yield ether;\n  };\n};\n";

#[test]
fn includes_are_searched_in_each_include_dir_in_order_then_the_environment() {
    let dir = tempfile::tempdir().unwrap();
    let main = write(dir.path(), "src/c.gen", USES_POSE);
    write(
        dir.path(),
        "first/pose.idl",
        "module pose { struct xyz { double x; }; };\n",
    );
    write(
        dir.path(),
        "second/pose.idl",
        "module pose { struct xyz { double x } };\n",
    );
    write(
        dir.path(),
        "env/pose.idl",
        "module pose { struct xyz { double x; }; };\n",
    );
    let main = main.to_str().unwrap();
    let first = dir.path().join("first");
    let second = dir.path().join("second");
    let (first, second) = (first.to_str().unwrap(), second.to_str().unwrap());
    // `first` before `second`: the good file is read.
    let (status, file) = json(&["--static-only", "-I", first, "-I", second, main]);
    assert_eq!(status, 0, "{file:#}");
    // `second` first: its syntax error is reported, in that file.
    let (status, file) = json(&["--static-only", "-I", second, "-I", first, main]);
    assert_eq!(status, 1);
    assert_eq!(codes(&file, "error"), ["syntax"]);
    let at = file["diagnostics"][0]["file"].as_str().unwrap();
    assert!(at.ends_with("second/pose.idl"), "{at}");
    // Nowhere: `include-not-found` names the folders and suggests `-I`.
    let (status, file) = json(&["--static-only", main]);
    assert_eq!(status, 1);
    assert_eq!(codes(&file, "error"), ["include-not-found"]);
    let help = file["diagnostics"][0]["help"].as_str().unwrap_or_default();
    assert!(help.contains("-I"), "{file:#}");
    // GENOM_INCLUDE_PATH is searched after the `-I` folders.
    let env = dir.path().join("env");
    let out = genom_check()
        .env("GENOM_INCLUDE_PATH", &env)
        .args(["--static-only", "--format", "json", main])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let out = genom_check()
        .env("GENOM_INCLUDE_PATH", &env)
        .args(["--static-only", "-I", second, main])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(1),
        "-I comes before the environment"
    );
}

#[test]
fn pragmas_are_in_the_json_report() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "#pragma require \"openrobots2-idl >= 2.0\"\n#pragma provides nothing\n{USES_POSE}"
    );
    let main = write(dir.path(), "c.gen", &text);
    write(
        dir.path(),
        "pose.idl",
        "module pose { struct xyz { double x; }; };\n",
    );
    let (status, file) = json(&["--static-only", main.to_str().unwrap()]);
    assert_eq!(status, 0, "{file:#}");
    let pragmas: Vec<(String, String, u64)> = file["pragmas"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            (
                p["kind"].as_str().unwrap().to_owned(),
                p["args"].as_str().unwrap().to_owned(),
                p["line"].as_u64().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        pragmas,
        [
            ("require".into(), "\"openrobots2-idl >= 2.0\"".into(), 1),
            ("provides".into(), "nothing".into(), 2),
        ]
    );
}

#[test]
fn wcet_file_problems_are_reported() {
    // Unreadable: exit 2 naming the WCET file, not the component.
    let out = genom_check()
        .args(["--static-only", "--wcet", "no/such.wcet", DEMO])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(stderr.contains("cannot read `no/such.wcet`"), "{stderr}");
    // On a LANGUAGE.md file: a usage error that says why.
    let out = genom_check()
        .args(["--wcet", DEMO_WCET, "specs/pilot.gen"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(stderr.contains("read as LANGUAGE.md"), "{stderr}");
    // A bad entry: `bad-wcet` with a span in the WCET file.
    let wcet = format!("{FIXTURES}/invalid/bad-wcet.unknown-state.wcet");
    let gen_file = format!("{FIXTURES}/invalid/bad-wcet.unknown-state.gen");
    let (status, file) = json(&["--static-only", "--wcet", &wcet, &gen_file]);
    assert_eq!(status, 1);
    let bad: Vec<&Value> = file["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|d| d["code"] == "bad-wcet")
        .collect();
    assert!(!bad.is_empty(), "{file:#}");
    assert!(bad.iter().all(|d| d["file"] == wcet.as_str()), "{file:#}");
}

#[test]
fn exceptions_thrown_from_c_code_are_not_unused_reports() {
    // In GenoM3 a codel throws from its C code: `throw e;` with no yield
    // to it is normal, not an `unused-report` (which LANGUAGE.md reports).
    let dir = tempfile::tempdir().unwrap();
    let text = "component c {\n  exception e_fail;\n  task t { period 10 ms; };\n\
        activity a() {\n    task t;\n    codel<start> go() yield pause::start, ether;\n    throw e_fail;\n  };\n\
        function f() { interrupt a; };\n};\n";
    let main = write(dir.path(), "c.gen", text);
    let (status, file) = json(&["--static-only", main.to_str().unwrap()]);
    assert_eq!(status, 0, "{file:#}");
    let all: Vec<String> = ["error", "warning", "advice"]
        .iter()
        .flat_map(|s| codes(&file, s))
        .collect();
    assert!(!all.contains(&"unused-report".to_owned()), "{file:#}");
    assert!(!all.contains(&"missing-on-inter".to_owned()), "{file:#}");
    assert!(all.contains(&"missing-wcet".to_owned()), "{file:#}");
    let help = file["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .find(|d| d["code"] == "missing-wcet")
        .and_then(|d| d["help"].as_str())
        .unwrap();
    assert!(help.contains("--wcet"), "{help}");
}
