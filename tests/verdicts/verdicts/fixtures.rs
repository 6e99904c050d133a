//! Each invalid fixture's behavioural verdict (deadlock, starvation,
//! dead-service, unbounded-interrupt, the dynamic part of
//! unreachable-codel) with its message, primary line and exact trace.

use super::support::{Expected, verify};
use crate::common;

use gen_frontend::FsLoader;
use genom_check::CheckOptions;
use genom_model::{Code, Diagnostic};
use genom_oracles::replay::Claim;
// ---------------------------------------------------------------- deadlock

#[test]
fn deadlock_circular_wait_through_delays() {
    verify(&Expected {
        fixture: "deadlock.circular-delays.gen",
        code: Code::Deadlock,
        message: "deadlock: `Grasp` and `Release` can be pending and wait on each other forever",
        line: 25,
        help: Some(
            "break the cycle: remove one of these `delays`, or use `forbids` to make the services exclusive",
        ),
        trace: &[
            "component-start",
            "request Calibrate",
            "acknowledge Calibrate",
            "start Calibrate::start",
            "request Grasp",
            "acknowledge Grasp",
            "request Release",
            "acknowledge Release",
            "violation",
        ],
        loop_start: None,
        claim: Claim::Deadlock(&["Grasp", "Release"]),
    });
}

#[test]
fn deadlock_three_way_cycle() {
    verify(&Expected {
        fixture: "deadlock.three-way-cycle.gen",
        code: Code::Deadlock,
        message: "deadlock: `Localize`, `Plan` and `Drive` can be pending and wait on each other forever",
        line: 26,
        help: None,
        trace: &[
            "component-start",
            "request Map",
            "acknowledge Map",
            "start Map::start",
            "request Localize",
            "acknowledge Localize",
            "request Plan",
            "acknowledge Plan",
            "request Drive",
            "acknowledge Drive",
            "violation",
        ],
        loop_start: None,
        claim: Claim::Deadlock(&["Localize", "Plan", "Drive"]),
    });
}

// -------------------------------------------------------------- starvation

#[test]
fn starvation_behind_an_auto_service() {
    verify(&Expected {
        fixture: "starvation.behind-auto-service.gen",
        code: Code::Starvation,
        message: "`Calibrate` can wait forever for `Stream`, which may never end",
        line: 38,
        help: Some(
            "give `Stream` a `max-time` or an exit from its loop, or do not make `Calibrate` wait for it",
        ),
        trace: &[
            "component-start",
            "start Stream::start",
            "request Calibrate",
            "acknowledge Calibrate",
            "codel-start Stream::start",
            "codel-end Stream::start -> grab",
            "codel-start Stream::grab",
            "codel-end Stream::grab -> grab",
            "violation",
        ],
        loop_start: Some(6),
        claim: Claim::Starvation {
            waiter: "Calibrate",
            blocker: "Stream",
        },
    });
}

#[test]
fn starvation_behind_a_loop_without_max_time() {
    verify(&Expected {
        fixture: "starvation.behind-endless-loop.gen",
        code: Code::Starvation,
        message: "`Park` can wait forever for `Track`, which may never end",
        line: 24,
        help: Some(
            "give `Track` a `max-time` or an exit from its loop, or do not make `Park` wait for it",
        ),
        trace: &[
            "component-start",
            "request Track",
            "acknowledge Track",
            "start Track::start",
            "request Park",
            "acknowledge Park",
            "codel-start Track::start",
            "codel-end Track::start -> follow",
            "codel-start Track::follow",
            "codel-end Track::follow -> follow",
            "violation",
        ],
        loop_start: Some(8),
        claim: Claim::Starvation {
            waiter: "Park",
            blocker: "Track",
        },
    });
}

