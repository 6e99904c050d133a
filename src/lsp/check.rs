//! An open document and its check: the editor's text checked under the
//! document's path (so that its includes and `genom-check.toml` are found
//! next to it), with the configuration's inputs, levels and inline allows.

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;
use std::time::Duration;

use genom_check::{CheckOptions, CheckResult, Inputs};
use lsp_types::{DiagnosticSeverity, Range, Uri};

use super::position;
use super::publish::{self, Target};
use crate::config::{self, Config};
use crate::suppress;

/// States explored by a save check when the configuration does not say
/// (the timeout bounds it first on most components).
const DEFAULT_MAX_STATES: usize = 10_000_000;

/// The server's settings for checks.
#[derive(Debug, Clone)]
pub struct Settings {
    /// How long a save check may explore (then `incomplete`).
    pub timeout: Duration,
    /// `--max-memory`: the state storage of a save check.
    pub max_memory: usize,
    /// The documentation URI template of codes (`{code}` replaced).
    pub code_url: Option<String>,
}

/// An open document.
#[derive(Debug)]
pub struct Document {
    /// Its URI, as the client sent it.
    pub uri: Uri,
    /// The path it is checked under.
    pub path: PathBuf,
    /// Its current text.
    pub text: String,
    /// Counts the texts and saves: a check of an older one is dropped.
    pub generation: u64,
    /// The text the last published check read, with its result (`None`
    /// when it could not run).
    pub checked: Option<(String, CheckResult)>,
    /// The URIs its last check published diagnostics to.
    pub published: BTreeSet<String>,
    /// The `$/progress` token of the save check running, with the
    /// generation it ends at.
    pub progress: Option<(lsp_types::ProgressToken, u64)>,
}

/// Diagnostics by file URI string.
pub type Published = BTreeMap<String, (Uri, Vec<lsp_types::Diagnostic>)>;

/// One check to run.
#[derive(Debug, Clone)]
pub struct Job {
    /// The document's URI.
    pub uri: Uri,
    /// The path it is checked under.
    pub path: PathBuf,
    /// The text to check.
    pub text: String,
    /// The document's generation when asked.
    pub generation: u64,
    /// The whole check (a save), not only the static checks.
    pub full: bool,
}

/// A finished check.
#[derive(Debug)]
pub struct Done {
    /// What was asked.
    pub job: Job,
    /// The result, when the check could run.
    pub result: Option<CheckResult>,
    /// Its diagnostics by file.
    pub files: Published,
}

impl Document {
    /// A document not checked yet.
    pub fn new(uri: Uri, text: String) -> Self {
        // A document that is no local file (`untitled:`) is checked as a
        // file of the current folder.
        let path = position::path_of(&uri).unwrap_or_else(|| {
            let name = uri.as_str().rsplit(['/', ':']).next().unwrap_or("");
            PathBuf::from(if name.is_empty() {
                "untitled.gen"
            } else {
                name
            })
        });
        Self {
            uri,
            path,
            text,
            generation: 0,
            checked: None,
            published: BTreeSet::new(),
            progress: None,
        }
    }

    /// The next check of the document (a new generation).
    pub fn job(&mut self, full: bool) -> Job {
        self.generation += 1;
        Job {
            uri: self.uri.clone(),
            path: self.path.clone(),
            text: self.text.clone(),
            generation: self.generation,
            full,
        }
    }

    /// The last checked text and its result.
    pub fn result(&self) -> Option<(&str, &CheckResult)> {
        self.checked.as_ref().map(|(t, r)| (t.as_str(), r))
    }
}

/// Checks the job's text (the static checks, or everything when `full`)
/// and places its diagnostics by file.
pub fn run(job: Job, settings: &Settings) -> Done {
    let config = config::for_file(&job.path, None);
    let (config, config_problem) = match config {
        Ok(c) => (c.unwrap_or_default(), None),
        Err(e) => (Config::default(), Some(e.render())),
    };
    // A save check computes the response times too (hover shows them);
    // the timed exploration they need runs only with WCETs.
    let options = CheckOptions::new()
        .behaviour(job.full)
        .response_times(job.full)
        .timeout(Some(config.timeout.unwrap_or(settings.timeout)))
        .max_memory(settings.max_memory)
        .max_states(config.max_states.unwrap_or(DEFAULT_MAX_STATES))
        .max_instances(
            config
                .max_instances
                .unwrap_or(genom_checker::DEFAULT_MAX_INSTANCES),
        );
    let inputs = Inputs {
        dialect: config.dialect,
        include_dirs: config.include_dirs.clone(),
        wcet_file: config.wcet_for(&job.path).cloned(),
    };
    let checked = genom_check::check_text(&job.path, job.text.clone(), &inputs, &options)
        .map_err(|e| e.to_string())
        .and_then(|mut r| suppress::apply(&mut r, &config.levels).map(|()| r));
    let target = Target {
        document: &job.uri,
        path: &job.path,
        code_url: settings.code_url.as_deref(),
    };
    let mut files = match &checked {
        Ok(result) => publish::by_file(result, &target),
        Err(problem) => problem_at_top(&job.uri, problem),
    };
    if let Some(problem) = config_problem {
        for (key, (uri, more)) in problem_at_top(&job.uri, &problem) {
            files
                .entry(key)
                .or_insert_with(|| (uri, Vec::new()))
                .1
                .extend(more);
        }
    }
    Done {
        job,
        result: checked.ok(),
        files,
    }
}

/// One error at the top of the document: why it was not (well) checked.
fn problem_at_top(uri: &Uri, message: &str) -> Published {
    let d = lsp_types::Diagnostic {
        range: Range::default(),
        severity: Some(DiagnosticSeverity::ERROR),
        source: Some("genom-check".to_owned()),
        message: message.to_owned(),
        ..lsp_types::Diagnostic::default()
    };
    BTreeMap::from([(uri.as_str().to_owned(), (uri.clone(), vec![d]))])
}
