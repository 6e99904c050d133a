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
    args_conflicts_with_subcommands = true,
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

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Check component files (the default).
    #[command(after_help = EXAMPLES)]
    Check(CheckArgs),
    /// Explain a diagnostic code.
    Explain(ExplainArgs),
}

/// Arguments of `check`.
#[derive(Debug, Clone, Args)]
pub struct CheckArgs {
    /// Component description files (`.gen`).
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
}

/// Arguments of `explain`.
#[derive(Debug, Clone, Args)]
pub struct ExplainArgs {
    /// A diagnostic code, such as `deadlock` or `unknown-data`.
    pub code: String,
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