/// The trace goes through initialisation: `Open` replies `end` once, then
/// the auto service is acknowledged. (The explorer currently adds a second
/// `reply` step for `Open`, with no value, to say that initialisation
/// completes: section 3 gives each instance exactly one final reply.)
#[test]
fn starvation_behind_an_auto_service_started_by_init() {
    verify(&Expected {
        fixture: "starvation.auto-started-by-init.gen",
        code: Code::Starvation,
        message: "`Calibrate` can wait forever for `Sample`, which may never end",
        line: 39,
        help: None,
        trace: &[
            "component-start",
            "request Open",
            "acknowledge Open",
            "start Open::start",
            "codel-start Open::start",
            "codel-end Open::start -> end",
            "reply Open -> end",
            "start Sample::start",
            "request Calibrate",
            "acknowledge Calibrate",
            "codel-start Sample::start",
            "codel-end Sample::start -> start",
            "codel-start Sample::start",
            "violation",
        ],
        loop_start: Some(11),
        claim: Claim::Starvation {
            waiter: "Calibrate",
            blocker: "Sample",
        },
    });
}

#[test]
fn starvation_of_a_service_delayed_by_an_auto_service() {
    verify(&Expected {
        fixture: "dead-service.delayed-by-auto.gen",
        code: Code::Starvation,
        message: "`Update` can wait forever for `Heartbeat`, which may never end",
        line: 24,
        help: None,
        trace: &[
            "component-start",
            "start Heartbeat::start",
            "request Update",
            "acknowledge Update",
            "codel-start Heartbeat::start",
            "codel-end Heartbeat::start -> beat",
            "codel-start Heartbeat::beat",
            "codel-end Heartbeat::beat -> beat",
            "violation",
        ],
        loop_start: Some(6),
        claim: Claim::Starvation {
            waiter: "Update",
            blocker: "Heartbeat",
        },
    });
}

// ------------------------------------------------------------ dead-service

/// Every request is rejected with `NOT_INITIALIZED`; the rejection step
/// gives that reason in `outcome`, as the trace format says.
#[test]
fn dead_services_behind_an_init_service_that_never_succeeds() {
    for (service, line) in [("Move", 25), ("GetPosition", 32)] {
        let message = format!("service `{service}` can never start");
        let request = format!("request {service}");
        let reject = format!("reject {service} -> NOT_INITIALIZED");
        verify(&Expected {
            fixture: "dead-service.init-never-succeeds.gen",
            code: Code::DeadService,
            message: &message,
            line,
            help: Some("NOT_INITIALIZED, because `Connect` can never complete successfully"),
            trace: &["component-start", &request, &reject, "violation"],
            loop_start: None,
            claim: Claim::DeadService(service),
        });
    }
}

#[test]
fn dead_service_forbidden_by_an_auto_service() {
    verify(&Expected {
        fixture: "dead-service.forbidden-by-auto.gen",
        code: Code::DeadService,
        message: "service `Calibrate` can never start",
        line: 24,
        help: Some("FORBIDDEN by `Monitor`, which runs forever"),
        trace: &[
            "component-start",
            "start Monitor::start",
            "request Calibrate",
            "reject Calibrate -> FORBIDDEN",
            "violation",
        ],
        loop_start: None,
        claim: Claim::DeadService("Calibrate"),
    });
}

#[test]
fn dead_service_delayed_by_an_auto_service() {
    verify(&Expected {
        fixture: "dead-service.delayed-by-auto.gen",
        code: Code::DeadService,
        message: "service `Update` can never start",
        line: 24,
        help: Some("`Update` is acknowledged but never starts: it is always delayed or waiting"),
        trace: &[
            "component-start",
            "start Heartbeat::start",
            "request Update",
            "acknowledge Update",
            "violation",
        ],
        loop_start: None,
        claim: Claim::DeadService("Update"),
    });
}

// ----------------------------------------------------- unbounded-interrupt

/// The second `Move` request interrupts the first while `start` runs; the
/// first then loops in `brake` forever.
const SELF_STOP_INTO_BRAKE: &[&str] = &[
    "component-start",
    "request Move",
    "acknowledge Move",
    "start Move::start",
    "codel-start Move::start",
    "request Move",
    "interrupt Move::start",
    "acknowledge Move",
    "codel-end Move::start",
    "codel-start Move::brake",
    "codel-end Move::brake -> brake",
    "violation",
];

