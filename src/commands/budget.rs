//! `genom-check budget FILE`: for each codel, the largest WCET that keeps
//! the component free of errors with the other WCETs as given, and the
//! largest common scale factor of all WCETs (see docs/timing.md, "WCET
//! budgets"). Printed as a table or, with `--format json`, as one JSON
//! document.
//!
//! The subcommand is always registered; a binary built without the cargo
//! feature `smt` (which brings z3) answers it with exit status 2 and a
//! message saying so, instead of an "unknown subcommand" error.
//!
//! Exit status: 0 when the component as given is clean and every budget
//! was found; 1 when the file has errors that prevent budgets (the report
//! is printed as `check` prints it), when the component as given has errors
//! (the budgets are still printed), or when a search was incomplete; 2 on
//! usage or I/O problems.

/// Runs `budget` (this binary was built without z3).
#[cfg(not(feature = "smt"))]
pub fn run(_args: &crate::cli::BudgetArgs, _output: &crate::cli::OutputArgs) -> u8 {
    eprintln!(
        "error: this genom-check was built without the `smt` feature, which `budget` needs \
         (rebuild with `cargo build --release --features smt`; it links the system libz3)"
    );
    super::EXIT_USAGE
}

#[cfg(feature = "smt")]
pub use with_smt::run;

#[cfg(feature = "smt")]
mod with_smt {
    use std::time::Instant;

    use genom_check::CheckOptions;
    use genom_checker::budget::{
        BudgetOptions, Budgets, CodelBudget, Limit, SCALE_STEPS, ScaleBudget, budgets,
    };
    use genom_model::component::{CodelId, Component};
    use genom_model::duration::format_ns;
    use genom_model::{Code, Dialect, Severity};
    use genom_render::{FileReport, github, human, json};
    use serde_json::{Value, json};

    use super::super::{EXIT_ERRORS, EXIT_OK, EXIT_USAGE};
    use crate::cli::{BudgetArgs, Format, OutputArgs};
    use crate::terminal;

    /// Computes and prints the budgets; returns the exit status.
    pub fn run(args: &BudgetArgs, output: &OutputArgs) -> u8 {
        let started = Instant::now();
        let shown = genom_check::display(&args.file);
        let options = CheckOptions::new().behaviour(false);
        let result = match genom_check::check_path(&args.file, &args.input.inputs(), &options) {
            Ok(r) => r,
            Err(e) => {
                eprintln!("error: {e}");
                return EXIT_USAGE;
            }
        };
        if result.dialect == Dialect::Genom3 {
            print_report(&shown, &result, output);
            eprintln!(
                "error: `{shown}` is a GenoM3 component: budgets explore its timed behaviour, and the engines do not model GenoM3's execution semantics yet"
            );
            return EXIT_ERRORS;
        }
        let blocking = result
            .diagnostics
            .iter()
            .any(|d| d.severity == Severity::Error && d.code != Code::CodelOverrun);
        let Some(component) = result.component.as_ref().filter(|_| !blocking) else {
            print_report(&shown, &result, output);
            eprintln!("error: `{shown}` has errors that leave no component to compute budgets for");
            return EXIT_ERRORS;
        };
        let codels = match selected(component, &args.codels) {
            Ok(c) => c,
            Err(name) => {
                eprintln!(
                    "error: `{shown}` has no codel `{name}` (write `SERVICE::CODEL`, or `SERVICE` for its start codel)"
                );
                return EXIT_USAGE;
            }
        };
        let options = budget_options(args, codels, started);
        let found = match budgets(component, &options) {
            Ok(b) => b,
            Err(e) => {
                eprintln!("error: `{shown}`: {e}");
                return EXIT_ERRORS;
            }
        };
        match output.format {
            // Budgets are a table, not diagnostics: GitHub gets it as text.
            Format::Human | Format::Github | Format::Sarif => {
                terminal::emit(&table(&shown, component, &found, args));
            }
            Format::Json => terminal::emit(&(to_json(&shown, component, &found) + "\n")),
        }
        exit_status(&found)
    }

    fn budget_options(
        args: &BudgetArgs,
        codels: Option<Vec<CodelId>>,
        started: Instant,
    ) -> BudgetOptions {
        let cap_ns = u64::try_from(args.cap.as_nanos()).unwrap_or(u64::MAX);
        let defaults = BudgetOptions::default();
        BudgetOptions {
            max_states: args.max_states,
            max_memory: args.max_memory,
            deadline: args.timeout.and_then(|t| started.checked_add(t)),
            cap_ns,
            codels,
            scale: !args.no_scale,
            jobs: args
                .jobs
                .map_or(defaults.jobs, |j| usize::try_from(j).unwrap_or(1)),
            ..defaults
        }
    }

