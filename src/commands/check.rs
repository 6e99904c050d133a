//! `genom-check check FILE...`: checks each file and prints the reports
//! (human or JSON), then returns the exit status.

use genom_check::{CheckOptions, CheckResult, display};
use genom_model::{Counts, Dialect, Severity};
use genom_render::{FileReport, escaped, github, human, json};

use super::{EXIT_ERRORS, EXIT_OK, EXIT_USAGE};
use crate::cli::{CheckArgs, Deny, EngineArg, Format, OutputArgs};
use crate::config::{self, Config};
use crate::progress::Progress;
use crate::{suppress, terminal};

/// Exploration states allowed when neither `--max-states` nor the
/// configuration says.
pub(super) const DEFAULT_MAX_STATES: usize = 10_000_000;

/// Checks every file, prints, and returns the exit status.
pub fn run(args: &CheckArgs, output: &OutputArgs) -> u8 {
    if args.no_reduction && args.engine == EngineArg::Symbolic {
        eprintln!(
            "error: `--no-reduction` turns off the explicit engine's reductions; `--engine symbolic` has none (use `--engine explicit --no-reduction`)"
        );
        return EXIT_USAGE;
    }
    let mut unread: Vec<json::JsonUnread> = Vec::new();
    let mut results: Vec<(String, CheckResult)> = Vec::new();
    for path in &args.files {
        let config = match config::for_file(path, args.config.as_deref()) {
            Ok(c) => c,
            Err(e) => {
                eprintln!("{}", e.render());
                return EXIT_USAGE;
            }
        };
        let (options, inputs) = effective(args, config.as_ref(), path);
        let progress = Progress::wanted(output.format == Format::Human, output.quiet)
            .then(|| Progress::start(display(path), options.describe_limits()));
        let checked = genom_check::check_path(path, &inputs, &options);
        if let Some(p) = progress {
            p.finish();
        }
        match checked {
            Ok(mut result) => {
                let levels = config.map(|c| c.levels).unwrap_or_default();
                if let Err(e) = suppress::apply(&mut result, &levels) {
                    eprintln!("error: {e}");
                    return EXIT_USAGE;
                }
                results.push((display(path), result));
            }
            Err(e) => {
                eprintln!("error: {}", escaped(&e.to_string()));
                unread.push(json::JsonUnread {
                    path: display(path),
                    error: e.to_string(),
                });
            }
        }
    }
    if let Some(message) = unknown_deadline(args, &results) {
        eprintln!("error: {message}");
        return EXIT_USAGE;
    }
    let reports: Vec<FileReport<'_>> = results.iter().map(|(path, r)| r.report(path)).collect();
    match output.format {
        Format::Human => print_human(&reports, output),
        Format::Json => terminal::emit(&(json::render_with_unread(&reports, &unread) + "\n")),
        Format::Github => print_github(&reports, output),
        Format::Sarif => terminal::emit(&super::explain::sarif(&reports)),
    }
    exit_status(&reports, output.deny, !unread.is_empty())
}

