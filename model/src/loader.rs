//! Reading source files, for every front-end: the [`Loader`] trait (the file
//! system, or memory for tests and fuzzing) and lexical path handling for
//! includes.

use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Component, Path, PathBuf};

/// Why a file could not be read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LoadError {
    /// No file at that path.
    #[error("no such file")]
    NotFound,
    /// The path is a directory.
    #[error("it is a directory")]
    IsDirectory,
    /// The bytes are not UTF-8.
    #[error("it is not valid UTF-8 text")]
    NotUtf8,
    /// A device, FIFO or socket: reading it may never end.
    #[error("it is not a regular file (a device, FIFO or socket)")]
    NotRegular,
    /// Over the 1 GiB limit of the offset space.
    #[error("it is too large ({0} bytes; the limit is 1 GiB)")]
    TooLarge(u64),
    /// Any other I/O error.
    #[error("{0}")]
    Io(String),
}

/// Largest file accepted: spans are 32-bit offsets shared by all files.
pub const MAX_FILE_BYTES: u64 = 1 << 30;

/// Where source text comes from.
pub trait Loader {
    /// Reads a whole file as UTF-8 text.
    fn load(&self, path: &Path) -> Result<String, LoadError>;

    /// A key identifying the file (to detect cycles and repeated includes).
    fn identity(&self, path: &Path) -> PathBuf {
        normalize(path)
    }

    /// Whether `path` names a readable file (for include searches).
    fn exists(&self, path: &Path) -> bool {
        self.load(path).is_ok()
    }
}

/// The name the text read from standard input is checked under (its
/// includes are searched from the current folder).
pub const STDIN_NAME: &str = "<stdin>";

/// Whether `path` is `-`: standard input.
pub fn is_stdin(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// How a path given by the user is shown: `/`-separated, and `-` (standard
/// input) as `<stdin>`.
pub fn display(path: &Path) -> String {
    if is_stdin(path) {
        STDIN_NAME.to_owned()
    } else {
        crate::span::display_path(path)
    }
}

/// Reads a whole text from `reader`, at most [`MAX_FILE_BYTES`].
pub fn read_bounded(reader: impl Read) -> Result<String, LoadError> {
    let mut bytes = Vec::new();
    reader
        .take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| io_error(&e))?;
    let read = u64::try_from(bytes.len()).unwrap_or(u64::MAX);
    if read > MAX_FILE_BYTES {
        return Err(LoadError::TooLarge(read));
    }
    String::from_utf8(bytes).map_err(|_| LoadError::NotUtf8)
}

/// Reads from the file system.
#[derive(Debug, Clone, Copy, Default)]
pub struct FsLoader;

impl Loader for FsLoader {
    fn load(&self, path: &Path) -> Result<String, LoadError> {
        let meta = std::fs::metadata(path).map_err(|e| io_error(&e))?;
        if meta.is_dir() {
            return Err(LoadError::IsDirectory);
        }
        if !meta.is_file() {
            return Err(LoadError::NotRegular);
        }
        if meta.len() > MAX_FILE_BYTES {
            return Err(LoadError::TooLarge(meta.len()));
        }
        // Bounded even if the file grows while it is read.
        let file = std::fs::File::open(path).map_err(|e| io_error(&e))?;
        read_bounded(file)
    }

    fn identity(&self, path: &Path) -> PathBuf {
        std::fs::canonicalize(path).unwrap_or_else(|_| normalize(path))
    }

    fn exists(&self, path: &Path) -> bool {
        path.is_file()
    }
}

fn io_error(e: &std::io::Error) -> LoadError {
    match e.kind() {
        std::io::ErrorKind::NotFound => LoadError::NotFound,
        std::io::ErrorKind::IsADirectory => LoadError::IsDirectory,
        _ => LoadError::Io(e.to_string()),
    }
}

/// Files held in memory, keyed by normalised path.
#[derive(Debug, Clone, Default)]
pub struct MemoryLoader {
    files: BTreeMap<PathBuf, String>,
}

impl MemoryLoader {
    /// An empty set of files.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a file.
    #[must_use]
    pub fn with(mut self, path: impl AsRef<Path>, text: impl Into<String>) -> Self {
        self.files.insert(normalize(path.as_ref()), text.into());
        self
    }
}

impl Loader for MemoryLoader {
    fn load(&self, path: &Path) -> Result<String, LoadError> {
        let key = normalize(path);
        if let Some(text) = self.files.get(&key) {
            return Ok(text.clone());
        }
        let is_dir = self.files.keys().any(|k| k.starts_with(&key) && *k != key);
        Err(if is_dir {
            LoadError::IsDirectory
        } else {
            LoadError::NotFound
        })
    }

    fn exists(&self, path: &Path) -> bool {
        self.files.contains_key(&normalize(path))
    }
}

/// Removes `.` components and folds `dir/..` pairs, without touching the
/// file system (so paths stay as the user wrote them).
pub fn normalize(path: &Path) -> PathBuf {
    let mut out: Vec<Component<'_>> = Vec::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir if matches!(out.last(), Some(Component::Normal(_))) => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out.iter().collect()
}

/// The path of an include written in `including`.
pub fn resolve_include(including: &Path, written: &str) -> PathBuf {
    let written = Path::new(written);
    if written.is_absolute() {
        return normalize(written);
    }
    normalize(
        &including
            .parent()
            .unwrap_or_else(|| Path::new(""))
            .join(written),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn includes_resolve_relative_to_the_including_file() {
        assert_eq!(
            resolve_include(Path::new("specs/pilot.gen"), "demoStruct.idl"),
            PathBuf::from("specs/demoStruct.idl")
        );
        assert_eq!(
            resolve_include(Path::new("specs/a/b.idl"), "../c.idl"),
            PathBuf::from("specs/c.idl")
        );
        assert_eq!(
            resolve_include(Path::new("pilot.gen"), "./x.idl"),
            PathBuf::from("x.idl")
        );
    }

    #[test]
    fn memory_loader_reports_directories_and_missing_files() {
        let l = MemoryLoader::new().with("d/a.idl", "");
        assert_eq!(l.load(Path::new("d/a.idl")), Ok(String::new()));
        assert_eq!(l.load(Path::new("d")), Err(LoadError::IsDirectory));
        assert_eq!(l.load(Path::new("e.idl")), Err(LoadError::NotFound));
    }
}
