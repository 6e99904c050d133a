//! Runs the stages of a check in order (text → AST → model → verdicts):
//! the front-end of the file's language lowers the text into the model,
//! the checker checks it. [`frontend`] is the one place the language of a
//! file is chosen.

use std::path::Path;
use std::time::Instant;

use gen_frontend::{FsLoader, GenFrontend, LoadError, Loader};
use genom_model::Dialect;
use genom_model::frontend::{Frontend, Input, Loaded, Refused};
use genom3_frontend::Genom3Frontend;

pub use genom_checker::CheckOptions;

use crate::types::{CheckResult, InputError, Inputs, STDIN_NAME, display, is_stdin};

/// Every front-end, in the order [`frontend`] asks them whether they
/// recognise a text; LANGUAGE.md, which recognises nothing of its own, is
/// the default.
pub static FRONTENDS: [&dyn Frontend; 2] = [&Genom3Frontend, &GenFrontend];

/// The front-end of a file: the one place the language is chosen. The
/// `dialect` asked for (`--dialect`, the configuration), else the first
/// front-end that recognises the text's syntax, else LANGUAGE.md's.
pub fn frontend(dialect: Option<Dialect>, text: &str) -> &'static dyn Frontend {
    let chosen = match dialect {
        Some(d) => FRONTENDS.iter().find(|f| f.dialect() == d),
        None => FRONTENDS.iter().find(|f| f.recognises(text)),
    };
    chosen.copied().unwrap_or(&GenFrontend)
}

/// The dialect a text is written in, by its syntax: GenoM3 when it has a
/// GenoM3-only construct, else LANGUAGE.md.
pub fn detect(text: &str) -> Dialect {
    frontend(None, text).dialect()
}

/// Checks the file at `path` in the dialect `inputs` says or its syntax
/// shows. Fails only when a file cannot be read at all.
pub fn check_path(
    path: &Path,
    inputs: &Inputs,
    options: &CheckOptions,
) -> Result<CheckResult, InputError> {
    let read = if is_stdin(path) {
        genom_model::loader::read_bounded(std::io::stdin().lock())
    } else {
        FsLoader.load(path)
    };
    let text = read.map_err(|error| InputError::Read {
        path: display(path),
        error,
    })?;
    let path = if is_stdin(path) {
        Path::new(STDIN_NAME)
    } else {
        path
    };
    check_text(path, text, inputs, options)
}

/// Checks `text` as the content of the file at `path` (which need not
/// exist, or may hold older text: an editor's unsaved buffer); its includes
/// are read from disk next to `path`. Fails only when the WCET file cannot
/// be read, or is given for a LANGUAGE.md file.
pub fn check_text(
    path: &Path,
    text: String,
    inputs: &Inputs,
    options: &CheckOptions,
) -> Result<CheckResult, InputError> {
    let started = Instant::now();
    let input = Input {
        path,
        loader: &FsLoader,
        include_dirs: &inputs.include_dirs,
        env_include_path: true,
        wcet_file: inputs.wcet_file.as_deref(),
        watch: options.watch(started),
    };
    let loaded =
        frontend(inputs.dialect, &text)
            .load(input, text)
            .map_err(|refused| match refused {
                Refused::Unreadable { path, error } => InputError::Read {
                    path: display(&path),
                    error,
                },
                Refused::NoWcetFile => InputError::WcetNeedsGenom3 {
                    path: display(path),
                },
            })?;
    Ok(genom_checker::check(loaded, options, started).into())
}

/// Checks the LANGUAGE.md file at `path`. Fails only when that file cannot
/// be read.
pub fn check_file(
    path: &Path,
    loader: &dyn Loader,
    options: &CheckOptions,
) -> Result<CheckResult, LoadError> {
    let text = loader.load(path)?;
    Ok(check_source(path, text, loader, options))
}

/// Checks already-loaded LANGUAGE.md text; includes are read through
/// `loader`.
pub fn check_source(
    path: &Path,
    text: String,
    loader: &dyn Loader,
    options: &CheckOptions,
) -> CheckResult {
    let started = Instant::now();
    let input = Input {
        watch: options.watch(started),
        ..Input::new(path, loader)
    };
    // Without a WCET file, the front-end reads whatever the text is.
    let loaded = GenFrontend
        .load(input, text)
        .unwrap_or_else(|_| Loaded::default());
    genom_checker::check(loaded, options, started).into()
}
