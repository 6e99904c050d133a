//! Command-line arguments (clap). `genom-check FILE...` is the same as
//! `genom-check check FILE...`.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

const EXAMPLES: &str = "\
Examples:
  genom-check specs/pilot.gen                 check one component
  genom-check specs/*.gen --deny warnings     fail CI on warnings too
  genom-check --format json specs/pilot.gen   machine-readable diagnostics
  genom-check explain deadlock                what a diagnostic code means
  genom-check --static-only -I include --wcet comp.wcet comp.gen
                                              a GenoM3 component, its interfaces
                                              under include/, WCETs from a side file

Exit status: 0 no error, 1 errors (or warnings with --deny warnings),
2 usage or I/O problems.";

/// Verifies GenoM robotics components: static checks, deadlock and
/// reachability analysis, timing verification.
#[derive(Debug, Parser)]
#[command(
    name = "genom-check",
    version,
    about,
    after_help = EXAMPLES,
    subcommand_negates_reqs = true
)]
pub struct Cli {
    /// A subcommand; without one, the files are checked.
    #[command(subcommand)]
    pub command: Option<Command>,

    /// What to check when no subcommand is given.
    #[command(flatten)]
    pub check: CheckArgs,

    /// Output options shared by all subcommands.
    #[command(flatten)]
    pub output: OutputArgs,
}

impl Cli {
    /// The `--max-memory` of the command to run, if it has one.
    pub fn max_memory(&self) -> Option<usize> {
        match &self.command {
            None => Some(self.check.max_memory),
            Some(Command::Check(a)) => Some(a.max_memory),
            Some(Command::Export(a)) => Some(a.max_memory),
            Some(Command::Budget(a)) => Some(a.max_memory),
            Some(Command::Lsp(a)) => Some(a.max_memory),
            Some(
                Command::Explain(_)
                | Command::Generate(_)
                | Command::WcetTemplate(_)
                | Command::Completions(_)
                | Command::Manpage,
            ) => None,
        }
    }
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Check component files (the default).
    #[command(after_help = EXAMPLES)]
    Check(CheckArgs),
    /// Explain a diagnostic code.
    Explain(ExplainArgs),
    /// Export the verified model: uppaal, fiacre, tchecker, pnml, tina, config, dot, svg, promela.
    Export(ExportArgs),
    /// Print a random valid component (for benchmarks and tests).
    #[command(hide = true)]
    Generate(GenerateArgs),
    /// WCET budgets: the largest WCET of each codel, and the largest common scale
    /// factor of all WCETs, that keep the component free of errors (needs the `smt`
    /// feature).
    Budget(BudgetArgs),
    /// Write a WCET file to start from for a GenoM3 component: one line per
    /// codel that can take time, its value `?` (not measured yet) to replace.
    WcetTemplate(WcetTemplateArgs),
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell).
    Completions(CompletionsArgs),
    /// Print the manual page (roff), e.g. `genom-check manpage > genom-check.1`.
    Manpage,
    /// Run a Language Server on standard input and output, for editors
    /// (docs/editors.md).
    Lsp(LspArgs),
}

/// Arguments of `lsp`.
#[derive(Debug, Clone, Args)]
pub struct LspArgs {
    /// How long the full check run on each save may explore, e.g. `10s`
    /// (then `incomplete`; `genom-check.toml`'s timeout wins).
    #[arg(long, value_name = "DURATION", value_parser = parse_duration, default_value = "10s")]
    pub timeout: std::time::Duration,

    /// Bound the server's memory, e.g. `512M`, `4G` (checks past it end
    /// `incomplete`).
    #[arg(long, value_name = "SIZE", value_parser = parse_size, default_value = "4G")]
    pub max_memory: usize,
}

/// Arguments of `wcet-template`.
#[derive(Debug, Clone, Args)]
pub struct WcetTemplateArgs {
    /// The GenoM3 component description file (`.gen`).
    #[arg(value_name = "FILE")]
    pub file: PathBuf,

    /// How the file is read (a `--wcet` file given here is checked, not
    /// used).
    #[command(flatten)]
    pub input: InputArgs,

    /// Write the template to this file (never over an input of the run)
    /// instead of standard output.
    #[arg(short = 'o', long = "output", value_name = "PATH")]
    pub output: Option<PathBuf>,
}

/// Arguments of `completions`.
#[derive(Debug, Clone, Args)]
pub struct CompletionsArgs {
    /// The shell.
    #[arg(value_enum)]
    pub shell: clap_complete::Shell,
}

/// Arguments of `check`.
#[derive(Debug, Clone, Args)]
pub struct CheckArgs {
    /// Component description files (`.gen`); `-` reads standard input.
    #[arg(required_unless_present = "system", value_name = "FILE")]
    pub files: Vec<PathBuf>,

    /// Check a functional layer instead: a system file (TOML) naming
    /// components, their WCET files, their port connections, external
    /// sources and cause-effect chains (docs/functional-layer.md).
    #[arg(long, value_name = "FILE", conflicts_with = "files")]
    pub system: Option<PathBuf>,

    /// With `--system`: a cause-effect chain to bound, `FROM->TO` or
    /// `FROM->TO<=DEADLINE` (`maneuver.desired->rotorcraft.rotor_input<=30ms`);
    /// `FROM` is an out port or an external source, `TO` an in port or a
    /// component (its every in port); `TO` alone takes every source
    /// (repeatable).
    #[arg(long = "chain", value_name = "CHAIN", requires = "system", value_parser = parse_chain)]
    pub chains: Vec<genom_system::description::ChainSpec>,

    /// How the files are read.
    #[command(flatten)]
    pub input: InputArgs,

    /// Stop exploring after this many states (then `incomplete`)
    /// [default: 10000000, or `genom-check.toml`'s].
    #[arg(long, value_name = "N")]
    pub max_states: Option<usize>,

    /// Stop exploring after this long, e.g. `30s`, `500ms`, `2min` (then `incomplete`).
    #[arg(long, value_name = "DURATION", value_parser = parse_duration)]
    pub timeout: Option<std::time::Duration>,

    /// Bound the process's memory, e.g. `512M`, `4G` (then `incomplete`).
    #[arg(long, value_name = "SIZE", value_parser = parse_size, default_value = "8G")]
    pub max_memory: usize,

    /// The configuration file to use instead of the nearest
    /// `genom-check.toml` above each checked file (docs/configuration.md).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,

    /// Run only the static checks (no state-space exploration).
    #[arg(long)]
    pub static_only: bool,

    /// Explore every cluster whole with every interleaving: turn off the
    /// compositional exploration and the partial-order reduction of the untimed
    /// engine (same verdicts; slower; traces may differ).
    #[arg(long)]
    pub no_reduction: bool,

    /// Which engine explores the untimed clusters: `explicit` (states one
    /// by one, with the partial-order reduction), `symbolic` (BDDs), or
    /// `auto`: explicit, then symbolic for a cluster the explicit engine
    /// could not finish within the state or memory limit (docs/limits.md).
    /// GenoM3's untimed parts the same way, the symbolic one there being
    /// the kernel's BDD sets. The statistics say which decided each
    /// cluster or part. Timed explorations always use clock zones.
    #[arg(long, value_enum, default_value_t = EngineArg::Auto)]
    pub engine: EngineArg,

    /// GenoM3: explore up to N live requests of each activity at once (at
    /// most 31, GenoM3's slots per task), plus, for an activity that
    /// interrupts itself, one more request that restarts it while they run.
    /// A timing verdict holds for clients that send at most N requests of an
    /// activity before its replies come (restarts of a self-interrupting
    /// activity included); the untimed verdicts do not depend on N
    /// [default: 1, or `genom-check.toml`'s].
    #[arg(long, value_name = "N", value_parser = parse_instances)]
    pub max_instances: Option<usize>,

    /// A deadline for a service's worst-case response time (from its
    /// acknowledgment to its final reply), e.g. `Move=50ms`; a later worst
    /// case is a `deadline-miss` error with its trace (repeatable).
    #[arg(long = "deadline", value_name = "SERVICE=DURATION", value_parser = parse_deadline)]
    pub deadlines: Vec<(String, u64)>,

    /// Computes and prints every service's worst-case response time (from
    /// acknowledgment to final reply; JSON `response_times`). Costs one more
    /// timed exploration; implied, for those services, by `--deadline`.
    #[arg(long)]
    pub response_times: bool,
}

/// How files are read: their dialect and, for GenoM3, where their
/// includes and WCETs are.
#[derive(Debug, Clone, Args)]
pub struct InputArgs {
    /// The language of the files; default: recognised by their syntax.
    #[arg(long, value_enum, value_name = "DIALECT")]
    pub dialect: Option<DialectArg>,

    /// A folder searched for GenoM3 `#include` files, after the including
    /// file's folder and before `GENOM_INCLUDE_PATH` (repeatable, in order).
    #[arg(short = 'I', long = "include-dir", value_name = "DIR")]
    pub include_dirs: Vec<PathBuf>,

    /// A GenoM3 WCET file: one `OWNER.STATE DURATION` per line, e.g.
    /// `move.start 400us` (see docs/genom3.md).
    #[arg(long, value_name = "FILE")]
    pub wcet: Option<PathBuf>,
}

impl InputArgs {
    /// The library's view of these arguments.
    pub fn inputs(&self) -> genom_check::Inputs {
        genom_check::Inputs {
            dialect: self.dialect.map(|d| match d {
                DialectArg::Gen => genom_model::Dialect::Gen,
                DialectArg::Genom3 => genom_model::Dialect::Genom3,
            }),
            include_dirs: self.include_dirs.clone(),
            wcet_file: self.wcet.clone(),
        }
    }
}

/// The engines `--engine` names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum EngineArg {
    /// Explicit, then symbolic for a cluster the explicit engine could not finish.
    Auto,
    /// The explicit explorer only.
    Explicit,
    /// The symbolic (BDD) engine.
    Symbolic,
}

impl From<EngineArg> for genom_checker::Engine {
    fn from(e: EngineArg) -> Self {
        match e {
            EngineArg::Auto => genom_checker::Engine::Auto,
            EngineArg::Explicit => genom_checker::Engine::Explicit,
            EngineArg::Symbolic => genom_checker::Engine::Symbolic,
        }
    }
}

/// The languages `--dialect` names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DialectArg {
    /// The dialect of LANGUAGE.md.
    Gen,
    /// GenoM3 (LAAS-CNRS).
    Genom3,
}

/// Parses `30s`, `500ms`, `2min`, `1.5s` with the language's duration units.
pub(crate) fn parse_duration(text: &str) -> Result<std::time::Duration, String> {
    let t = text.trim();
    // The language's own literals first (`10ms`, `2min`), then the usual
    // forms (`1h`, `1h 30m`, `90sec`).
    let parsed = gen_frontend::literal::duration_ns(t)
        .ok()
        .and_then(|ns| u64::try_from(ns).ok())
        .map(std::time::Duration::from_nanos)
        .or_else(|| humantime::parse_duration(t).ok())
        .ok_or_else(|| {
            format!("`{text}` is not a duration such as `30s`, `500ms`, `2min` or `1h`")
        })?;
    if parsed.is_zero() {
        return Err(format!("`{text}` must be positive"));
    }
    Ok(parsed)
}

/// Parses `--chain FROM->TO<=DURATION`.
fn parse_chain(text: &str) -> Result<genom_system::description::ChainSpec, String> {
    genom_system::description::parse_chain_arg(text)
}

/// Parses `--deadline SERVICE=DURATION` (the duration as `--timeout`'s,
/// a whole number of nanoseconds, may be 0).
fn parse_deadline(text: &str) -> Result<(String, u64), String> {
    let (name, duration) = text
        .split_once('=')
        .ok_or_else(|| format!("`{text}` is not `SERVICE=DURATION`, e.g. `Move=50ms`"))?;
    let name = name.trim();
    if name.is_empty() {
        return Err(format!("`{text}` names no service"));
    }
    let ns = if duration.trim() == "0" {
        0
    } else {
        u64::try_from(parse_duration(duration)?.as_nanos())
            .ok()
            .filter(|&ns| ns <= genom_model::limits::MAX_DURATION_NS)
            .ok_or_else(|| genom_model::limits::duration_too_long(duration.trim()))?
    };
    Ok((name.to_owned(), ns))
}

/// Parses `--max-instances`: 1 to 31 (GenoM3's slots per task less the
/// permanent activity).
pub(crate) fn parse_instances(text: &str) -> Result<usize, String> {
    let max = genom_checker::genom3::POOL - 1;
    match text.trim().parse::<usize>() {
        Ok(n) if (1..=max).contains(&n) => Ok(n),
        _ => Err(format!(
            "`{text}` is not a number of instances from 1 to {max} (GenoM3 runs at most {max} per task)"
        )),
    }
}

/// Parses `512M`, `4G`, `1.5G`, `100k` (binary multiples), a byte count,
/// or the usual written sizes (`4GB`, `1.5 GiB`, `512MiB`: decimal
/// `KB`/`MB`/`GB`, binary `KiB`/`MiB`/`GiB`).
fn parse_size(text: &str) -> Result<usize, String> {
    let t = text.trim();
    let (digits, factor) = match t.as_bytes().last() {
        Some(b'k' | b'K') => (&t[..t.len() - 1], 1usize << 10),
        Some(b'm' | b'M') => (&t[..t.len() - 1], 1 << 20),
        Some(b'g' | b'G') => (&t[..t.len() - 1], 1 << 30),
        _ => (t, 1),
    };
    digits
        .parse::<usize>()
        .ok()
        .and_then(|n| n.checked_mul(factor))
        .or_else(|| fractional(digits, factor))
        .or_else(|| {
            let written: bytesize::ByteSize = t.parse().ok()?;
            usize::try_from(written.as_u64()).ok()
        })
        .filter(|&n| n > 0)
        .ok_or_else(|| format!("`{text}` is not a size such as `512M`, `4G` or `1.5GB`"))
}

/// Arguments of `export`.
#[derive(Debug, Clone, Args)]
pub struct ExportArgs {
    /// The format.
    #[arg(value_enum, value_name = "FORMAT")]
    pub target: ExportFormat,

    /// The component description file.
    #[arg(value_name = "FILE")]
    pub file: PathBuf,

    /// How the file is read.
    #[command(flatten)]
    pub input: InputArgs,

    /// Write to this file (and companion files next to it) instead of stdout.
    #[arg(short, long, value_name = "PATH")]
    pub output: Option<PathBuf>,

    /// Export even when verification found errors or is incomplete (marked unverified).
    #[arg(long)]
    pub allow_unverified: bool,

    /// Stop exploring after this many states (then `incomplete`).
    #[arg(long, value_name = "N", default_value_t = 10_000_000)]
    pub max_states: usize,

    /// Stop exploring after this long, e.g. `30s` (then `incomplete`).
    #[arg(long, value_name = "DURATION", value_parser = parse_duration)]
    pub timeout: Option<std::time::Duration>,

    /// Bound the process's memory, e.g. `512M`, `4G` (then `incomplete`).
    #[arg(long, value_name = "SIZE", value_parser = parse_size, default_value = "8G")]
    pub max_memory: usize,

    /// Which engine verifies the untimed clusters first, as `check --engine`.
    #[arg(long, value_enum, default_value_t = EngineArg::Auto)]
    pub engine: EngineArg,
}

/// Export formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ExportFormat {
    /// UPPAAL XML model and query file.
    Uppaal,
    /// Fiacre model (frac, TINA).
    Fiacre,
    /// TChecker timed automata.
    Tchecker,
    /// PNML Petri net.
    Pnml,
    /// TINA .net Petri net.
    Tina,
    /// Verified runtime configuration (JSON).
    Config,
    /// Graphviz diagrams.
    Dot,
    /// SVG diagrams.
    Svg,
    /// Promela model of the untimed semantics (SPIN).
    Promela,
}

/// Arguments of `budget` (see docs/timing.md, "WCET budgets").
#[derive(Debug, Clone, Args)]
pub struct BudgetArgs {
    /// The component description file (`.gen`).
    #[arg(value_name = "FILE")]
    pub file: PathBuf,

    /// How the file is read.
    #[command(flatten)]
    pub input: InputArgs,

    /// Only the budget of this codel, as `SERVICE::CODEL` (`SERVICE` alone: its
    /// start codel); repeatable. Default: every codel.
    #[arg(long = "codel", value_name = "SERVICE::CODEL")]
    pub codels: Vec<String>,

    /// Do not compute the common scale factor.
    #[arg(long)]
    pub no_scale: bool,

    /// Largest budget searched, e.g. `1s` (a budget that reaches it is reported unbounded).
    #[arg(long, value_name = "DURATION", value_parser = parse_duration, default_value = "60min")]
    pub cap: std::time::Duration,

    /// Searches run in parallel (default: the number of CPUs).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=256))]
    pub jobs: Option<u64>,

    /// Stop each exploration after this many states (then the budget is incomplete).
    #[arg(long, value_name = "N", default_value_t = 10_000_000)]
    pub max_states: usize,

    /// Stop the whole computation after this long, e.g. `5min` (then incomplete).
    #[arg(long, value_name = "DURATION", value_parser = parse_duration)]
    pub timeout: Option<std::time::Duration>,

    /// Bound the process's memory, e.g. `4G` (then `incomplete`).
    #[arg(long, value_name = "SIZE", value_parser = parse_size, default_value = "8G")]
    pub max_memory: usize,
}

/// Arguments of `explain`.
#[derive(Debug, Clone, Args)]
pub struct ExplainArgs {
    /// A diagnostic code, such as `deadlock` or `unknown-data`.
    pub code: String,

    /// Whose words come first: `genom3` puts the section about GenoM3
    /// components (tasks, activities, `yield`, WCET files) before the
    /// LANGUAGE.md text; `gen` (the default) the other way round.
    #[arg(long, value_enum)]
    pub dialect: Option<DialectArg>,
}

/// Arguments of the hidden `generate` subcommand (see
/// `genom_generate`).
#[derive(Debug, Clone, Args)]
pub struct GenerateArgs {
    /// Seed of the random choices: the same arguments print the same text.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,

    /// Number of services (init, autos and setters included).
    #[arg(long, value_name = "K", default_value_t = 5, value_parser = clap::value_parser!(u64).range(1..=1000))]
    pub services: u64,

    /// Start, exec and inter codels per threaded service.
    #[arg(long, value_name = "C", default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..=100))]
    pub codels: u64,

    /// Number of threads.
    #[arg(long, value_name = "T", default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..=100))]
    pub threads: u64,

    /// Expected stops + delays + forbids references per service.
    #[arg(long, value_name = "D", default_value_t = 1.0)]
    pub density: f64,

    /// Make the first service an `init` service.
    #[arg(long)]
    pub init: bool,

    /// Number of `auto` services.
    #[arg(long, value_name = "A", default_value_t = 0)]
    pub autos: u64,

    /// Thread periods, codel WCETs and service max-times.
    #[arg(long)]
    pub timed: bool,

    /// Let `auto` services list `delays` and `forbids` (may make services dead).
    #[arg(long)]
    pub auto_rules: bool,

    /// Probability that an ordinary service is an attribute setter.
    #[arg(long, value_name = "P", default_value_t = 0.0)]
    pub setters: f64,

    /// Probability of an extra loop edge per codel.
    #[arg(long, value_name = "P", default_value_t = 0.3)]
    pub loops: f64,

    /// Probability that a service also stops itself (on top of --density).
    #[arg(long, value_name = "P", default_value_t = 0.0)]
    pub self_stops: f64,

    /// The dialect to generate: `gen` (LANGUAGE.md, the default) or `genom3`
    /// (then --services counts activities, --threads tasks, --codels the
    /// states of each activity, --density interrupts/after/before per service).
    #[arg(long, value_enum, value_name = "DIALECT", default_value_t = DialectArg::Gen)]
    pub dialect: DialectArg,

    /// GenoM3: number of functions.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u64).range(0..=100))]
    pub functions: u64,

    /// GenoM3: number of attributes.
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u64).range(0..=100))]
    pub attributes: u64,

    /// GenoM3: give some tasks permanent codels.
    #[arg(long)]
    pub permanent: bool,

    /// GenoM3: make some codels `async`.
    #[arg(long)]
    pub asyncs: bool,

    /// GenoM3: probability that a yield to a later state is `pause::`.
    #[arg(long, value_name = "P", default_value_t = 0.5)]
    pub pauses: f64,

    /// GenoM3: allow yields back without `pause::` (livelocks, unpaused loops).
    #[arg(long)]
    pub unpaused_cycles: bool,

    /// GenoM3 with --timed: the sum of the WCETs as a fraction of the shortest
    /// period (at most 0.5 keeps every task in its period; above 1 tasks may overrun).
    #[arg(long, value_name = "L", default_value_t = 0.3)]
    pub load: f64,

    /// GenoM3 with --timed: write the WCET side file there.
    #[arg(long, value_name = "FILE")]
    pub wcet_out: Option<PathBuf>,
}

/// `1.5` × `factor` (a suffix letter given), rounded down.
fn fractional(digits: &str, factor: usize) -> Option<usize> {
    if factor == 1 {
        return None;
    }
    let x: f64 = digits.parse().ok()?;
    #[allow(clippy::cast_precision_loss)] // factors are powers of two up to 2^30
    let bytes = x * factor as f64;
    // Below 2^53 (far above any memory size), the conversion is exact.
    (bytes.is_finite() && (1.0..9.0e15).contains(&bytes)).then(|| {
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // range checked
        let b = bytes as usize;
        b
    })
}

/// Output options.
#[derive(Debug, Clone, Args)]
pub struct OutputArgs {
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Human, global = true)]
    pub format: Format,

    /// Treat warnings as errors for the exit status.
    #[arg(long, value_enum, value_name = "LEVEL", global = true)]
    pub deny: Option<Deny>,

    /// Print only errors and warnings, without advice and summaries.
    #[arg(short, long, global = true)]
    pub quiet: bool,

    /// Show each advice in full, with its source snippet and help (by
    /// default the human report gives each advice one line).
    #[arg(short, long, global = true, conflicts_with = "quiet")]
    pub verbose: bool,

    /// When to use colours (`auto` honours NO_COLOR and non-terminals).
    #[arg(long, value_enum, default_value_t = Color::Auto, global = true)]
    pub color: Color,
}

/// Output formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// Graphical reports with source snippets.
    Human,
    /// One JSON document on stdout (see docs/json-format.md).
    Json,
    /// GitHub Actions workflow commands: annotations on the pull request's
    /// lines (see docs/ci.md).
    Github,
    /// SARIF 2.1.0, for code scanning (see docs/ci.md).
    Sarif,
}

/// What `--deny` can make fatal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Deny {
    /// Warnings make the exit status 1.
    Warnings,
}

/// Colour choice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Color {
    /// Colours on a terminal unless NO_COLOR is set.
    Auto,
    /// Always colour.
    Always,
    /// Never colour.
    Never,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_take_suffix_letters_fractions_and_written_units() {
        assert_eq!(parse_size("4G"), Ok(4 << 30));
        assert_eq!(parse_size("1.5G"), Ok(3 << 29));
        assert_eq!(parse_size("512M"), Ok(512 << 20));
        assert_eq!(parse_size("4GB"), Ok(4_000_000_000));
        assert_eq!(parse_size("1.5 GiB"), Ok(3 << 29));
        assert_eq!(parse_size("100"), Ok(100));
        assert!(parse_size("0").is_err());
        assert!(parse_size("-1G").is_err());
        assert!(parse_size("1.5x").is_err());
    }

    #[test]
    fn durations_take_the_language_literals_and_the_usual_forms() {
        let secs = |s: u64| Ok(std::time::Duration::from_secs(s));
        assert_eq!(parse_duration("30s"), secs(30));
        assert_eq!(parse_duration("2min"), secs(120));
        assert_eq!(parse_duration("1h"), secs(3600));
        assert_eq!(parse_duration("1h 30m"), secs(5400));
        assert_eq!(
            parse_duration("500ms"),
            Ok(std::time::Duration::from_millis(500))
        );
        assert!(parse_duration("0s").is_err());
        assert!(parse_duration("soon").is_err());
    }

    #[test]
    fn instances_are_bounded_by_genom3_slots() {
        assert_eq!(parse_instances("1"), Ok(1));
        assert_eq!(parse_instances("31"), Ok(31));
        for bad in ["0", "32", "many", "-1"] {
            let e = parse_instances(bad).unwrap_err();
            assert!(e.contains("from 1 to 31"), "{e}");
        }
    }
}
