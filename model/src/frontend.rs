//! The one interface of the front-ends: a [`Frontend`] reads a file of its
//! language (already read as text, its includes and side files through a
//! [`Loader`]) and returns what it [`Loaded`]: the sources, the lowered
//! component and every diagnostic found on the way (as oxc's
//! `ParserReturn { program, diagnostics }`). The product chooses the
//! front-end of a file in one place (`genom_check::frontend`); the checker
//! reads only what the front-end returned.

use std::path::{Path, PathBuf};

use crate::component::Component;
use crate::dialect::{Dialect, Pragma};
use crate::limits::Watch;
use crate::loader::{LoadError, Loader};
use crate::{Assumption, Code, Diagnostic, SourceMap};

/// What a front-end reads: the checked file's text and where the rest
/// comes from.
#[derive(Clone, Copy)]
pub struct Input<'a> {
    /// The checked file (it need not exist: an editor's unsaved text).
    pub path: &'a Path,
    /// Reads the includes and side files.
    pub loader: &'a dyn Loader,
    /// Include folders (`-I`), searched in order after the including
    /// file's folder (GenoM3).
    pub include_dirs: &'a [PathBuf],
    /// Also search the folders of `GENOM_INCLUDE_PATH` after
    /// `include_dirs` (GenoM3; on by default).
    pub env_include_path: bool,
    /// A WCET side file (`--wcet`).
    pub wcet_file: Option<&'a Path>,
    /// When to stop reading (`--timeout`, `--max-memory`).
    pub watch: Watch,
}

impl<'a> Input<'a> {
    /// The file at `path`, its includes read through `loader`: no include
    /// folder but `GENOM_INCLUDE_PATH`'s, no WCET file, no limit.
    pub fn new(path: &'a Path, loader: &'a dyn Loader) -> Self {
        Input {
            path,
            loader,
            include_dirs: &[],
            env_include_path: true,
            wcet_file: None,
            watch: Watch::unlimited(),
        }
    }
}

/// What a front-end returns (`XReturn { value, diagnostics }`).
#[derive(Debug, Clone, Default)]
pub struct Loaded {
    /// The language the file was read as.
    pub dialect: Dialect,
    /// Every loaded file, the checked file first.
    pub sources: SourceMap,
    /// The lowered model the checker reads: `None` when a file is missing
    /// or does not parse (its findings would be the cascade of what is
    /// missing). It may hold types only (a file with no component).
    pub model: Option<Component>,
    /// Whether the files define a component: only then is the model one
    /// (an IDL file gives types to check, no component).
    pub has_component: bool,
    /// Every diagnostic the front-end found, sorted.
    pub diagnostics: Vec<Diagnostic>,
    /// The `#pragma` lines of the file (GenoM3), in order.
    pub pragmas: Vec<Pragma>,
    /// What the verdicts will rest on besides the text (the WCETs of a side
    /// file).
    pub assumptions: Vec<Assumption>,
}

/// Why a front-end read nothing at all.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Refused {
    /// A side file (the WCET file) cannot be read.
    Unreadable {
        /// The side file, as given.
        path: PathBuf,
        /// Why.
        error: LoadError,
    },
    /// The language takes no WCET file (its codels carry their own).
    NoWcetFile,
}

/// A front-end: one language read into the one model.
pub trait Frontend: Sync {
    /// The language it reads.
    fn dialect(&self) -> Dialect;

    /// Whether `text` shows a construct of this language only (to choose a
    /// front-end when none is asked for).
    fn recognises(&self, text: &str) -> bool;

    /// Reads `text` as the file of `input`, with its includes and side
    /// files. Fails only when a side file cannot be read, or is given to a
    /// language that takes none.
    fn load(&self, input: Input<'_>, text: String) -> Result<Loaded, Refused>;

    /// The long explanation (`genom-check explain`) of a code this
    /// front-end owns: its syntax and resolution codes; `None` for others.
    fn explanation(&self, code: Code) -> Option<&'static str>;
}