#[test]
fn unbounded_interrupt_looping_inter_codel() {
    verify(&Expected {
        fixture: "unbounded-interrupt.looping-inter-codel.gen",
        code: Code::UnboundedInterrupt,
        message: "`Move` may never end once interrupted: its inter codels can loop forever",
        line: 16,
        help: Some("give the inter codels a way to `end` (or a report): cleanup must terminate"),
        trace: SELF_STOP_INTO_BRAKE,
        loop_start: Some(9),
        claim: Claim::UnboundedInterrupt("Move"),
    });
}

#[test]
fn unbounded_interrupt_even_when_the_loop_has_an_exit() {
    verify(&Expected {
        fixture: "unbounded-interrupt.loop-with-exit.gen",
        code: Code::UnboundedInterrupt,
        message: "`Move` may never end once interrupted: its inter codels can loop forever",
        line: 17,
        help: None,
        trace: SELF_STOP_INTO_BRAKE,
        loop_start: Some(9),
        claim: Claim::UnboundedInterrupt("Move"),
    });
}

#[test]
fn unbounded_interrupt_after_the_watchdog() {
    verify(&Expected {
        fixture: "unbounded-interrupt.watchdog-cleanup-loop.gen",
        code: Code::UnboundedInterrupt,
        message: "`Home` may never end once interrupted: its inter codels can loop forever",
        line: 13,
        help: None,
        trace: &[
            "component-start",
            "wake-up",
            "request Home",
            "acknowledge Home",
            "start Home::start",
            "wake-up",
            "codel-start Home::start",
            "codel-end Home::start -> seek",
            "wake-up",
            "codel-start Home::seek",
            "codel-end Home::seek -> seek",
            "wake-up",
            "codel-start Home::seek",
            "codel-end Home::seek -> seek",
            "watchdog Home::seek",
            "wake-up",
            "codel-start Home::retract",
            "codel-end Home::retract -> park",
            "wake-up",
            "codel-start Home::park",
            "codel-end Home::park -> retract",
            "violation",
        ],
        loop_start: Some(15),
        claim: Claim::UnboundedInterrupt("Home"),
    });
}

// ------------------------------------------------- unreachable-codel (dynamic)

/// `unreachable-codel` for a codel the codel graph reaches (so the static
/// part is silent) but no execution runs; it carries no trace.
fn assert_never_reached(fixture: &str, service: &str, codel: &str, line: usize) {
    let path = common::invalid(fixture);
    let result = common::check(&path);
    let report = common::render(&path, &result);
    let found: Vec<&Diagnostic> = result
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::UnreachableCodel)
        .collect();
    assert_eq!(found.len(), 1, "{report}");
    assert_eq!(
        found[0].message,
        format!("inter codel `{codel}` of service `{service}` is never reached in any execution")
    );
    assert_eq!(common::primary_line(&result, found[0]), line, "{report}");
    assert!(found[0].trace.is_none());
    let statically = genom_check::check_file(
        &common::relative(&path),
        &FsLoader,
        &CheckOptions::new().behaviour(false),
    )
    .expect("fixture is readable");
    assert!(
        !statically
            .diagnostics
            .iter()
            .any(|d| d.code == Code::UnreachableCodel),
        "the codel graph reaches `{codel}`: only exploration finds it unreachable"
    );
}

#[test]
fn unreachable_inter_codel_whose_only_interrupter_is_forbidden() {
    assert_never_reached(
        "unreachable-codel.inter-only-when-forbidden.gen",
        "Scan",
        "abortScan",
        24,
    );
}

#[test]
fn unreachable_inter_codel_whose_interrupter_is_locked_out() {
    assert_never_reached(
        "unreachable-codel.stopper-locked-out.gen",
        "Home",
        "restoreGoal",
        20,
    );
}

#[test]
fn unreachable_cleanup_of_an_auto_service_nothing_stops() {
    let path = common::invalid("dead-service.delayed-by-auto.gen");
    let result = common::check(&path);
    let d: Vec<&Diagnostic> = result
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::UnreachableCodel)
        .collect();
    assert_eq!(d.len(), 1);
    assert_eq!(
        d[0].message,
        "inter codel `close` of service `Heartbeat` is never reached in any execution"
    );
    assert_eq!(common::primary_line(&result, d[0]), 21);
}
