//! `check --system FILE`: loads a system file and its components (each
//! through the pipeline's front-end, with its WCET file, static checks
//! only), then hands them to `genom-system` for the port checks and the
//! cause-effect chains (docs/functional-layer.md). Never prints.

use std::collections::BTreeMap;
use std::path::Path;

use gen_frontend::{FsLoader, Loader};
use genom_model::{Diagnostic, SourceMap, Span};
use genom_system::description::{self, ChainSpec};

use crate::pipeline::{CheckOptions, check_path};
use crate::types::{CheckResult, InputError, Inputs, display};

/// Everything a system check found.
#[derive(Debug, Clone)]
pub struct SystemResult {
    /// The system file (the diagnostics' spans point into it).
    pub sources: SourceMap,
    /// The system's diagnostics (ports, chains), sorted.
    pub diagnostics: Vec<Diagnostic>,
    /// Each component's own check (static checks), by its path as given.
    pub components: Vec<(String, CheckResult)>,
    /// The chains' bounds and the components' timing.
    pub report: genom_system::SystemReport,
}

/// Checks the system file at `path`; `extra` are the command line's
/// chains. Fails only when a file cannot be read.
pub fn check_system(
    path: &Path,
    inputs: &Inputs,
    extra: &[ChainSpec],
    options: &CheckOptions,
    limits: genom_system::Limits,
) -> Result<SystemResult, InputError> {
    let text = FsLoader.load(path).map_err(|error| InputError::Read {
        path: display(path),
        error,
    })?;
    let mut sources = SourceMap::new();
    let id = sources.add(path, text.clone());
    let base = sources.file(id).map_or(0, |f| f.base);
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut result = SystemResult {
        sources,
        diagnostics: Vec::new(),
        components: Vec::new(),
        report: genom_system::SystemReport::default(),
    };
    let file = match description::parse(&text, base, dir) {
        Ok(f) => f,
        Err(d) => {
            result.diagnostics = d;
            return Ok(result);
        }
    };
    let statics = options.clone().behaviour(false);
    let mut comps = BTreeMap::new();
    for entry in &file.components {
        let mut own = inputs.clone();
        own.include_dirs.extend(file.include.iter().cloned());
        own.wcet_file = entry.wcet.clone();
        let checked = check_path(&entry.file, &own, &statics)?;
        if let Some(c) = checked.component.clone() {
            comps.insert(entry.name.clone(), c);
        }
        result.components.push((display(&entry.file), checked));
    }
    let broken = result.components.iter().any(|(_, r)| {
        r.component.is_none()
            || r.diagnostics
                .iter()
                .any(|d| d.severity == genom_model::Severity::Error)
    });
    if broken {
        return Ok(result);
    }
    let (mut diags, report) =
        genom_system::analyse(&file, extra, &comps, limits, Span::new(base, base));
    genom_model::diagnostic::sort_diagnostics(&mut diags);
    result.diagnostics = diags;
    result.report = report;
    Ok(result)
}