fn print_human(reports: &[FileReport<'_>], output: &OutputArgs) {
    let color = terminal::use_color(output.color);
    terminal::emit(&human_report(reports, output, color));
}

/// The human report of `reports`: errors and warnings in full, each advice
/// in one line (in full with `--verbose`, none with `--quiet`), then, unless
/// quiet, the response times, the summary and assumptions of each file,
/// the `explain` hint, a word on shortened advice and the total.
pub(super) fn human_report(reports: &[FileReport<'_>], output: &OutputArgs, color: bool) -> String {
    let options = human::HumanOptions {
        color,
        width: terminal::width(),
    };
    let mut out = String::new();
    let mut shortened = 0;
    for report in reports {
        for d in report.diagnostics {
            if d.severity != Severity::Advice || output.verbose {
                out.push_str(&human::render_diagnostic(report.sources, d, options));
            } else if !output.quiet {
                out.push_str(&human::render_advice_line(report.sources, d, options));
                shortened += 1;
            }
        }
        if !output.quiet {
            out.push_str(&genom_model::response::render_table(report.response_times));
            out.push_str(&(summary_line(report) + "\n"));
            if let Some(a) = assumptions(report) {
                out.push_str(&format!("  {a}\n"));
            }
        }
    }
    if output.quiet {
        return out;
    }
    if let Some(hint) = explain_hint(reports) {
        out.push_str(&(hint + "\n"));
    }
    if shortened > 0 {
        out.push_str("Advice is shown in one line each: `--verbose` shows it in full.\n");
    }
    if reports.len() > 1 {
        out.push_str(&(human::render_total(total(reports), reports.len()) + "\n"));
    }
    out
}

/// The options and inputs for `path`: the command line's, else the
/// configuration's, else the defaults.
pub(super) fn effective(
    args: &CheckArgs,
    config: Option<&Config>,
    path: &std::path::Path,
) -> (CheckOptions, genom_check::Inputs) {
    let options = CheckOptions::new()
        .max_states(
            args.max_states
                .or(config.and_then(|c| c.max_states))
                .unwrap_or(DEFAULT_MAX_STATES),
        )
        .timeout(args.timeout.or(config.and_then(|c| c.timeout)))
        .max_memory(args.max_memory)
        .behaviour(!args.static_only)
        .reduction(!args.no_reduction)
        .engine(args.engine.into())
        .max_instances(
            args.max_instances
                .or(config.and_then(|c| c.max_instances))
                .unwrap_or(genom_checker::DEFAULT_MAX_INSTANCES),
        )
        .response_times(args.response_times);
    let options = args
        .deadlines
        .iter()
        .fold(options, |o, (s, ns)| o.deadline_for(s, *ns));
    let mut inputs = args.input.inputs();
    if let Some(c) = config {
        inputs.dialect = inputs.dialect.or(c.dialect);
        inputs.include_dirs.extend(c.include_dirs.iter().cloned());
        if inputs.wcet_file.is_none() {
            inputs.wcet_file = c.wcet_for(path).cloned();
        }
    }
    (options, inputs)
}

/// A `--deadline` naming a service that a checked component (either
/// dialect) does not have: the usage error to print (with the closest
/// name).
fn unknown_deadline(args: &CheckArgs, results: &[(String, CheckResult)]) -> Option<String> {
    for (path, r) in results {
        let Some(c) = r.component.as_ref() else {
            continue;
        };
        let names: Vec<&str> = c.services.values().map(|s| s.name.name.as_str()).collect();
        for (service, _) in &args.deadlines {
            if names.contains(&service.as_str()) {
                continue;
            }
            let hint = genom_model::diagnostic::closest(service, names.iter().copied())
                .map(|n| format!(" (did you mean `{n}`?)"))
                .unwrap_or_default();
            return Some(format!(
                "--deadline: `{path}` has no service `{service}`{hint}"
            ));
        }
    }
    None
}

/// Once per run, as rustc does: how to learn more about the codes shown
/// (the first error's code as the example, else the first code).
pub(super) fn explain_hint(reports: &[FileReport<'_>]) -> Option<String> {
    let all = || reports.iter().flat_map(|r| r.diagnostics.iter());
    let example = all()
        .find(|d| d.severity == Severity::Error)
        .or_else(|| all().next())?
        .code
        .as_str();
    let distinct: std::collections::BTreeSet<&str> = all().map(|d| d.code.as_str()).collect();
    let explain = match super::explain::common_dialect(reports) {
        Dialect::Genom3 => "genom-check explain --dialect genom3",
        Dialect::Gen => "genom-check explain",
    };
    Some(if distinct.len() == 1 {
        format!("For more information about `{example}`, run `{explain} {example}`.")
    } else {
        format!(
            "For more information about a code, run `{explain} CODE`, e.g. `{explain} {example}`."
        )
    })
}

/// GitHub annotations (advice and summaries left out with `--quiet`).
fn print_github(reports: &[FileReport<'_>], output: &OutputArgs) {
    let kept: Vec<Vec<genom_model::Diagnostic>> = reports
        .iter()
        .map(|r| {
            r.diagnostics
                .iter()
                .filter(|d| !(output.quiet && d.severity == Severity::Advice))
                .cloned()
                .collect()
        })
        .collect();
    let shown: Vec<FileReport<'_>> = reports
        .iter()
        .zip(&kept)
        .map(|(r, d)| FileReport {
            diagnostics: d,
            ..*r
        })
        .collect();
    if output.quiet {
        terminal::emit(&github::render(&shown, None));
    } else {
        let summaries: Vec<String> = reports
            .iter()
            .map(|r| match assumptions(r) {
                Some(a) => format!("{}; {a}", summary_line(r)),
                None => summary_line(r),
            })
            .collect();
        terminal::emit(&github::render(&shown, Some(&summaries)));
    }
}

/// The counts over every report.
fn total(reports: &[FileReport<'_>]) -> Counts {
    let mut total = Counts::default();
    for r in reports {
        total.merge(r.counts());
    }
    total
}

/// The summary line of one file: counts, then the exploration figures.
pub(super) fn summary_line(report: &FileReport<'_>) -> String {
    let mut line = match report.dialect {
        Dialect::Gen => human::render_summary(report.path, report.counts()),
        Dialect::Genom3 => {
            let path = format!("{} ({})", report.path, Dialect::Genom3.title());
            human::render_summary(&path, report.counts())
        }
    };
    if let Some(s) = report.statistics {
        line.push_str(&format!(
            " ({} states, {} transitions, {:.1} ms{}{})",
            s.states,
            s.transitions,
            s.time_ms,
            engines(s),
            if s.complete { "" } else { ", incomplete" }
        ));
    }
    line
}

/// `assuming A; B` when the verdicts rest on something the component
/// does not say (a WCET file, an instance bound), control characters
/// escaped.
pub(super) fn assumptions(report: &FileReport<'_>) -> Option<String> {
    let assumed = report.statistics?.assumed()?;
    // The WCET file's name comes from outside.
    Some(format!("assuming {}", escaped(&assumed)))
}

/// `, symbolic` when the symbolic engine decided some part (the explicit
/// engine, the default, goes unsaid).
fn engines(s: &genom_model::Statistics) -> String {
    match s.engines().as_str() {
        "" | "explicit" | "zones" => String::new(),
        e => format!(", {e}"),
    }
}

fn exit_status(reports: &[FileReport<'_>], deny: Option<Deny>, io_failed: bool) -> u8 {
    if io_failed {
        return EXIT_USAGE;
    }
    let mut counts = Counts::default();
    for r in reports {
        counts.merge(r.counts());
    }
    let denied_warnings = deny == Some(Deny::Warnings) && counts.warnings > 0;
    if counts.errors > 0 || denied_warnings {
        EXIT_ERRORS
    } else {
        EXIT_OK
    }
}
