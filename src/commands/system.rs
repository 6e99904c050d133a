//! `genom-check check --system FILE [--chain CHAIN]...`: checks a
//! functional layer (docs/functional-layer.md) and prints its port
//! diagnostics, each component's task timing and every chain's data age
//! and reaction time with the timelines that reach them.

use std::fmt::Write as _;
use std::path::Path;

use genom_check::{CheckOptions, Inputs, SystemResult, display};
use genom_model::duration::format_ns;
use genom_model::{Dialect, Severity};
use genom_render::{FileReport, escaped, json};
use genom_system::description::ChainSpec;

use super::{EXIT_ERRORS, EXIT_OK, EXIT_USAGE};
use crate::cli::{CheckArgs, Deny, Format, OutputArgs};
use crate::config;
use crate::terminal;

/// `check --system FILE`: the options (command line, else the
/// configuration), then [`check`].
pub fn run(system: &Path, args: &CheckArgs, output: &OutputArgs) -> u8 {
    let config = match config::for_file(system, args.config.as_deref()) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("{}", e.render());
            return EXIT_USAGE;
        }
    };
    let (options, inputs) = super::check::effective(args, config.as_ref(), system);
    let limits = genom_system::Limits {
        max_states: args
            .max_states
            .or(config.as_ref().and_then(|c| c.max_states))
            .unwrap_or(super::check::DEFAULT_MAX_STATES),
        deadline: args
            .timeout
            .or(config.as_ref().and_then(|c| c.timeout))
            .map(|t| std::time::Instant::now() + t),
        max_bytes: args.max_memory,
    };
    check(system, &inputs, &args.chains, &options, limits, output)
}

/// Checks the system file, prints, and returns the exit status.
fn check(
    path: &Path,
    inputs: &Inputs,
    chains: &[ChainSpec],
    options: &CheckOptions,
    limits: genom_system::Limits,
    output: &OutputArgs,
) -> u8 {
    let result = match genom_check::check_system(path, inputs, chains, options, limits) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {}", escaped(&e.to_string()));
            return EXIT_USAGE;
        }
    };
    let shown = display(path);
    let mut reports: Vec<FileReport<'_>> =
        result.components.iter().map(|(p, r)| r.report(p)).collect();
    // Components' own findings: only errors and warnings (their advice
    // is `genom-check check FILE`'s).
    let kept: Vec<Vec<genom_model::Diagnostic>> = reports
        .iter()
        .map(|r| {
            r.diagnostics
                .iter()
                .filter(|d| d.severity != Severity::Advice)
                .cloned()
                .collect()
        })
        .collect();
    for (r, k) in reports.iter_mut().zip(&kept) {
        r.diagnostics = k;
    }
    reports.push(FileReport {
        path: &shown,
        sources: &result.sources,
        diagnostics: &result.diagnostics,
        statistics: None,
        dialect: Dialect::Genom3,
        pragmas: &[],
        response_times: &[],
    });
    match output.format {
        Format::Json => {
            let files: serde_json::Value =
                serde_json::from_str(&json::render(&reports)).unwrap_or(serde_json::Value::Null);
            let system = serde_json::to_value(&result.report).unwrap_or(serde_json::Value::Null);
            let out = serde_json::json!({ "files": files, "system": system });
            terminal::emit(&(serde_json::to_string_pretty(&out).unwrap_or_default() + "\n"));
        }
        _ => {
            let color = terminal::use_color(output.color);
            let mut text = super::check::human_report(&reports, output, color);
            if !output.quiet {
                text.push_str(&render_report(&result));
            }
            terminal::emit(&text);
        }
    }
    let mut counts = genom_model::Counts::default();
    for r in &reports {
        counts.merge(r.counts());
    }
    if counts.errors > 0 || (output.deny == Some(Deny::Warnings) && counts.warnings > 0) {
        EXIT_ERRORS
    } else {
        EXIT_OK
    }
}

/// The human text of the timing and the chains.
pub fn render_report(result: &SystemResult) -> String {
    let mut out = String::new();
    let r = &result.report;
    if r.components.is_empty() {
        return out;
    }
    out.push_str("\nAssuming:\n");
    for a in &r.assumptions {
        let _ = writeln!(out, "  {}", escaped(a));
    }
    out.push_str("\nTasks (each component a process, each task on its own core):\n");
    for c in &r.components {
        for t in &c.tasks {
            let period = t.period_ns.map_or("no period".to_owned(), format_ns);
            let verdict = match &t.unbounded {
                None => {
                    "never overruns (timed engine): its codels run within each period".to_owned()
                }
                Some(why) => format!("no bound: {why}"),
            };
            let _ = writeln!(out, "  {}.{} ({period}): {verdict}", c.name, t.name);
            for w in c.windows.iter().filter(|w| w.thread == t.thread) {
                let _ = writeln!(
                    out,
                    "    codel {} ends at most {} after its tick",
                    w.codel,
                    format_ns(w.end_ns)
                );
            }
        }
    }
    for req in &r.requests {
        let deadline = req
            .deadline_ns
            .map(|d| format!(" (deadline {})", format_ns(d)))
            .unwrap_or_default();
        let _ = writeln!(
            out,
            "\nChains {}{deadline}: {}",
            req.request,
            req.chains.len()
        );
        for (i, ch) in req.chains.iter().enumerate() {
            let _ = writeln!(out, "  {}. {} -> {}", i + 1, ch.source, ch.sink);
            for s in &ch.stages {
                let writes = s
                    .writes
                    .as_deref()
                    .map(|w| format!(", writes {w}"))
                    .unwrap_or_default();
                let _ = writeln!(
                    out,
                    "       {}.{} codel {} reads {}{writes}",
                    s.component, s.task, s.codel, s.reads
                );
            }
            match (ch.data_age_ns, ch.reaction_ns) {
                (Some(a), Some(b)) => {
                    let _ = writeln!(
                        out,
                        "     data age <= {} s ({}), reaction time <= {} s ({})",
                        seconds(a),
                        format_ns(a),
                        seconds(b),
                        format_ns(b)
                    );
                }
                _ => {
                    let _ = writeln!(
                        out,
                        "     no bound: {}",
                        ch.unbounded.as_deref().unwrap_or("unknown")
                    );
                }
            }
            for s in &ch.sampling {
                let _ = writeln!(out, "     sampling: {s}");
            }
            if !ch.age_trace.is_empty() {
                out.push_str("     data-age timeline:\n");
                for l in &ch.age_trace {
                    let _ = writeln!(out, "       [{}] {}", format_ns(l.time_ns), l.text);
                }
                out.push_str("     reaction-time timeline:\n");
                for l in &ch.reaction_trace {
                    let _ = writeln!(out, "       [{}] {}", format_ns(l.time_ns), l.text);
                }
            }
        }
    }
    out
}

/// Nanoseconds as seconds, to the nanosecond.
fn seconds(ns: u64) -> String {
    format!("{}.{:09}", ns / 1_000_000_000, ns % 1_000_000_000)
}
