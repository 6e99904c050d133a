//! Fuzz target `wcet`: the GenoM3 WCET side file (`OWNER.STATE DURATION`
//! lines, `genom-check --wcet`) on arbitrary UTF-8 text, read against one
//! fixed small GenoM3 component through the calls the CLI makes
//! (`genom3_frontend::add_wcet_file`, then the static checks, then, when no
//! error but `codel-overrun` is left, the GenoM3 engines with the timed
//! one, under small limits). It must never panic, every label must point
//! inside a loaded file (the WCET file included), and both renderers must
//! not panic.

#![no_main]

use std::path::Path;
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use genom_check::CheckOptions;
use genom_check_fuzz::{PATH, assert_spans, render};
use genom3_frontend::{Genom3Return, MemoryLoader};
use genom_model::{Code, Severity};
use libfuzzer_sys::fuzz_target;

/// The component the WCETs are given for: a task with permanent codels
/// (`t.start`, `t.main`, `t.stop`), an activity on it (`go.start`,
/// `go.exec`) and a function with a validate codel (`set.validate`,
/// `set.codel`). Small, and without a lock shared between the task and the
/// control thread, so that the timed check of a clean file finishes in
/// milliseconds (with such a lock it took 200 ms under ASan).
const COMPONENT: &str = "component w {
  ids { long x; long y; long z; };
  task t {
    period 10 ms;
    codel<start> w_init(out x) yield main;
    codel<main> w_main(inout x) yield pause::main, stop;
    codel<stop> w_stop(inout x) yield ether;
  };
  activity go() {
    task t;
    codel<start> w_go(out y) yield exec;
    codel<exec> w_exec(inout y) yield pause::exec, ether;
  };
  function set(in long v) { validate w_check(in v); codel w_set(in v, out z); };
};
";

/// The component loaded once (it has no include): the fuzzed WCET file is
/// added to a copy of it.
fn component() -> &'static Genom3Return {
    static LOADED: OnceLock<Genom3Return> = OnceLock::new();
    LOADED.get_or_init(|| {
        let out = genom3_frontend::load_with(
            Path::new(PATH),
            COMPONENT.to_owned(),
            &[],
            &MemoryLoader::new(),
        );
        assert!(
            out.component.is_some()
                && !out
                    .diagnostics
                    .iter()
                    .any(|d| d.severity == Severity::Error),
            "the fixed component must load cleanly: {:#?}",
            out.diagnostics
        );
        out
    })
}

fuzz_target!(|text: &str| {
    let started = Instant::now();
    let base = component();
    let mut out = Genom3Return {
        sources: base.sources.clone(),
        component: base.component.clone(),
        diagnostics: base.diagnostics.clone(),
        ..Genom3Return::default()
    };
    genom3_frontend::add_wcet_file(&mut out, Path::new("fuzz.wcet"), text.to_owned());
    assert_spans(&out.sources, &out.diagnostics);
    let options = CheckOptions::new()
        .max_states(20_000)
        .timeout(Some(Duration::from_millis(200)))
        .max_memory(64 << 20);
    let has_component = out.component.is_some();
    let complete = out.is_complete();
    let model = out.component.take().filter(|_| complete);
    let static_only = options.clone().behaviour(false);
    let mut verdicts =
        genom_checker::verify(model, has_component, out.diagnostics, &static_only, started);
    assert_spans(&out.sources, &verdicts.diagnostics);
    // As the CLI: a codel longer than its period is a timing finding; any
    // other error (a bad WCET line) stops before the engines.
    let clean = !verdicts
        .diagnostics
        .iter()
        .any(|d| d.severity == Severity::Error && d.code != Code::CodelOverrun);
    let mut statistics = None;
    if let (true, Some(c)) = (clean, verdicts.component.as_ref()) {
        if let Some(v) = genom_checker::verify_genom3(c, &options, started) {
            v.attach_codel_overrun_traces(&mut verdicts.diagnostics);
            verdicts.diagnostics.extend(v.diagnostics);
            statistics = Some(v.statistics);
        }
    }
    assert_spans(&out.sources, &verdicts.diagnostics);
    let _ = render(&out.sources, &verdicts.diagnostics, statistics.as_ref());
});
