//! Writing an export's files (`export -o PATH`): the main output and its
//! companions (UPPAAL's `.q` query file), with three guarantees.
//!
//! - No output is written over a file the run read (the checked file, its
//!   includes, the WCET file), however it is named: files are compared by
//!   identity (device and inode, with `same-file`), so `./x.gen`, an
//!   absolute path, a symbolic link or a hard link to an input are refused
//!   as `x.gen` is. Two outputs at one path (`-o m.q` for UPPAAL) are
//!   refused too.
//! - All or nothing: each output that is (or will be) a regular file is
//!   written to a temporary file in the same folder, and the temporary files
//!   are renamed over their targets only once every one of them is written
//!   whole. A failed write (full disk, file size limit) leaves every target
//!   as it was and removes the temporary files.
//! - An output that is not a regular file (`/dev/null`, a FIFO, a terminal)
//!   cannot be replaced by a rename: it is written directly, and a companion
//!   file is not written next to it (`/dev/null.q` would be a stray regular
//!   file); [`Plan::skipped`] says which were left out.
//!
//! A symbolic link is followed: the file it points to is replaced, and the
//! link stays. Nothing here prints: errors are returned for the binary to
//! report.

use std::fs;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use same_file::Handle;

use crate::terminal::shown;

/// A file the run read, which no output may replace.
#[derive(Debug, Clone, Copy)]
pub struct Input<'a> {
    /// Its path, as read.
    pub path: &'a Path,
    /// What it is, for messages: `the checked file`, `an included file`,
    /// `the WCET file`.
    pub role: &'static str,
}

/// Why the outputs were not written. Paths are shown escaped.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// An output is one of the run's inputs.
    #[error(
        "refusing to write {what} to `{output}`: it is {role} `{input}`, an input of this run (choose another -o path)"
    )]
    Input {
        /// What the output holds.
        what: String,
        /// The output's path.
        output: String,
        /// The input's role.
        role: &'static str,
        /// The input's path.
        input: String,
    },
    /// Two outputs would be written to one file.
    #[error("refusing to write: {first} and {second} would both go to `{path}` ({hint})")]
    SamePath {
        /// What the first output holds.
        first: String,
        /// What the second holds.
        second: String,
        /// The path.
        path: String,
        /// What to do instead.
        hint: String,
    },
    /// An output cannot be written (nothing was replaced).
    #[error("cannot write `{path}`: {error}")]
    Write {
        /// The path.
        path: String,
        /// Why.
        error: String,
    },
}

/// One output: where, what, and how it is written.
#[derive(Debug)]
struct Output<'a> {
    /// The path as given (or derived from it, for a companion).
    path: PathBuf,
    /// What it holds, for messages.
    what: String,
    text: &'a str,
    how: How,
}

/// How an output is written.
#[derive(Debug, Clone, PartialEq, Eq)]
enum How {
    /// A regular file, or none yet: a temporary file in the folder of this
    /// absolute path (the target, symbolic links resolved), then renamed.
    Replace(PathBuf),
    /// A device or a FIFO: written directly.
    Direct,
}

/// The outputs of one export, checked and ready to write.
#[derive(Debug)]
pub struct Plan<'a> {
    outputs: Vec<Output<'a>>,
    skipped: Vec<String>,
}

impl<'a> Plan<'a> {
    /// The main output at `main` and each companion next to it (its suffix
    /// replacing the extension). Fails when an output is a folder or cannot
    /// be reached, or when two outputs are the same file.
    pub fn new(
        main: &Path,
        main_text: &'a str,
        companions: &'a [(String, String)],
    ) -> Result<Self, OutputError> {
        let how = how(main)?;
        let mut outputs = vec![Output {
            path: main.to_path_buf(),
            what: "the export".to_owned(),
            text: main_text,
            how: how.clone(),
        }];
        let mut skipped = Vec::new();
        for (suffix, text) in companions {
            if how == How::Direct {
                skipped.push(suffix.clone());
                continue;
            }
            let path = companion(main, suffix);
            let output = Output {
                how: self::how(&path)?,
                what: format!("the `{suffix}` companion"),
                path,
                text,
            };
            if let Some(other) = outputs.iter().find(|o| same_target(o, &output)) {
                let hint = if other.path == output.path {
                    format!("give -o a path whose extension is not `{suffix}`")
                } else {
                    "they are links to one file; choose another -o path".to_owned()
                };
                return Err(OutputError::SamePath {
                    first: other.what.clone(),
                    second: output.what,
                    path: shown(&output.path),
                    hint,
                });
            }
            outputs.push(output);
        }
        Ok(Plan { outputs, skipped })
    }

    /// The suffixes of the companions left out because the main output is
    /// not a regular file.
    pub fn skipped(&self) -> &[String] {
        &self.skipped
    }

    /// The paths written, main output first.
    pub fn paths(&self) -> impl Iterator<Item = &Path> {
        self.outputs.iter().map(|o| o.path.as_path())
    }