    /// The codels named by `--codel` (`None`: all); `Err` with the first
    /// name that matches none.
    fn selected(c: &Component, names: &[String]) -> Result<Option<Vec<CodelId>>, String> {
        if names.is_empty() {
            return Ok(None);
        }
        let mut out = Vec::new();
        for name in names {
            let (service, codel) = name.split_once("::").unwrap_or((name, "start"));
            let id = c
                .service_named(service)
                .and_then(|s| c.codel_named(s, codel))
                .ok_or_else(|| name.clone())?;
            if !out.contains(&id) {
                out.push(id);
            }
        }
        out.sort();
        Ok(Some(out))
    }

    fn print_report(shown: &str, result: &genom_check::CheckResult, output: &OutputArgs) {
        let report = FileReport {
            statistics: None,
            ..result.report(shown)
        };
        match output.format {
            Format::Json => terminal::emit(&(json::render(&[report]) + "\n")),
            Format::Sarif => terminal::emit(&crate::commands::explain::sarif(&[report])),
            Format::Github => {
                let summary = [human::render_summary(shown, report.counts())];
                terminal::emit(&github::render(&[report], Some(&summary)));
            }
            Format::Human => {
                let options = human::HumanOptions {
                    color: terminal::use_color(output.color),
                    width: terminal::width(),
                };
                for d in report.diagnostics {
                    if !(output.quiet && d.severity == Severity::Advice) {
                        terminal::emit(&human::render_diagnostic(report.sources, d, options));
                    }
                }
                terminal::emit(&(human::render_summary(shown, report.counts()) + "\n"));
            }
        }
    }

    fn exit_status(b: &Budgets) -> u8 {
        let settled = |l: Limit| matches!(l, Limit::Exact(_) | Limit::Unbounded);
        let mut all = b
            .codels
            .iter()
            .map(|x| x.limit)
            .chain(b.scale.as_ref().map(|s| s.limit));
        if b.as_given.is_empty() && all.all(settled) {
            EXIT_OK
        } else {
            EXIT_ERRORS
        }
    }

