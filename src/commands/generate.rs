//! `genom-check generate --seed N --services K ...` (hidden): prints a
//! random valid component, for benchmarks and tests.

use genom_generate::{GeneratorConfig, generate};

use super::{EXIT_OK, EXIT_USAGE};
use crate::cli::GenerateArgs;

/// Prints the generated component.
pub fn run(args: &GenerateArgs) -> u8 {
    let probabilities = [
        ("--density", args.density),
        ("--setters", args.setters),
        ("--loops", args.loops),
    ];
    for (name, value) in probabilities {
        let limit = if name == "--density" {
            f64::INFINITY
        } else {
            1.0
        };
        if !(0.0..=limit).contains(&value) {
            eprintln!("error: `{name}` must be between 0 and {limit}, not {value}");
            return EXIT_USAGE;
        }
    }
    let size = |n: u64| usize::try_from(n).unwrap_or(usize::MAX);
    let config = GeneratorConfig {
        services: size(args.services),
        codels_per_service: size(args.codels),
        threads: size(args.threads),
        rule_density: args.density,
        init: args.init,
        autos: size(args.autos),
        timed: args.timed,
        auto_rules: args.auto_rules,
        setters: args.setters,
        loops: args.loops,
        self_stops: args.self_stops,
        ..GeneratorConfig::new(args.seed, size(args.services))
    };
    crate::terminal::emit(&generate(&config));
    EXIT_OK
}
