//! The near-identical valid twins of the invalid fixtures, which must not
//! have the verdict, and at least two fixture pairs per behavioural code.

use super::support::{BEHAVIOURAL, gen_files};
use crate::common;

use genom_model::{Code, Diagnostic};
// ------------------------------------------------------------------- twins

/// Each invalid fixture, its valid twin, and the verdicts only the invalid
/// one has.
const TWINS: &[(&str, &str, &[Code])] = &[
    (
        "deadlock.circular-delays.gen",
        "delays-chain-without-back-edge.gen",
        &[Code::Deadlock],
    ),
    (
        "deadlock.three-way-cycle.gen",
        "../invalid/max-time-exceeded.delays-cycle-broken-by-watchdog.gen",
        &[Code::Deadlock],
    ),
    (
        "starvation.behind-auto-service.gen",
        "../invalid/max-time-exceeded.waiter-behind-auto-service.gen",
        &[Code::Starvation],
    ),
    (
        "starvation.behind-endless-loop.gen",
        "loop-blocker-has-max-time.gen",
        &[Code::Starvation],
    ),
    (
        "starvation.auto-started-by-init.gen",
        "calibrate-stops-sampling.gen",
        &[Code::Starvation],
    ),
    (
        "dead-service.init-never-succeeds.gen",
        "init-can-succeed.gen",
        &[Code::DeadService],
    ),
    (
        "dead-service.forbidden-by-auto.gen",
        "auto-service-forbids-nothing.gen",
        &[Code::DeadService],
    ),
    (
        "dead-service.delayed-by-auto.gen",
        "update-stops-auto-service.gen",
        &[Code::DeadService, Code::Starvation, Code::UnreachableCodel],
    ),
    (
        "unbounded-interrupt.looping-inter-codel.gen",
        "inter-codel-exits.gen",
        &[Code::UnboundedInterrupt],
    ),
    (
        "unbounded-interrupt.loop-with-exit.gen",
        "inter-codel-exits.gen",
        &[Code::UnboundedInterrupt],
    ),
    (
        "unbounded-interrupt.watchdog-cleanup-loop.gen",
        "watchdog-cleanup-ends.gen",
        &[Code::UnboundedInterrupt],
    ),
    (
        "unreachable-codel.inter-only-when-forbidden.gen",
        "halt-may-interrupt-scan.gen",
        &[Code::UnreachableCodel],
    ),
    (
        "unreachable-codel.stopper-locked-out.gen",
        "stopper-control-codel-without-lock.gen",
        &[Code::UnreachableCodel],
    ),
];

#[test]
fn each_invalid_fixture_has_a_near_identical_twin_without_the_verdict() {
    for &(bad, good, codes) in TWINS {
        let (bad_path, good_path) = (common::invalid(bad), common::valid(good));
        let changed = common::changed_lines(&common::body(&bad_path), &common::body(&good_path));
        assert!(
            changed <= 2,
            "{bad} and {good} differ by {changed} lines: one rule should change"
        );
        let bad_result = common::check(&bad_path);
        let good_result = common::check(&good_path);
        for &code in codes {
            assert!(
                bad_result.diagnostics.iter().any(|d| d.code == code),
                "{bad} reports `{code}`:\n{}",
                common::render(&bad_path, &bad_result)
            );
        }
        let unexpected: Vec<&Diagnostic> = good_result
            .diagnostics
            .iter()
            .filter(|d| BEHAVIOURAL.contains(&d.code) || d.code == Code::UnreachableCodel)
            .collect();
        assert!(
            unexpected.is_empty(),
            "{good} must be clean:\n{}",
            common::render(&good_path, &good_result)
        );
        assert!(
            good_result.statistics.as_ref().is_some_and(|s| s.complete),
            "{good} is fully explored"
        );
    }
}

#[test]
fn every_behavioural_code_has_at_least_two_fixture_pairs() {
    let invalid = gen_files("tests/fixtures/invalid");
    for code in [
        Code::Deadlock,
        Code::Starvation,
        Code::DeadService,
        Code::UnboundedInterrupt,
        Code::UnreachableCodel,
    ] {
        let n = TWINS
            .iter()
            .filter(|(bad, _, _)| bad.starts_with(&format!("{code}.")))
            .count();
        assert!(n >= 2, "`{code}` has {n} fixtures with twins");
        for (bad, _, _) in TWINS
            .iter()
            .filter(|(bad, _, _)| bad.starts_with(&format!("{code}.")))
        {
            assert!(invalid.iter().any(|p| p.ends_with(bad)), "{bad} exists");
        }
    }
}
