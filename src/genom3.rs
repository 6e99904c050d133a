//! The check of a GenoM3 file: the GenoM3 front-end reads it with its
//! includes and WCET side file and lowers it into the model, then the
//! checker runs its static checks, then (no `--static-only`, no errors) the
//! GenoM3 engine explores it under GenoM3's semantics; with WCETs given
//! (`--wcet`), the timed GenoM3 engine checks the schedulability of every
//! task.

use std::path::Path;
use std::time::Instant;

use genom_genom3::Genom3Options;
use genom_model::{Assumption, Dialect, Severity};

use genom_checker::CheckOptions;

use crate::types::{CheckResult, InputError, Inputs, display};

/// Checks GenoM3 text read from `path`. Fails only when the WCET file
/// cannot be read.
pub(crate) fn check(
    path: &Path,
    text: String,
    inputs: &Inputs,
    options: &CheckOptions,
) -> Result<CheckResult, InputError> {
    let started = Instant::now();
    let options3 = Genom3Options {
        include_dirs: inputs.include_dirs.clone(),
        use_env_include_path: true,
        wcet_file: inputs.wcet_file.clone(),
        watch: options.watch(started),
    };
    // The checked file is read already: only the WCET file can fail.
    let mut front =
        genom_genom3::load_text(path, text, &options3).map_err(|error| InputError::Read {
            path: inputs.wcet_file.as_deref().map(display).unwrap_or_default(),
            error,
        })?;
    // A partial component (a file missing or unparsed) is not checked: its
    // findings would be the cascade of what is missing.
    let has_component = front.component.is_some();
    let model = front.component.take().filter(|_| front.is_complete());
    let static_only = options.clone().behaviour(false);
    let verdicts = genom_checker::verify(
        model,
        has_component,
        front.diagnostics,
        &static_only,
        started,
    );
    let mut result = CheckResult {
        dialect: Dialect::Genom3,
        sources: front.sources,
        diagnostics: verdicts.diagnostics,
        component: verdicts.component,
        statistics: None,
        pragmas: front.pragmas,
        response_times: Vec::new(),
    };
    // A codel longer than its task's period (`codel-overrun`) is a timing
    // finding, not a broken model: the engines still run.
    let clean = !result
        .diagnostics
        .iter()
        .any(|d| d.severity == Severity::Error && d.code != genom_model::Code::CodelOverrun);
    // (The component stays in the result: `--static-only` and unclean
    // checks keep it too.)
    let explored = match (options.runs_behaviour() && clean, result.component.as_ref()) {
        (true, Some(c)) => genom_checker::verify_genom3(c, options, started),
        _ => None,
    };
    if let Some(mut v) = explored {
        if let Some(wcet) = &inputs.wcet_file {
            let file = Assumption::wcet(&display(wcet));
            v.statistics.assumptions.insert(0, file);
        }
        v.attach_codel_overrun_traces(&mut result.diagnostics);
        result.extend(v.diagnostics);
        result.statistics = Some(v.statistics);
        result.response_times = v.response_times;
    }
    Ok(result)
}
