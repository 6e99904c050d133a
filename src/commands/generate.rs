//! `genom-check generate --seed N --services K ...` (hidden): prints a
//! random valid component, for benchmarks and tests; with `--dialect
//! genom3`, a GenoM3 component (and, with `--timed --wcet-out FILE`, its
//! WCET side file).

use genom_generate::{GeneratorConfig, Genom3Config, generate, generate_genom3};

use super::{EXIT_OK, EXIT_USAGE};
use crate::cli::{DialectArg, GenerateArgs};

/// Prints the generated component.
pub fn run(args: &GenerateArgs) -> u8 {
    let probabilities = [
        ("--density", args.density),
        ("--setters", args.setters),
        ("--loops", args.loops),
        ("--pauses", args.pauses),
        ("--load", args.load),
    ];
    for (name, value) in probabilities {
        let limit = if matches!(name, "--density" | "--load") {
            f64::INFINITY
        } else {
            1.0
        };
        if !(0.0..=limit).contains(&value) {
            eprintln!("error: `{name}` must be between 0 and {limit}, not {value}");
            return EXIT_USAGE;
        }
    }
    match args.dialect {
        DialectArg::Gen => gen_dialect(args),
        DialectArg::Genom3 => genom3_dialect(args),
    }
}

fn size(n: u64) -> usize {
    usize::try_from(n).unwrap_or(usize::MAX)
}

/// LANGUAGE.md: the options of [`GeneratorConfig`].
fn gen_dialect(args: &GenerateArgs) -> u8 {
    let genom3_only = [
        ("--wcet-out", args.wcet_out.is_some()),
        ("--permanent", args.permanent),
        ("--asyncs", args.asyncs),
        ("--unpaused-cycles", args.unpaused_cycles),
    ];
    if let Some((flag, _)) = genom3_only.iter().find(|(_, on)| *on) {
        eprintln!("error: `{flag}` needs `--dialect genom3`");
        return EXIT_USAGE;
    }
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

/// GenoM3: the options of [`Genom3Config`]; the WCET file goes to
/// `--wcet-out`.
fn genom3_dialect(args: &GenerateArgs) -> u8 {
    let gen_only = [
        ("--init", args.init),
        ("--autos", args.autos > 0),
        ("--auto-rules", args.auto_rules),
        ("--setters", args.setters > 0.0),
        ("--self-stops", args.self_stops > 0.0),
    ];
    if let Some((flag, _)) = gen_only.iter().find(|(_, on)| *on) {
        eprintln!(
            "error: `{flag}` is not a GenoM3 option (GenoM3 has no init, auto or setter services; use --density for interrupts)"
        );
        return EXIT_USAGE;
    }
    if args.wcet_out.is_some() && !args.timed {
        eprintln!("error: `--wcet-out` needs `--timed` (only timed components have WCETs)");
        return EXIT_USAGE;
    }
    let config = Genom3Config {
        tasks: size(args.threads),
        activities: size(args.services),
        functions: size(args.functions),
        attributes: size(args.attributes),
        states: size(args.codels),
        density: args.density,
        timed: args.timed,
        permanent: args.permanent,
        asyncs: args.asyncs,
        pauses: args.pauses,
        unpaused_cycles: args.unpaused_cycles,
        load: args.load,
        ..Genom3Config::new(args.seed)
    };
    let component = generate_genom3(&config);
    if let (Some(path), Some(text)) = (&args.wcet_out, &component.wcet) {
        if let Err(e) = std::fs::write(path, text) {
            eprintln!("error: cannot write `{}`: {e}", path.display());
            return EXIT_USAGE;
        }
    }
    crate::terminal::emit(&component.r#gen);
    EXIT_OK
}
