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
    /// The last check of its text (`None` when it could not run).
    pub result: Option<CheckResult>,
    /// The URIs its last check published diagnostics to.
    pub published: BTreeSet<String>,
}

/// Diagnostics by file URI string.
pub type Published = BTreeMap<String, (Uri, Vec<lsp_types::Diagnostic>)>;

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
            result: None,
            published: BTreeSet::new(),
        }
    }

    /// Checks the text (the static checks, or everything when `full`),
    /// keeps the result and returns its diagnostics by file.
    pub fn check(&mut self, settings: &Settings, full: bool) -> Published {
        let config = config::for_file(&self.path, None);
        let (config, config_problem) = match config {
            Ok(c) => (c.unwrap_or_default(), None),
            Err(e) => (Config::default(), Some(e.render())),
        };
        let options = CheckOptions::new()
            .behaviour(full)
            .timeout(Some(config.timeout.unwrap_or(settings.timeout)))
            .max_states(config.max_states.unwrap_or(DEFAULT_MAX_STATES))
            .max_instances(
                config
                    .max_instances
                    .unwrap_or(genom_checker::DEFAULT_MAX_INSTANCES),
            );
        let inputs = Inputs {
            dialect: config.dialect,
            include_dirs: config.include_dirs.clone(),
            wcet_file: config.wcet_for(&self.path).cloned(),
        };
        let checked = genom_check::check_text(&self.path, self.text.clone(), &inputs, &options)
            .map_err(|e| e.to_string())
            .and_then(|mut r| suppress::apply(&mut r, &config.levels).map(|()| r));
        let target = Target {
            document: &self.uri,
            path: &self.path,
            code_url: settings.code_url.as_deref(),
        };
        let mut files = match &checked {
            Ok(result) => publish::by_file(result, &target),
            Err(problem) => self.problem(problem),
        };
        if let Some(problem) = config_problem {
            files.extend(self.problem(&problem));
        }
        self.result = checked.ok();
        files
    }

    /// One error at the top of the document: why it was not checked.
    fn problem(&self, message: &str) -> Published {
        let d = lsp_types::Diagnostic {
            range: Range::default(),
            severity: Some(DiagnosticSeverity::ERROR),
            source: Some("genom-check".to_owned()),
            message: message.to_owned(),
            ..lsp_types::Diagnostic::default()
        };
        BTreeMap::from([(self.uri.as_str().to_owned(), (self.uri.clone(), vec![d]))])
    }
}
