//! `genom-check export FORMAT FILE [-o PATH]`: verifies the component, then
//! writes the model in the chosen format. A component with errors, or whose
//! verification is incomplete, is refused (exit 1, with the diagnostics)
//! unless `--allow-unverified`, which marks the export as unverified.

use std::path::{Path, PathBuf};

use genom_checker::{CheckOptions, CheckResult};
use genom_export::{ExportInput, Format, Verification};
use genom_model::render::{FileReport, human};
use genom_model::{Code, Counts, Severity};
use genom_parser::FsLoader;

use super::{EXIT_ERRORS, EXIT_OK, EXIT_USAGE};
use crate::cli::{ExportArgs, ExportFormat, OutputArgs};
use crate::terminal;

/// Runs the export.
pub fn run(args: &ExportArgs, output: &OutputArgs) -> u8 {
    let shown = args.file.to_string_lossy().replace('\\', "/");
    let options = CheckOptions::new()
        .max_states(args.max_states)
        .timeout(args.timeout);
    let result = match genom_checker::check_file(&args.file, &FsLoader, &options) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: cannot read `{shown}`: {e}");
            return EXIT_USAGE;
        }
    };
    let verification = verification(&result);
    let Some(component) = &result.component else {
        print_report(&shown, &result, output);
        eprintln!("error: `{shown}` has no component to export");
        return EXIT_ERRORS;
    };
    if !verification.verified && !args.allow_unverified {
        print_report(&shown, &result, output);
        eprintln!(
            "error: refusing to export `{shown}`: verification has errors or is incomplete (use --allow-unverified to export anyway)"
        );
        return EXIT_ERRORS;
    }
    let input = ExportInput {
        component,
        sources: &result.sources,
        verification: &verification,
    };
    match genom_export::export(format(args.target), &input) {
        Ok(exported) => write(args, format(args.target), &exported),
        Err(e) => {
            eprintln!("error: {e}");
            EXIT_ERRORS
        }
    }
}

fn format(f: ExportFormat) -> Format {
    match f {
        ExportFormat::Uppaal => Format::Uppaal,
        ExportFormat::Fiacre => Format::Fiacre,
        ExportFormat::Tchecker => Format::Tchecker,
        ExportFormat::Pnml => Format::Pnml,
        ExportFormat::Tina => Format::Tina,
        ExportFormat::Config => Format::Config,
        ExportFormat::Dot => Format::Dot,
        ExportFormat::Svg => Format::Svg,
        ExportFormat::Promela => Format::Promela,
    }
}

/// What the check established.
fn verification(result: &CheckResult) -> Verification {
    let counts = Counts::of(&result.diagnostics);
    let stats = result.statistics.as_ref();
    let complete = stats.is_some_and(|s| s.complete);
    let verified = counts.errors == 0 && complete && result.component.is_some();
    let incomplete = result
        .diagnostics
        .iter()
        .any(|d| d.code == Code::Incomplete);
    let properties = if verified && !incomplete {
        proven(result)
    } else {
        Vec::new()
    };
    Verification {
        verified,
        counts,
        states: stats.map_or(0, |s| s.states),
        transitions: stats.map_or(0, |s| s.transitions),
        complete,
        properties,
        tool_version: env!("CARGO_PKG_VERSION").to_owned(),
    }
}

/// The properties a clean, complete check proves.
fn proven(result: &CheckResult) -> Vec<String> {
    let mut out: Vec<String> = [
        "static-semantics",
        "deadlock-freedom",
        "starvation-freedom",
        "no-dead-service",
        "no-unbounded-interrupt",
    ]
    .iter()
    .map(|s| (*s).to_owned())
    .collect();
    let warned = |code: Code| {
        result
            .diagnostics
            .iter()
            .any(|d| d.code == code && d.severity >= Severity::Warning)
    };
    if !warned(Code::UnreachableCodel) {
        out.push("codel-reachability".to_owned());
    }
    let timed = result.component.as_ref().is_some_and(|c| {
        c.codels.values().any(|k| k.wcet.is_some())
            || c.services.values().any(|s| s.max_time.is_some())
    });
    if timed {
        out.push("no-thread-overrun".to_owned());
        out.push("max-time".to_owned());
    }
    out
}

fn print_report(shown: &str, result: &CheckResult, output: &OutputArgs) {
    let report = FileReport {
        path: shown,
        sources: &result.sources,
        diagnostics: &result.diagnostics,
        statistics: result.statistics.as_ref(),
    };
    let options = human::HumanOptions {
        color: terminal::use_color(output.color),
        width: terminal::width(),
    };
    for d in report
        .diagnostics
        .iter()
        .filter(|d| d.severity >= Severity::Warning)
    {
        terminal::emit(&human::render_diagnostic(report.sources, d, options));
    }
    terminal::emit(&(human::render_summary(shown, report.counts()) + "\n"));
}

/// Writes the main output (stdout without `-o`) and companion files.
fn write(args: &ExportArgs, format: Format, exported: &genom_export::Exported) -> u8 {
    let Some(path) = &args.output else {
        terminal::emit(&exported.main);
        return EXIT_OK;
    };
    if let Err(e) = std::fs::write(path, &exported.main) {
        eprintln!("error: cannot write `{}`: {e}", path.display());
        return EXIT_USAGE;
    }
    for (suffix, text) in &exported.extra {
        let companion = companion(path, suffix);
        if let Err(e) = std::fs::write(&companion, text) {
            eprintln!("error: cannot write `{}`: {e}", companion.display());
            return EXIT_USAGE;
        }
    }
    let _ = format;
    EXIT_OK
}

/// `model.xml` + `.q` → `model.q`.
fn companion(path: &Path, suffix: &str) -> PathBuf {
    path.with_extension(suffix.trim_start_matches('.'))
}
