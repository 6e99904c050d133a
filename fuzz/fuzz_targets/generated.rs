//! Fuzz target `generated`: structure-aware. The input bytes choose a
//! generator configuration (services, codels, threads, rule density, init,
//! autos, timing, loops, self-stops, setters); the generated component is
//! checked twice, with and without the untimed engine's reductions
//! (compositional exploration, partial-order reduction), under small
//! limits. It must never panic, every label must point inside the file,
//! the renderers must not panic, and when both runs complete they must
//! give the same diagnostics (code, severity, message): the reductions
//! are sound and complete for the verdicts (docs/semantics.md).

#![no_main]

use std::path::Path;
use std::time::Duration;

use genom_check::{CheckOptions, CheckResult};
use genom_check_fuzz::{PATH, assert_spans, loader, render};
use genom_generate::GeneratorConfig;
use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;

/// A configuration chosen by the fuzzer's bytes (small enough to explore
/// in milliseconds).
fn config(u: &mut Unstructured<'_>) -> Result<GeneratorConfig> {
    let services = u.int_in_range(1..=6)?;
    let mut c = GeneratorConfig::new(u.arbitrary()?, services);
    c.codels_per_service = u.int_in_range(1..=4)?;
    c.threads = u.int_in_range(1..=3)?;
    c.rule_density = f64::from(u.int_in_range(0u8..=12)?) / 4.0;
    c.init = u.arbitrary()?;
    c.autos = u.int_in_range(0..=services)?;
    c.timed = u.arbitrary()?;
    c.auto_rules = u.arbitrary()?;
    c.setters = f64::from(u.int_in_range(0u8..=4)?) / 4.0;
    c.loops = f64::from(u.int_in_range(0u8..=4)?) / 4.0;
    c.self_stops = f64::from(u.int_in_range(0u8..=4)?) / 4.0;
    c.ids_blocks = u.int_in_range(0..=2)?;
    c.exports = u.int_in_range(0..=2)?;
    Ok(c)
}

fn check(text: &str, reduction: bool) -> CheckResult {
    let options = CheckOptions::new()
        .max_states(50_000)
        .timeout(Some(Duration::from_millis(500)))
        .max_memory(64 << 20)
        .reduction(reduction);
    genom_check::check_source(Path::new(PATH), text.to_owned(), &loader(), &options)
}

/// The verdicts of a run: what each diagnostic says, in order.
fn verdicts(r: &CheckResult) -> Vec<String> {
    r.diagnostics
        .iter()
        .map(|d| format!("{:?} {:?} {}", d.severity, d.code, d.message))
        .collect()
}

fn complete(r: &CheckResult) -> bool {
    r.statistics.as_ref().is_some_and(|s| s.complete)
}

fuzz_target!(|data: &[u8]| {
    let mut u = Unstructured::new(data);
    let Ok(config) = config(&mut u) else {
        return;
    };
    let text = genom_generate::generate(&config);
    let reduced = check(&text, true);
    let whole = check(&text, false);
    for r in [&reduced, &whole] {
        assert_spans(&r.sources, &r.diagnostics);
        let _ = render(&r.sources, &r.diagnostics, r.statistics.as_ref());
    }
    if complete(&reduced) && complete(&whole) {
        assert_eq!(
            verdicts(&reduced),
            verdicts(&whole),
            "the reductions changed the verdicts of\n{text}"
        );
    }
});
