//! Figures of the untimed GenoM3 engine on one generated component, the
//! explicit explorer beside the kernel's symbolic sets, both without the
//! early stop (a whole exploration of every part): per method, states,
//! transitions, time, the process's peak heap growth and, for the sets,
//! the reached set's peak BDD nodes. Run in release:
//!
//! `cargo run --release -p genom-engine --example genom3_sets -- SEED TASKS ACTIVITIES ATTRIBUTES [--max-instances N] [--only explicit|sets] [--whole]`
//!
//! `--only` runs one method (for its peak memory, read with
//! `/usr/bin/time -v`); `--whole` also explores the whole machine, not
//! part by part, with the sets.
//!
//! (`functions 2`, `permanent`, untimed, as the bench's `gen-7x10`:
//! `7 10 5`).
#![allow(clippy::print_stdout, clippy::unwrap_used, clippy::expect_used)]

use std::time::Instant;

use genom_engine::genom3::{Machine, analyse_machine_by};
use genom_engine::kernel::explore::Found;
use genom_engine::kernel::explore::Limits;
use genom_engine::kernel::method::Method;
use genom_engine::kernel::sets::{SetLimits, explore_sets_until};
use genom_generate::{Genom3Config, generate_genom3};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let num = |k: usize| {
        args.get(k)
            .and_then(|a| a.parse::<usize>().ok())
            .expect("4 numbers")
    };
    let instances = args
        .iter()
        .position(|a| a == "--max-instances")
        .and_then(|k| args.get(k + 1)?.parse().ok())
        .unwrap_or(1);
    let cfg = Genom3Config {
        tasks: num(1),
        activities: num(2),
        attributes: num(3),
        functions: 2,
        permanent: true,
        timed: false,
        ..Genom3Config::new(num(0) as u64)
    };
    let g = generate_genom3(&cfg);
    let c = genom3_frontend::load_clean(&g.r#gen, None).expect("loads");
    let m = Machine::new(&c, instances).expect("GenoM3");
    let limits = Limits {
        max_states: usize::MAX,
        ..Limits::default()
    };
    let only = args
        .iter()
        .position(|a| a == "--only")
        .and_then(|k| args.get(k + 1));
    for (name, method) in [("explicit", Method::Explicit), ("sets", Method::Symbolic)] {
        if only.is_some_and(|o| o != name) {
            continue;
        }
        let started = Instant::now();
        let a = analyse_machine_by(&m, limits, false, method);
        println!(
            "{name:>8}: {} states, {} transitions, {} parts, {:.2} s, complete {}",
            a.states,
            a.transitions,
            a.parts.len(),
            started.elapsed().as_secs_f64(),
            a.stopped.is_none(),
        );
    }
    if !args.iter().any(|a| a == "--whole") {
        return;
    }
    // The whole machine's sets (no parts).
    let engine = genom_engine::genom3::steps::Engine::new(m.clone());
    let started = Instant::now();
    let s = explore_sets_until(&engine, SetLimits::default(), |_, _| Found::Open);
    println!(
        "   whole: {} states in {} layers, {} bits, peak {} BDD nodes, {:.2} s",
        s.states,
        s.depth(),
        s.bits(),
        s.peak_nodes,
        started.elapsed().as_secs_f64()
    );
}
