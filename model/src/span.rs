//! Source positions: the global byte-offset [`Span`] carried by every AST and
//! model node, and the [`SourceMap`] that owns the text of every loaded file.
//!
//! All files of one check share a single offset space (as in rustc): file *n*
//! occupies `[base_n, base_n + len_n]`, with a one-byte gap between files, so
//! a `Span` alone identifies its file. Nothing outside `gen-frontend/` ever sees a
//! pest type; spans are converted at the parser boundary.

use std::path::{Path, PathBuf};

/// A half-open byte range `[start, end)` in the global offset space of a
/// [`SourceMap`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub struct Span {
    /// First byte (global offset).
    pub start: u32,
    /// One past the last byte (global offset).
    pub end: u32,
}

impl Span {
    /// A span from global offsets.
    pub const fn new(start: u32, end: u32) -> Self {
        Self { start, end }
    }

    /// An empty span at `offset`.
    pub const fn point(offset: u32) -> Self {
        Self::new(offset, offset)
    }

    /// Length in bytes.
    pub const fn len(self) -> u32 {
        self.end.saturating_sub(self.start)
    }

    /// True for an empty span.
    pub const fn is_empty(self) -> bool {
        self.end <= self.start
    }

    /// The smallest span covering both.
    pub fn to(self, other: Span) -> Span {
        Span::new(self.start.min(other.start), self.end.max(other.end))
    }
}

/// Index of a file in a [`SourceMap`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct FileId(pub u32);

/// One loaded file: its path as the user gave it, its text and line index.
#[derive(Debug, Clone)]
pub struct SourceFile {
    /// Path for display (relative as given on the command line or include).
    pub path: PathBuf,
    /// The file's text.
    pub text: String,
    /// Global offset of the file's first byte.
    pub base: u32,
    line_starts: Vec<u32>,
}

/// A path as shown to people: with `/` separators on every platform.
pub fn display_path(path: &Path) -> String {
    path.to_string_lossy().replace('\\', "/")
}

impl SourceFile {
    /// The path as a display string with `/` separators.
    pub fn display_path(&self) -> String {
        display_path(&self.path)
    }

    /// 1-based line and column (in characters) of a local byte offset.
    pub fn line_col(&self, local: u32) -> (usize, usize) {
        let line = match self.line_starts.binary_search(&local) {
            Ok(i) => i,
            Err(i) => i.saturating_sub(1),
        };
        let start = self.line_starts.get(line).copied().unwrap_or(0) as usize;
        let end = (local as usize).min(self.text.len());
        let col = self
            .text
            .get(start..end)
            .map_or(end.saturating_sub(start), |s| s.chars().count());
        (line + 1, col + 1)
    }

    /// The byte offset (local) where the 1-based line `line` starts.
    pub fn line_start(&self, line: usize) -> Option<usize> {
        let at = self.line_starts.get(line.checked_sub(1)?)?;
        Some(*at as usize)
    }

    /// The text of the 1-based line `line`, without its newline.
    pub fn line_text(&self, line: usize) -> &str {
        let Some(&start) = self.line_starts.get(line.saturating_sub(1)) else {
            return "";
        };
        let rest = self.text.get(start as usize..).unwrap_or("");
        rest.split('\n').next().unwrap_or("").trim_end_matches('\r')
    }
}

/// A span resolved to its file: file id and local byte offsets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Located {
    /// The file holding the span.
    pub file: FileId,
    /// Local byte offset of the start.
    pub offset: u32,
    /// Length in bytes.
    pub length: u32,
}

/// Every file loaded for one check, in load order (the checked file first).
#[derive(Debug, Clone, Default)]
pub struct SourceMap {
    files: Vec<SourceFile>,
}

impl SourceMap {
    /// An empty map.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a file and returns its id; its base follows the previous file.
    pub fn add(&mut self, path: impl AsRef<Path>, text: String) -> FileId {
        let base = self.files.last().map_or(0, |f| {
            f.base
                .saturating_add(to_u32(f.text.len()))
                .saturating_add(1)
        });
        let mut line_starts = vec![0];
        line_starts.extend(
            text.bytes()
                .enumerate()
                .filter(|&(_, b)| b == b'\n')
                .map(|(i, _)| u32::try_from(i + 1).unwrap_or(u32::MAX)),
        );
        let id = FileId(to_u32(self.files.len()));
        self.files.push(SourceFile {
            path: path.as_ref().to_path_buf(),
            text,
            base,
            line_starts,
        });
        id
    }

    /// The file with this id.
    pub fn file(&self, id: FileId) -> Option<&SourceFile> {
        self.files.get(id.0 as usize)
    }

    /// All files with their ids, in load order.
    pub fn files(&self) -> impl Iterator<Item = (FileId, &SourceFile)> {
        self.files
            .iter()
            .enumerate()
            .map(|(i, f)| (FileId(to_u32(i)), f))
    }

    /// The file a global offset falls in.
    pub fn file_of(&self, offset: u32) -> Option<FileId> {
        let idx = self.files.partition_point(|f| f.base <= offset);
        idx.checked_sub(1).map(|i| FileId(to_u32(i)))
    }

    /// Resolves a global span to its file and local offsets.
    pub fn locate(&self, span: Span) -> Option<Located> {
        let file = self.file_of(span.start)?;
        let f = self.file(file)?;
        let offset = span.start - f.base;
        let max = to_u32(f.text.len()).saturating_sub(offset);
        Some(Located {
            file,
            offset,
            length: span.len().min(max),
        })
    }

    /// The source text a span covers ("" when out of range).
    pub fn slice(&self, span: Span) -> &str {
        self.locate(span)
            .and_then(|l| {
                let f = self.file(l.file)?;
                f.text
                    .get(l.offset as usize..(l.offset + l.length) as usize)
            })
            .unwrap_or("")
    }

    /// The global span of a whole file.
    pub fn file_span(&self, id: FileId) -> Span {
        self.file(id).map_or(Span::default(), |f| {
            Span::new(f.base, f.base + to_u32(f.text.len()))
        })
    }
}

/// Converts a length or index to `u32`, saturating (files are < 4 GiB).
pub(crate) fn to_u32(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_get_disjoint_offset_ranges() {
        let mut map = SourceMap::new();
        let a = map.add("a.gen", "abc\ndef".into());
        let b = map.add("b.idl", "xyz".into());
        assert_eq!(map.file_of(0), Some(a));
        assert_eq!(map.file_of(7), Some(a));
        assert_eq!(map.file_of(8), Some(b));
        let loc = map.locate(Span::new(9, 10)).unwrap();
        assert_eq!((loc.file, loc.offset, loc.length), (b, 1, 1));
        assert_eq!(map.slice(Span::new(9, 11)), "yz");
    }

    #[test]
    fn line_and_column_are_one_based_in_characters() {
        let mut map = SourceMap::new();
        let a = map.add("a.gen", "ab\né x\n".into());
        let f = map.file(a).unwrap();
        assert_eq!(f.line_col(0), (1, 1));
        assert_eq!(f.line_col(3), (2, 1));
        // 'é' is two bytes: the 'x' after "é " is column 3.
        assert_eq!(f.line_col(6), (2, 3));
        assert_eq!(f.line_text(2), "é x");
    }
}
