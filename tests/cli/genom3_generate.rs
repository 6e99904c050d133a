//! The GenoM3 generator (`genom_generate::generate_genom3`) through the
//! whole pipeline: generated components load with no error, their checks
//! (untimed, and timed with the generated WCET file) end with behavioural
//! verdicts or `incomplete`, the knobs do what they say, and over the
//! seeds of `Genom3Config::small` both overrunning and clean timed
//! verdicts occur, and some dead services, so that the differential tests
//! have something to compare.

#![allow(clippy::expect_used, clippy::unwrap_used)] // test support code

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Duration;

use genom_check::{CheckOptions, CheckResult, Inputs, check_path};
use genom_generate::{Genom3Component, Genom3Config, generate_genom3};
use genom_model::{Code, Dialect, Severity};

/// The only errors a generated component may get: verdicts of the
/// engines, and `incomplete` when a limit stops them.
const VERDICTS: [Code; 6] = [
    Code::DeadService,
    Code::UnreachableCodel,
    Code::Livelock,
    Code::ThreadOverrun,
    Code::CodelOverrun,
    Code::Incomplete,
];

/// Writes the component (and, when `timed`, its WCET file) into `dir`
/// and checks it with small limits.
fn check(dir: &Path, name: &str, c: &Genom3Component, timed: bool) -> CheckResult {
    let path = dir.join(format!("{name}.gen"));
    std::fs::write(&path, &c.r#gen).unwrap();
    let wcet_file = c.wcet.as_ref().filter(|_| timed).map(|w| {
        let p: PathBuf = dir.join(format!("{name}.wcet"));
        std::fs::write(&p, w).unwrap();
        p
    });
    let inputs = Inputs {
        dialect: Some(Dialect::Genom3),
        wcet_file,
        ..Inputs::default()
    };
    let options = CheckOptions::new()
        .max_states(5_000)
        .timeout(Some(Duration::from_secs(2)));
    check_path(&path, &inputs, &options).unwrap()
}

/// The errors that are not verdicts, rendered for a failure message.
fn front_end_errors(r: &CheckResult) -> Vec<String> {
    r.diagnostics
        .iter()
        .filter(|d| d.severity == Severity::Error && !VERDICTS.contains(&d.code))
        .map(|d| format!("{:?} {}", d.code, d.message))
        .collect()
}

fn has(r: &CheckResult, code: Code) -> bool {
    r.diagnostics.iter().any(|d| d.code == code)
}

#[test]
fn small_components_of_200_seeds_load_and_check() {
    let dir = tempfile::tempdir().unwrap();
    let mut tally: BTreeMap<&str, usize> = BTreeMap::new();
    for seed in 0..200 {
        let c = generate_genom3(&Genom3Config::small(seed));
        let untimed = check(dir.path(), &format!("s{seed}"), &c, false);
        let errors = front_end_errors(&untimed);
        assert!(errors.is_empty(), "seed {seed}: {errors:#?}\n{}", c.r#gen);
        assert!(untimed.component.is_some() && untimed.statistics.is_some());
        if has(&untimed, Code::DeadService) || has(&untimed, Code::UnreachableCodel) {
            *tally.entry("dead or unreachable").or_default() += 1;
        }
        if c.wcet.is_none() {
            continue;
        }
        let timed = check(dir.path(), &format!("t{seed}"), &c, true);
        let errors = front_end_errors(&timed);
        assert!(
            errors.is_empty(),
            "seed {seed} timed: {errors:#?}\n{}",
            c.r#gen
        );
        assert!(!has(&timed, Code::MissingWcet), "seed {seed}");
        let key = if has(&timed, Code::ThreadOverrun) {
            "thread-overrun"
        } else if has(&timed, Code::Incomplete) {
            "incomplete"
        } else {
            "clean timing"
        };
        *tally.entry(key).or_default() += 1;
    }
    eprintln!("verdicts over 200 seeds: {tally:?}");
    for key in ["dead or unreachable", "thread-overrun", "clean timing"] {
        assert!(tally.get(key).is_some_and(|&n| n > 0), "{tally:?}");
    }
}

/// Timed: every task periodic, every codel (permanent ones included) with
/// a WCET; load 0.3 without `async` codels: no task overruns.
#[test]
fn timed_components_are_periodic_and_fully_timed() {
    let dir = tempfile::tempdir().unwrap();
    for seed in 0..20 {
        let cfg = Genom3Config {
            timed: true,
            permanent: true,
            asyncs: false,
            load: 0.3,
            ..Genom3Config::small(seed)
        };
        let r = check(
            dir.path(),
            &format!("p{seed}"),
            &generate_genom3(&cfg),
            true,
        );
        let c = r.component.as_ref().expect("a component");
        assert!(
            c.threads.values().all(|t| t.period.is_some()),
            "seed {seed}"
        );
        assert!(
            !has(&r, Code::MissingWcet) && !has(&r, Code::BadWcet),
            "seed {seed}"
        );
        let info = c.genom3.as_ref().expect("GenoM3 facts");
        let permanent = info.tasks.iter().flat_map(|t| &t.codels);
        assert!(permanent.clone().all(|k| k.wcet.is_some()), "seed {seed}");
        assert!(
            !has(&r, Code::ThreadOverrun),
            "seed {seed}: overrun at load 0.3"
        );
    }
}

/// Density 0: no generated service interrupts, or waits for, another.
#[test]
fn density_zero_gives_no_interrupts_after_or_before() {
    let dir = tempfile::tempdir().unwrap();
    for seed in 0..20 {
        let cfg = Genom3Config {
            density: 0.0,
            ..Genom3Config::small(seed)
        };
        let r = check(
            dir.path(),
            &format!("d{seed}"),
            &generate_genom3(&cfg),
            false,
        );
        let c = r.component.as_ref().expect("a component");
        for s in c.services.values().filter(|s| generated(&s.name.name)) {
            assert!(s.stops.is_empty(), "seed {seed} {}", s.name.name);
        }
        let info = c.genom3.as_ref().expect("GenoM3 facts");
        for s in &info.services {
            if generated(&c.services[s.service].name.name) {
                assert!(s.after.is_empty() && s.before.is_empty() && !s.interrupts_all);
            }
        }
    }
}

/// A service the generator named (`a0`, `f1`, `attr2`), not a built-in one.
fn generated(name: &str) -> bool {
    let rest = name
        .strip_prefix("attr")
        .or_else(|| name.strip_prefix('a'))
        .or_else(|| name.strip_prefix('f'));
    rest.is_some_and(|r| !r.is_empty() && r.bytes().all(|b| b.is_ascii_digit()))
}

/// The `unpaused_cycles` knob is what gives `livelock` or `unpaused-loop`:
/// off (the default), no seed has one.
#[test]
fn unpaused_cycles_give_livelocks_only_when_asked() {
    let dir = tempfile::tempdir().unwrap();
    let mut found = false;
    for seed in 0..30 {
        let cfg = Genom3Config {
            activities: 2,
            states: 3,
            pauses: 0.0,
            ..Genom3Config::small(seed)
        };
        let r = check(
            dir.path(),
            &format!("l{seed}"),
            &generate_genom3(&cfg),
            false,
        );
        assert!(
            !has(&r, Code::Livelock) && !has(&r, Code::UnpausedLoop),
            "seed {seed}"
        );
        let with = Genom3Config {
            unpaused_cycles: true,
            ..cfg
        };
        let r = check(
            dir.path(),
            &format!("u{seed}"),
            &generate_genom3(&with),
            false,
        );
        found |= has(&r, Code::Livelock) || has(&r, Code::UnpausedLoop);
    }
    assert!(
        found,
        "unpaused_cycles never gave a livelock or unpaused loop"
    );
}
