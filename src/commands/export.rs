//! `genom-check export FORMAT FILE [-o PATH]`: verifies the component, then
//! writes the model in the chosen format. A component with errors, or whose
//! verification is incomplete, is refused (exit 1, with the diagnostics)
//! unless `--allow-unverified`, which marks the export as unverified.
//! With `-o`, the files are written as [`crate::output`] says: never over
//! an input of the run, all or nothing.

use std::path::PathBuf;

use genom_check::{CheckOptions, CheckResult};
use genom_export::{ExportInput, Format, Verification};
use genom_render::{FileReport, escaped, github, json};

use super::{EXIT_ERRORS, EXIT_OK, EXIT_USAGE};
use crate::cli::{Color, Deny, ExportArgs, ExportFormat, Format as ReportFormat, OutputArgs};
use crate::output::{Input, Plan};
use crate::terminal;

/// Runs the export.
pub fn run(args: &ExportArgs, output: &OutputArgs) -> u8 {
    let shown = genom_check::display(&args.file);
    let options = CheckOptions::new()
        .max_states(args.max_states)
        .timeout(args.timeout)
        .max_memory(args.max_memory)
        .engine(args.engine.into())
        // A GenoM3 configuration carries each service's worst-case
        // response time; a WCET file is taken for GenoM3 only.
        .response_times(args.target == ExportFormat::Config && args.input.wcet.is_some());
    let result = match genom_check::check_path(&args.file, &args.input.inputs(), &options) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {}", escaped(&e.to_string()));
            return EXIT_USAGE;
        }
    };
    let mut verification = verification(&result);
    let foreign = models_foreign_semantics(args, &result);
    if foreign {
        verification.verified = false;
        verification.properties.clear();
    }
    if let Some(status) = refuse(args, output, &shown, &result, &verification, foreign) {
        return status;
    }
    let Some(component) = &result.component else {
        return EXIT_ERRORS;
    };
    let input = ExportInput {
        component,
        sources: &result.sources,
        verification: &verification,
    };
    match genom_export::export(format(args.target), &input) {
        Ok(exported) => match write(args, &exported, &result) {
            Ok(written) if !output.quiet => {
                for note in &exported.notes {
                    eprintln!("note: {note}");
                }
                // An unverified export had its whole report on stderr.
                let summary = verification.verified.then(|| result.report(&shown));
                report_written(&written, summary.as_ref());
                EXIT_OK
            }
            Ok(_) => EXIT_OK,
            Err(status) => status,
        },
        Err(e) => {
            eprintln!("error: {e}");
            EXIT_ERRORS
        }
    }
}

