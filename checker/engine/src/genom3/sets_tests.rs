//! The GenoM3 engine explored by the kernel's symbolic sets against the
//! explicit explorer: the same states part by part, the same facts, and
//! livelock traces as short, replayed by the independent oracle.

use genom_model::component::Component;

use super::analysis::{G3Analysis, analyse_machine_by, analyse_machine_with};
use super::machine::Machine;
use crate::kernel::explore::Limits;
use crate::kernel::method::Method;

fn generated(seed: u64) -> Component {
    let mut cfg = genom_generate::Genom3Config::small(seed);
    cfg.timed = false;
    crate::testing::load_genom3(&genom_generate::generate_genom3(&cfg).r#gen)
}

fn limits(max_states: usize) -> Limits {
    Limits {
        max_states,
        ..Limits::default()
    }
}

/// Every livelock trace of `a` replays in the independent oracle.
fn replays(c: &Component, a: &G3Analysis, seed: u64) {
    for l in &a.livelocks {
        if let Err(e) = genom_oracles::replay::genom3::replay_genom3(c, &l.trace) {
            panic!("seed {seed}: {e}\n{:#?}", l.trace);
        }
    }
}

/// The facts two analyses read, and the livelocks' cycles and trace
/// lengths (both breadth-first: as short; the states may differ).
fn same_facts(sets: &G3Analysis, explicit: &G3Analysis, seed: u64) {
    assert_eq!(sets.started, explicit.started, "seed {seed}");
    assert_eq!(sets.completed, explicit.completed, "seed {seed}");
    assert_eq!(sets.reached, explicit.reached, "seed {seed}");
    assert_eq!(sets.boot.len(), explicit.boot.len(), "seed {seed}");
    let cycles = |a: &G3Analysis| -> Vec<String> {
        a.livelocks
            .iter()
            .map(|l| format!("{:?} {}", l.cycle, l.trace.steps.len()))
            .collect()
    };
    assert_eq!(cycles(sets), cycles(explicit), "seed {seed}");
}

/// Compares the symbolic sets with the explicit explorer on `c`: the
/// number of livelocks compared, `None` when the explicit exploration
/// does not finish.
fn compare(c: &Component, seed: u64) -> Option<usize> {
    let m = Machine::new(c, 1).expect("GenoM3");
    let explicit = analyse_machine_with(&m, limits(200_000), false);
    if explicit.stopped.is_some() {
        return None;
    }
    let sets = analyse_machine_by(&m, limits(200_000), false, Method::Symbolic);
    assert!(sets.stopped.is_none(), "seed {seed}");
    assert!(sets.parts.iter().all(|p| p.symbolic && p.complete));
    let states = |a: &G3Analysis| a.parts.iter().map(|p| p.states).collect::<Vec<_>>();
    assert_eq!(states(&sets), states(&explicit), "seed {seed}");
    same_facts(&sets, &explicit, seed);
    replays(c, &sets, seed);
    // With the early stop too.
    let early = analyse_machine_by(&m, limits(200_000), true, Method::Symbolic);
    same_facts(&early, &explicit, seed);
    replays(c, &early, seed);
    Some(sets.livelocks.len())
}

#[test]
fn the_symbolic_sets_reach_the_explicit_states_and_facts() {
    let compared = (0..60)
        .filter_map(|seed| compare(&generated(seed), seed))
        .count();
    assert!(compared >= 40, "{compared} components compared");
}

#[test]
fn the_symbolic_sets_find_the_semantics_fixtures_livelocks() {
    let dir = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/fixtures/genom3/semantics"
    );
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "gen"))
        .collect();
    files.sort();
    let (mut compared, mut livelocks) = (0, 0);
    for (k, f) in files.iter().enumerate() {
        let c = crate::testing::load_genom3(&std::fs::read_to_string(f).unwrap());
        if let Some(n) = compare(&c, k as u64) {
            compared += 1;
            livelocks += n;
        }
    }
    assert!(compared >= 10, "{compared} fixtures compared");
    assert!(livelocks >= 5, "{livelocks} livelock traces compared");
}

#[test]
fn auto_explores_symbolically_a_part_the_explicit_store_cannot_hold() {
    let mut fell_back = 0;
    for seed in 0..30 {
        let c = generated(seed);
        let m = Machine::new(&c, 1).expect("GenoM3");
        let whole = analyse_machine_with(&m, limits(200_000), true);
        let Some(largest) = whole.parts.iter().map(|p| p.states).max() else {
            continue;
        };
        if whole.stopped.is_some() || largest < 50 {
            continue;
        }
        // A state limit below the largest part: the explicit explorer
        // alone stops there and says so.
        let cramped = limits(largest as usize / 2);
        let explicit = analyse_machine_by(&m, cramped, true, Method::Explicit);
        assert!(explicit.stopped.is_some(), "seed {seed}");
        // `auto` finishes it with the sets, with the same facts.
        let auto = analyse_machine_by(&m, cramped, true, Method::Auto);
        assert!(auto.stopped.is_none(), "seed {seed}");
        assert!(auto.parts.iter().any(|p| p.symbolic), "seed {seed}");
        // Each part the sets finished follows the record of the explicit
        // attempt they supersede; the states of both count.
        for (k, p) in auto.parts.iter().enumerate() {
            assert_eq!(p.superseded, !p.complete && !p.symbolic, "seed {seed}");
            if p.superseded {
                let next = &auto.parts[k + 1];
                assert!(next.symbolic && next.complete && next.services == p.services);
            }
        }
        assert_eq!(
            auto.states,
            auto.parts.iter().map(|p| p.states).sum::<u64>()
        );
        same_facts(&auto, &whole, seed);
        replays(&c, &auto, seed);
        fell_back += 1;
    }
    assert!(fell_back >= 10, "{fell_back} components fell back");
}

#[test]
fn auto_explores_symbolically_a_part_past_the_memory_limit() {
    // The same fallback when the explicit store outgrows `--max-memory`
    // (here its own bytes: tests have no counting allocator).
    let mut fell_back = 0;
    for seed in 0..30 {
        let c = generated(seed);
        let m = Machine::new(&c, 1).expect("GenoM3");
        let whole = analyse_machine_with(&m, limits(200_000), true);
        if whole.stopped.is_some() || whole.states < 200 {
            continue;
        }
        let cramped = Limits {
            max_bytes: 1024,
            ..limits(200_000)
        };
        let explicit = analyse_machine_by(&m, cramped, true, Method::Explicit);
        if explicit.stopped != Some(crate::kernel::Stop::Memory) {
            continue;
        }
        let auto = analyse_machine_by(&m, cramped, true, Method::Auto);
        assert!(auto.stopped.is_none(), "seed {seed}");
        assert!(auto.parts.iter().any(|p| p.superseded), "seed {seed}");
        same_facts(&auto, &whole, seed);
        replays(&c, &auto, seed);
        fell_back += 1;
    }
    assert!(fell_back >= 5, "{fell_back} components fell back");
}
