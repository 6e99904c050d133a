//! Figures of the symbolic engine on one generated component: per cluster
//! of more than one service, BDD variables, steps, reachable states, BDD
//! nodes, breadth-first depth, time, and the verdicts found (with traces
//! when `--traces` is given). Run in release:
//!
//! `cargo run --release -p genom-engine --example symbolic_figures -- SEED SERVICES CODELS THREADS DENSITY [--chained] [--traces] [--explicit] [--no-symbolic] [--seconds N]`
//!
//! (`--init --autos 1` as in `genom-check generate`); `--explicit` also
//! counts the cluster's states with the explicit explorer, no reduction.
#![allow(clippy::print_stdout, clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::time::{Duration, Instant};

use genom_engine::dialect::analysis::clusters;
use genom_engine::dialect::system::System;
use genom_engine::kernel::explore::{Limits, explore};
use genom_engine::symbolic::{Strategy, Symbolic, SymbolicLimits};
use genom_generate::{GeneratorConfig, generate};
use genom_model::behaviour::Behaviour;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let num = |k: usize| {
        args.get(k)
            .and_then(|a| a.parse::<f64>().ok())
            .expect("5 numbers")
    };
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let cfg = GeneratorConfig {
        codels_per_service: num(2) as usize,
        threads: num(3) as usize,
        rule_density: num(4),
        init: true,
        autos: 1,
        ..GeneratorConfig::new(num(0) as u64, num(1) as usize)
    };
    let traces = args.iter().any(|a| a == "--traces");
    let explicit = args.iter().any(|a| a == "--explicit");
    let symbolic = !args.iter().any(|a| a == "--no-symbolic");
    let seconds = args
        .iter()
        .position(|a| a == "--seconds")
        .and_then(|k| args.get(k + 1)?.parse().ok())
        .unwrap_or(600);
    let text = generate(&cfg);
    let lowered = gen_frontend::lower(
        Path::new("gen.gen"),
        text,
        &gen_frontend::MemoryLoader::new(),
    );
    let c = lowered.model.expect("a component");
    let b = Behaviour::new(&c);
    for cluster in clusters(&c).into_iter().filter(|k| k.len() > 1) {
        let sys = System::new(&c, &b, &cluster, false);
        if symbolic {
            run_symbolic(&sys, &args, seconds, traces);
        }
        if explicit {
            let t = Instant::now();
            let e = explore(&sys, Limits::default(), |_, _| {});
            println!(
                "  explicit: {} states in {:.2} s, stopped {:?}",
                e.store.len(),
                t.elapsed().as_secs_f64(),
                e.stopped
            );
        }
    }
}

fn run_symbolic(sys: &System<'_>, args: &[String], seconds: u64, traces: bool) {
    {
        let cluster: Vec<_> = sys.services().collect();
        let sym = Symbolic::new(sys).expect("a whole cluster");
        let limits = SymbolicLimits {
            deadline: Some(Instant::now() + Duration::from_secs(seconds)),
            strategy: if args.iter().any(|a| a == "--chained") {
                Strategy::Chained
            } else {
                Strategy::Breadth
            },
            ..SymbolicLimits::default()
        };
        let reach = sym.reach(limits);
        println!(
            "cluster of {} services: {} variables, {} steps; {} states, {} nodes (peak {}), depth {}, {:.2} s, stopped {:?}",
            cluster.len(),
            sym.variables(),
            sym.steps(),
            reach.states(),
            reach.nodes(),
            reach.peak_nodes,
            reach.depth(),
            reach.elapsed.as_secs_f64(),
            reach.stopped
        );
        let t = Instant::now();
        let v = sym.verdicts(&reach, traces);
        println!(
            "  verdicts in {:.2} s: {} codels reached, {} services started, {} pending, {} unbounded, {} starvations, {} deadlocks (trace lengths {:?})",
            t.elapsed().as_secs_f64(),
            v.reached.len(),
            v.started.len(),
            v.pending.len(),
            v.unbounded.len(),
            v.starvations.len(),
            v.deadlocks.len(),
            v.deadlocks.iter().map(|d| d.path.len()).collect::<Vec<_>>()
        );
    }
}