    /// Refuses an output that is one of `inputs` (by identity).
    pub fn refuse_inputs(&self, inputs: &[Input<'_>]) -> Result<(), OutputError> {
        let existing: Vec<(&Output<'_>, Handle)> = self
            .outputs
            .iter()
            .filter_map(|o| match &o.how {
                How::Replace(target) if target.is_file() => {
                    Handle::from_path(target).ok().map(|h| (o, h))
                }
                _ => None,
            })
            .collect();
        if existing.is_empty() {
            return Ok(());
        }
        for input in inputs {
            // Inputs are regular files (anything else is refused when read):
            // never open a FIFO here.
            if !input.path.is_file() {
                continue;
            }
            let Ok(handle) = Handle::from_path(input.path) else {
                continue;
            };
            if let Some((output, _)) = existing.iter().find(|(_, h)| *h == handle) {
                return Err(OutputError::Input {
                    what: output.what.clone(),
                    output: shown(&output.path),
                    role: input.role,
                    input: shown(input.path),
                });
            }
        }
        Ok(())
    }

    /// Writes every output: the temporary files first, then the devices and
    /// FIFOs, then the renames. On failure no regular target has changed
    /// (unless a rename itself fails, after the files were written).
    pub fn write(self) -> Result<(), OutputError> {
        let mut staged = Vec::new();
        for o in &self.outputs {
            if let How::Replace(target) = &o.how {
                let temp = stage(target, o.text).map_err(|e| failed(&o.path, &e))?;
                staged.push((temp, target, &o.path));
            }
        }
        for o in self.outputs.iter().filter(|o| o.how == How::Direct) {
            direct(&o.path, o.text).map_err(|e| failed(&o.path, &e))?;
        }
        for (temp, target, path) in staged {
            temp.persist(target).map_err(|e| failed(path, &e.error))?;
        }
        Ok(())
    }
}

/// `model.xml` + `.q` → `model.q`.
pub fn companion(path: &Path, suffix: &str) -> PathBuf {
    path.with_extension(suffix.trim_start_matches('.'))
}

/// How `path` is written: replaced when it is a regular file or does not
/// exist yet, directly when it is something else; a folder is an error.
fn how(path: &Path) -> Result<How, OutputError> {
    match fs::metadata(path) {
        Ok(m) if m.is_dir() => Err(OutputError::Write {
            path: shown(path),
            error: "it is a folder".to_owned(),
        }),
        Ok(m) if !m.is_file() => Ok(How::Direct),
        Ok(_) => fs::canonicalize(path)
            .map(How::Replace)
            .map_err(|e| failed(path, &e)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => absolute(path).map(How::Replace),
        Err(e) => Err(failed(path, &e)),
    }
}

/// The absolute path of a file that does not exist yet: its folder
/// resolved, then its name.
fn absolute(path: &Path) -> Result<PathBuf, OutputError> {
    let (Some(name), parent) = (path.file_name(), path.parent()) else {
        return Err(OutputError::Write {
            path: shown(path),
            error: "it names no file".to_owned(),
        });
    };
    let folder = match parent {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let folder = fs::canonicalize(folder).map_err(|e| failed(path, &e))?;
    Ok(folder.join(name))
}

/// Whether two outputs would land in one file.
fn same_target(a: &Output<'_>, b: &Output<'_>) -> bool {
    match (&a.how, &b.how) {
        (How::Replace(x), How::Replace(y)) => x == y,
        _ => a.path == b.path,
    }
}

/// `text` in a new temporary file next to `target` (hidden, named after
/// it), with the target's permissions when it exists and the usual ones
/// (`0666` less the umask) otherwise.
fn stage(target: &Path, text: &str) -> std::io::Result<tempfile::NamedTempFile> {
    let folder = target.parent().unwrap_or(Path::new("."));
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let prefix = format!(".{name}.");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        builder.permissions(fs::Permissions::from_mode(0o666));
    }
    // A file that could not be written in place is not replaced either
    // (opened for writing, not truncated: nothing changes).
    let existing = fs::metadata(target).ok();
    if existing.is_some() {
        fs::OpenOptions::new().write(true).open(target)?;
    }
    let mut temp = builder.tempfile_in(folder)?;
    // Through the `File`: its errors do not name the temporary path.
    temp.as_file_mut().write_all(text.as_bytes())?;
    temp.as_file_mut().flush()?;
    if let Some(existing) = existing {
        temp.as_file().set_permissions(existing.permissions())?;
    }
    Ok(temp)
}

/// Writes `text` into an existing device or FIFO.
fn direct(path: &Path, text: &str) -> std::io::Result<()> {
    let mut file = fs::OpenOptions::new().write(true).open(path)?;
    file.write_all(text.as_bytes())?;
    file.flush()
}

fn failed(path: &Path, e: &std::io::Error) -> OutputError {
    OutputError::Write {
        path: shown(path),
        error: e.to_string(),
    }
}