    fn codes(codes: &[Code]) -> String {
        codes
            .iter()
            .map(|c| c.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// A budget as text: the exact value, or why there is none.
    fn limit_text(limit: Limit, cap: &str) -> String {
        match limit {
            Limit::Exact(ns) => format_ns(ns),
            Limit::Unbounded => format!("no limit up to {cap}"),
            Limit::NoCleanValue => "none (errors at 0)".to_owned(),
            Limit::Incomplete { at_least: Some(ns) } => format!("≥ {} (incomplete)", format_ns(ns)),
            Limit::Incomplete { at_least: None } => "incomplete".to_owned(),
        }
    }

    /// A scale factor in steps, as `×2.000`.
    fn factor(steps: u64) -> String {
        format!("×{}.{:03}", steps / SCALE_STEPS, steps % SCALE_STEPS)
    }

    fn scale_text(limit: Limit) -> String {
        match limit {
            Limit::Exact(s) => factor(s),
            Limit::Unbounded => "no limit up to ×1000".to_owned(),
            Limit::NoCleanValue => "none (errors at ×0)".to_owned(),
            Limit::Incomplete { at_least: Some(s) } => format!("≥ {} (incomplete)", factor(s)),
            Limit::Incomplete { at_least: None } => "incomplete".to_owned(),
        }
    }

    fn table(shown: &str, c: &Component, b: &Budgets, args: &BudgetArgs) -> String {
        let cap = format_ns(u64::try_from(args.cap.as_nanos()).unwrap_or(u64::MAX));
        let mut rows: Vec<[String; 5]> = vec![[
            "codel".into(),
            "WCET".into(),
            "budget".into(),
            "z3 bound".into(),
            "limited by (1 ns above)".into(),
        ]];
        for x in &b.codels {
            rows.push(codel_row(c, x, &cap));
        }
        let mut out = format!("WCET budgets of `{shown}`\n");
        if !b.as_given.is_empty() {
            out.push_str(&format!(
                "note: the component as given has errors ({}); budgets keep the other WCETs as given\n",
                codes(&b.as_given)
            ));
        }
        out.push_str(&render_rows(&rows));
        if let Some(s) = &b.scale {
            out.push_str(&scale_line(s));
        }
        out.push_str(&format!(
            "{} explorations, {:.1} ms; each budget is clean at its value and has an error 1 ns above\n",
            b.runs,
            b.elapsed.as_secs_f64() * 1000.0
        ));
        out
    }

    fn codel_row(c: &Component, x: &CodelBudget, cap: &str) -> [String; 5] {
        [
            c.codel_label(x.codel),
            x.given.map_or_else(|| "-".to_owned(), format_ns),
            limit_text(x.limit, cap),
            x.smt.map_or_else(|| "-".to_owned(), format_ns),
            codes(&x.limited_by),
        ]
    }

    fn scale_line(s: &ScaleBudget) -> String {
        let mut line = format!("\nscale factor of all WCETs: {}", scale_text(s.limit));
        if let Limit::Exact(steps) = s.limit {
            line.push_str(&format!(
                " (clean at {}, {} at {})",
                factor(steps),
                codes(&s.limited_by),
                factor(steps + 1)
            ));
        }
        line.push_str("\n\n");
        line
    }

    fn render_rows(rows: &[[String; 5]]) -> String {
        let mut widths = [0usize; 5];
        for r in rows {
            for (w, cell) in widths.iter_mut().zip(r) {
                *w = (*w).max(cell.chars().count());
            }
        }
        let mut out = String::new();
        for r in rows {
            let mut line = String::from(" ");
            for (w, cell) in widths.iter().zip(r) {
                line.push(' ');
                line.push_str(cell);
                line.push_str(&" ".repeat(w - cell.chars().count() + 1));
            }
            out.push_str(line.trim_end());
            out.push('\n');
        }
        out
    }

    fn status(limit: Limit) -> &'static str {
        match limit {
            Limit::Exact(_) => "exact",
            Limit::Unbounded => "unbounded",
            Limit::NoCleanValue => "no-clean-value",
            Limit::Incomplete { .. } => "incomplete",
        }
    }

    /// The value JSON reports for a limit: the budget when exact, the cap
    /// when unbounded (checked clean), the largest value known clean when
    /// incomplete.
    fn value(limit: Limit, cap: u64) -> Value {
        match limit {
            Limit::Exact(v) => json!(v),
            Limit::Unbounded => json!(cap),
            Limit::Incomplete { at_least } => json!(at_least),
            Limit::NoCleanValue => Value::Null,
        }
    }

    fn code_list(codes: &[Code]) -> Value {
        Value::from(codes.iter().map(|c| c.as_str()).collect::<Vec<_>>())
    }

    fn to_json(shown: &str, c: &Component, b: &Budgets) -> String {
        let codels: Vec<Value> = b.codels.iter().map(|x| codel_json(c, x, b)).collect();
        let scale = b.scale.as_ref().map(|s| {
            json!({
                "status": status(s.limit),
                "steps": value(s.limit, b.scale_cap),
                "steps_per_unit": SCALE_STEPS,
                "factor": match s.limit {
                    Limit::Exact(v) | Limit::Incomplete { at_least: Some(v) } => json!(v as f64 / SCALE_STEPS as f64),
                    Limit::Unbounded => json!(b.scale_cap as f64 / SCALE_STEPS as f64),
                    _ => Value::Null,
                },
                "smt_bound_steps": s.smt,
                "limited_by": code_list(&s.limited_by),
                "explorations": s.runs,
            })
        });
        let doc = json!({
            "file": shown,
            "unit_ns": 1,
            "grid_ns": b.grid_ns,
            "cap_ns": b.cap_ns,
            "clean_as_given": b.as_given.is_empty(),
            "errors_as_given": code_list(&b.as_given),
            "codels": codels,
            "scale": scale,
            "constraints": b.constraints,
            "explorations": b.runs,
            "time_ms": b.elapsed.as_secs_f64() * 1000.0,
        });
        serde_json::to_string_pretty(&doc).unwrap_or_default()
    }

    fn codel_json(c: &Component, x: &CodelBudget, b: &Budgets) -> Value {
        let codel = &c.codels[x.codel];
        json!({
            "codel": c.codel_label(x.codel),
            "service": c.services[codel.service].name.name,
            "name": codel.name.name,
            "wcet_ns": x.given,
            "status": status(x.limit),
            "budget_ns": value(x.limit, b.cap_ns),
            "smt_bound_ns": x.smt,
            "limited_by": code_list(&x.limited_by),
            "explorations": x.runs,
        })
    }
}
