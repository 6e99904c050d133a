//! The two GenoM3 engines per state: the untimed analysis and the timed
//! exploration (schedulability), and the untimed analysis with the kernel's
//! symbolic sets (`sets`), as states per second and bytes per
//! stored state, on generated GenoM3 components (`genom_generate`) and,
//! when the corpus is next to the repository (`../shared/corpus/genom3`,
//! or `GENOM3_CORPUS`), on real ones with the WCET files of
//! `tests/fixtures/genom3/wcet/`.
//!
//! `cargo bench -p genom-engine --bench genom3 -- --warm-up-time 1 --measurement-time 5`
//!
//! Each case explores at most [`MAX_STATES`] states, so a case past that
//! measures the same amount of work each time (it is then marked
//! incomplete). Before measuring, each case is explored once and its
//! figures printed on stderr: states, transitions, time, states per
//! second, bytes per stored state, complete or not. Criterion's throughput
//! is in states, so its `thrpt` reads as states per second.

#![allow(clippy::print_stderr, clippy::expect_used)]

use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

mod common;
use common::print;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use genom_engine::genom3::timed::analysis::analyse_timing;
use genom_engine::genom3::{Machine, analyse_machine, analyse_machine_by, analyse_machine_with};
use genom_engine::kernel::explore::Limits;
use genom_engine::kernel::method::Method;
use genom_generate::{Genom3Config, generate_genom3};
use genom_model::component::Component;
use genom3_frontend::Genom3Options;

/// The states a case explores at most.
const MAX_STATES: usize = 300_000;

fn limits() -> Limits {
    Limits {
        max_states: MAX_STATES,
        ..Limits::default()
    }
}

/// A generated component: seed, tasks, activities, attributes, timed.
fn generated(
    seed: u64,
    tasks: usize,
    activities: usize,
    attributes: usize,
    timed: bool,
) -> Component {
    let cfg = Genom3Config {
        tasks,
        activities,
        attributes,
        functions: 2,
        permanent: true,
        timed,
        ..Genom3Config::new(seed)
    };
    let g = generate_genom3(&cfg);
    genom3_frontend::load_clean(&g.r#gen, g.wcet.as_deref()).expect("a generated component loads")
}

/// A corpus component with its WCET file (when it has one), when the
/// corpus is here.
fn corpus(name: &str, folder: &str) -> Option<Component> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let corpus = std::env::var_os("GENOM3_CORPUS")
        .map_or_else(|| root.join("../shared/corpus/genom3"), PathBuf::from);
    let file = corpus.join(folder).join(format!("{name}.gen"));
    let wcet = root.join(format!("tests/fixtures/genom3/wcet/{name}.wcet"));
    let options = Genom3Options {
        include_dirs: vec![root.join("tests/fixtures/genom3/include")],
        wcet_file: wcet.exists().then_some(wcet),
        use_env_include_path: false,
        ..Genom3Options::default()
    };
    genom3_frontend::load(&file, &options).ok()?.component
}

/// The untimed analysis: states, transitions, bytes per state, complete.
fn untimed(m: &Machine<'_>) -> (u64, u64, f64, bool) {
    let a = analyse_machine(m, limits());
    (
        a.states,
        a.transitions,
        a.footprint.bytes_per_state,
        a.stopped.is_none(),
    )
}

/// The untimed analysis without the early stop (14.4b): a whole
/// exploration, up to the cap, for the store's bytes per state.
fn exhaustive(m: &Machine<'_>) -> (u64, u64, f64, bool) {
    let a = analyse_machine_with(m, limits(), false);
    (
        a.states,
        a.transitions,
        a.footprint.bytes_per_state,
        a.stopped.is_none(),
    )
}

/// [`exhaustive`] with the kernel's symbolic sets (no state cap: the
/// BDDs store no state one by one; no store, so no bytes per state).
fn sets(m: &Machine<'_>) -> (u64, u64, f64, bool) {
    let a = analyse_machine_by(m, limits(), false, Method::Symbolic);
    (a.states, a.transitions, 0.0, a.stopped.is_none())
}

/// The timed exploration: states, transitions, bytes per state, complete.
fn timed(m: &Machine<'_>) -> (u64, u64, f64, bool) {
    let a = analyse_timing(m, limits()).expect("few tasks");
    (
        a.states,
        a.transitions,
        a.footprint.bytes_per_state,
        a.stopped.is_none(),
    )
}

type Engine = fn(&Machine<'_>) -> (u64, u64, f64, bool);

fn bench(cr: &mut Criterion) {
    let mut cases: Vec<(String, Component, &str, Engine)> = vec![
        (
            "gen-3x4".into(),
            generated(3, 3, 4, 3, false),
            "untimed",
            untimed,
        ),
        (
            "gen-3x4-exhaustive".into(),
            generated(3, 3, 4, 3, false),
            "untimed",
            exhaustive,
        ),
        (
            "gen-3x4-exhaustive".into(),
            generated(3, 3, 4, 3, false),
            "sets",
            sets,
        ),
        (
            "gen-3x4-timed".into(),
            generated(3, 3, 4, 3, true),
            "timed",
            timed,
        ),
        (
            "gen-7x10".into(),
            generated(1, 7, 10, 5, false),
            "untimed",
            untimed,
        ),
        (
            "gen-7x10-exhaustive".into(),
            generated(1, 7, 10, 5, false),
            "untimed",
            exhaustive,
        ),
    ];
    // The corpus components with a WCET file (timed and untimed), and
    // rotorcraft, the largest untimed one.
    let real: [(&str, &str); 7] = [
        ("rotorcraft", "rotorcraft-genom3"),
        ("uavvs", "uavvs-genom3"),
        ("uavatt", "uavatt-genom3"),
        ("uavpos", "uavpos-genom3"),
        ("T265", "T265-genom3"),
        ("nhfc", "nhfc-genom3"),
        ("rmp440", "infuse_rmp440-genom3"),
    ];
    for (name, folder) in real {
        if let Some(c) = corpus(name, folder) {
            let wcets = Machine::new(&c, 1).is_some_and(|m| {
                m.tasks.iter().any(|t| {
                    t.perm
                        .iter()
                        .flat_map(|f| &f.states)
                        .any(|s| s.wcet_ns.is_some())
                })
            });
            cases.push((name.into(), c.clone(), "untimed", untimed));
            if wcets {
                cases.push((format!("{name}-timed"), c, "timed", timed));
            }
        }
    }
    let mut group = cr.benchmark_group("genom3");
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));
    for (id, c, engine, run) in &cases {
        let m = Machine::new(c, 1).expect("a GenoM3 component");
        let started = Instant::now();
        let figures = run(&m);
        let (states, transitions, bytes, done) = figures;
        print(
            &format!("{engine}/{id}"),
            states,
            transitions,
            started.elapsed(),
            bytes,
            done,
        );
        group.throughput(Throughput::Elements(figures.0.max(1)));
        group.bench_with_input(BenchmarkId::new(*engine, id), &m, |bch, m| {
            bch.iter(|| black_box(run(m).0));
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
