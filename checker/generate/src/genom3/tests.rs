//! Unit tests of the GenoM3 generator on its plans and texts (the whole
//! check of generated components is in the workspace's
//! `tests/cli/genom3_generate.rs`).

use super::plan::Plan;
use super::*;

fn sample(seed: u64) -> Genom3Component {
    generate_genom3(&Genom3Config::small(seed))
}

#[test]
fn generation_is_deterministic() {
    for seed in [0, 1, 42, u64::MAX] {
        assert_eq!(sample(seed), sample(seed));
    }
    assert_ne!(sample(1).r#gen, sample(2).r#gen);
}

/// Every unpaused yield of every machine goes to a later state (or
/// `ether`): the unpaused graph has no cycle.
fn unpaused_forward(plan: &Plan) -> bool {
    let machines = plan
        .tasks
        .iter()
        .filter_map(|t| t.fsm.as_ref())
        .chain(plan.services.iter().filter_map(|s| s.fsm.as_ref()));
    machines.flat_map(|m| &m.codels).all(|c| {
        c.yields
            .iter()
            .all(|y| y.pause || y.to.is_none_or(|j| c.states.iter().all(|&s| j > s)))
    })
}

#[test]
fn without_unpaused_cycles_every_back_yield_is_paused() {
    for seed in 0..200 {
        let cfg = Genom3Config::small(seed);
        assert!(unpaused_forward(&build::plan(&cfg)), "seed {seed}");
    }
    let cycles = (0..200).any(|seed| {
        let cfg = Genom3Config {
            unpaused_cycles: true,
            states: 3,
            ..Genom3Config::small(seed)
        };
        !unpaused_forward(&build::plan(&cfg))
    });
    assert!(cycles, "unpaused_cycles never gave an unpaused back yield");
}

#[test]
fn density_zero_gives_no_relations() {
    for seed in 0..50 {
        let cfg = Genom3Config {
            density: 0.0,
            ..Genom3Config::small(seed)
        };
        let text = generate_genom3(&cfg).r#gen;
        for word in ["interrupts", "after", "before"] {
            assert!(!text.contains(&format!("    {word} ")), "{text}");
        }
    }
    let with = Genom3Config {
        density: 2.0,
        activities: 5,
        ..Genom3Config::new(3)
    };
    assert!(generate_genom3(&with).r#gen.contains("    interrupts "));
}

#[test]
fn timed_components_are_periodic_with_a_wcet_for_every_codel() {
    for seed in 0..50 {
        let cfg = Genom3Config {
            timed: true,
            permanent: true,
            ..Genom3Config::small(seed)
        };
        let plan = build::plan(&cfg);
        assert!(plan.tasks.iter().all(|t| t.period_ms.is_some()));
        let wcet = generate_genom3(&cfg).wcet.expect("a WCET file");
        let lines: Vec<&str> = wcet.lines().filter(|l| !l.starts_with('#')).collect();
        assert_eq!(lines.len(), wcet::entries(&plan).len());
        for (owner, state) in wcet::entries(&plan) {
            let key = format!("{owner}.{state} ");
            assert!(lines.iter().any(|l| l.starts_with(&key)), "{key}\n{wcet}");
        }
    }
    assert!(generate_genom3(&Genom3Config::new(1)).wcet.is_none());
}

#[test]
fn pauses_one_pauses_every_yield_but_ether() {
    let cfg = Genom3Config {
        pauses: 1.0,
        states: 4,
        permanent: true,
        ..Genom3Config::new(5)
    };
    let plan = build::plan(&cfg);
    let all = plan
        .services
        .iter()
        .filter_map(|s| s.fsm.as_ref())
        .flat_map(|m| &m.codels)
        .flat_map(|c| &c.yields)
        .all(|y| y.pause || y.to.is_none());
    assert!(all);
}

#[test]
fn the_requested_structure_is_there() {
    let cfg = Genom3Config {
        tasks: 3,
        activities: 5,
        functions: 2,
        attributes: 2,
        asyncs: true,
        ..Genom3Config::new(9)
    };
    let text = generate_genom3(&cfg).r#gen;
    let count = |w: &str| text.lines().filter(|l| l.starts_with(w)).count();
    assert_eq!(count("  task "), 3);
    assert_eq!(count("  activity "), 5);
    assert_eq!(count("  function "), 2);
    assert_eq!(count("  attribute "), 2);
    assert!(!text.contains("#include"));
}

/// The front-end loads generated components with no error diagnostic.
#[test]
fn the_genom3_front_end_loads_them() {
    use genom3_frontend::{Genom3Options, load_text};
    use std::path::Path;
    for seed in 0..100 {
        let c = sample(seed);
        let mut out = load_text(
            Path::new("gen.gen"),
            c.r#gen.clone(),
            &Genom3Options::default(),
        )
        .expect("loads");
        if let Some(w) = &c.wcet {
            genom3_frontend::add_wcet_file(&mut out, Path::new("gen.wcet"), w.clone());
        }
        let errors: Vec<String> = out
            .diagnostics
            .iter()
            .filter(|d| d.severity >= genom_model::Severity::Warning)
            .map(|d| format!("{:?} {}", d.code, d.message))
            .collect();
        assert!(errors.is_empty(), "seed {seed}: {errors:#?}\n{}", c.r#gen);
        assert!(out.component.is_some());
    }
}