/// Refuses an unverified export (the report on stdout, as `check` prints
/// it, and the reason on stderr), or, with `--allow-unverified`, reports
/// on stderr and lets it through. `Some(status)` when refused.
fn refuse(
    args: &ExportArgs,
    output: &OutputArgs,
    shown: &str,
    result: &CheckResult,
    verification: &Verification,
    foreign: bool,
) -> Option<u8> {
    let denied = output.deny == Some(Deny::Warnings) && verification.counts.warnings > 0;
    let reasons = |v: &Verification, denied: bool| {
        let mut r = reasons(v, denied);
        if foreign {
            if !r.is_empty() {
                r.push_str(", ");
            }
            r.push_str("this export models LANGUAGE.md's execution semantics, not GenoM3's (not implemented yet for GenoM3 components)");
        }
        r
    };
    if verification.verified && !denied {
        return None;
    }
    let color = terminal::use_color(output.color);
    if result.component.is_none() {
        terminal::emit(&report_text(shown, result, output, color));
        eprintln!("error: `{}` has no component to export", escaped(shown));
        return Some(EXIT_ERRORS);
    }
    if !args.allow_unverified {
        terminal::emit(&report_text(shown, result, output, color));
        eprintln!(
            "error: refusing to export `{}`: {} (use --allow-unverified to export it marked unverified)",
            escaped(shown),
            reasons(verification, denied)
        );
        return Some(EXIT_ERRORS);
    }
    // stdout may carry the export: the report goes to stderr.
    let color = output.color == Color::Always;
    eprint!("{}", report_text(shown, result, output, color));
    if verification.verified {
        eprintln!(
            "warning: exporting `{}` despite {}",
            escaped(shown),
            reasons(verification, denied)
        );
    } else {
        eprintln!(
            "warning: exporting `{}` unverified: {}; the export is marked `verified: false`",
            escaped(shown),
            reasons(verification, denied)
        );
    }
    None
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

/// Whether the export would model the component with another language's
/// semantics ([`Format::semantics`]: a GenoM3 component in a format that
/// has only LANGUAGE.md's).
fn models_foreign_semantics(args: &ExportArgs, result: &CheckResult) -> bool {
    format(args.target).semantics(result.dialect) != result.dialect
}

/// What the check established, with the response times it computed.
fn verification(result: &CheckResult) -> Verification {
    Verification {
        response_times: result.response_times.clone(),
        ..Verification::of(
            result.component.as_ref(),
            &result.diagnostics,
            result.statistics.as_ref(),
            env!("CARGO_PKG_VERSION"),
        )
    }
}

/// Why the export is not verified, for messages.
fn reasons(v: &Verification, denied: bool) -> String {
    let mut out = Vec::new();
    if !v.error_codes.is_empty() {
        out.push(format!(
            "{} error{} ({})",
            v.counts.errors,
            if v.counts.errors == 1 { "" } else { "s" },
            v.error_codes.join(", ")
        ));
    }
    if !v.complete && v.counts.errors == 0 {
        out.push("verification incomplete".to_owned());
    }
    if denied {
        out.push(format!(
            "{} warning{} (denied by --deny warnings)",
            v.counts.warnings,
            if v.counts.warnings == 1 { "" } else { "s" }
        ));
    }
    out.join(", ")
}

/// The check's report, as `check` prints it (human or JSON).
fn report_text(shown: &str, result: &CheckResult, output: &OutputArgs, color: bool) -> String {
    let report = result.report(shown);
    match output.format {
        ReportFormat::Json => return json::render(std::slice::from_ref(&report)) + "\n",
        ReportFormat::Github => {
            let summary = [super::check::summary_line(&report)];
            return github::render(std::slice::from_ref(&report), Some(&summary));
        }
        ReportFormat::Sarif => {
            return super::explain::sarif(std::slice::from_ref(&report));
        }
        ReportFormat::Human => {}
    }
    super::check::human_report(std::slice::from_ref(&report), output, color)
}

/// Writes the main output (stdout without `-o`) and companion files;
/// returns the files written, or the exit status of a failure (2, said on
/// stderr; a failed write to stdout is said once the command ends).
fn write(
    args: &ExportArgs,
    exported: &genom_export::Exported,
    result: &CheckResult,
) -> Result<Vec<PathBuf>, u8> {
    let Some(path) = &args.output else {
        terminal::emit(&exported.main);
        if terminal::failure().is_some() {
            return Err(EXIT_USAGE);
        }
        for (suffix, _) in &exported.extra {
            eprintln!("note: the `{suffix}` companion file is written only with -o");
        }
        return Ok(Vec::new());
    };
    let plan = Plan::new(path, &exported.main, &exported.extra)
        .and_then(|plan| plan.refuse_inputs(&inputs(args, result)).map(|()| plan));
    let plan = match plan {
        Ok(plan) => plan,
        Err(e) => {
            eprintln!("error: {e}");
            return Err(EXIT_USAGE);
        }
    };
    for suffix in plan.skipped() {
        eprintln!(
            "note: `{}` is not a regular file: its `{suffix}` companion file is not written next to it",
            terminal::shown(path)
        );
    }
    let written: Vec<PathBuf> = plan.paths().map(PathBuf::from).collect();
    if let Err(e) = plan.write() {
        eprintln!("error: {e}");
        return Err(EXIT_USAGE);
    }
    Ok(written)
}

/// Every file the run read: the checked file, its includes (the source
/// map lists them; `<built-in>` and `<stdin>` are no files), the WCET file.
fn inputs<'a>(args: &'a ExportArgs, result: &'a CheckResult) -> Vec<Input<'a>> {
    let mut all = Vec::new();
    if !genom_check::is_stdin(&args.file) {
        all.push(Input {
            path: &args.file,
            role: "the checked file",
        });
    }
    // Before the source map, which lists it too (its diagnostics point
    // into it).
    if let Some(wcet) = &args.input.wcet {
        all.push(Input {
            path: wcet,
            role: "the WCET file",
        });
    }
    for (i, (_, file)) in result.sources.files().enumerate() {
        if file.path.as_os_str().to_string_lossy().starts_with('<') {
            continue;
        }
        let role = if i == 0 {
            "the checked file"
        } else {
            "an included file"
        };
        all.push(Input {
            path: &file.path,
            role,
        });
    }
    all
}

/// Says on stderr (stdout may carry the export) what was written and the
/// verdict it rests on, as `check` prints it.
fn report_written(written: &[PathBuf], report: Option<&FileReport<'_>>) {
    if !written.is_empty() {
        let files: Vec<String> = written
            .iter()
            .map(|p| format!("`{}`", terminal::shown(p)))
            .collect();
        eprintln!("wrote {}", files.join(" and "));
    }
    if let Some(report) = report {
        eprintln!("{}", super::check::summary_line(report));
    }
}
