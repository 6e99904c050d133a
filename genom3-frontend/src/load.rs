//! Loading: reads the checked file and every file it includes (each with its
//! own [`FileId`] in the [`SourceMap`], so spans stay per file), runs the
//! preprocessor on each, parses each file's blanked text one statement at a
//! time, and orders the statements as a C preprocessor would (an included
//! file's statements at its `#include`).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use genom_model::limits::Watch;
use genom_model::nesting;
use genom_model::{Diagnostic, FileId, SourceMap, Span};
use pest::Parser as _;

use crate::ast::{Ast, Statement};
use crate::build::Builder;
use crate::grammar::{Genom3Parser, Rule};
use crate::preprocess::{self, Include, Pragma};
use crate::{diagnostics, syntax};

/// Syntax errors reported per file before giving up on it.
pub const MAX_SYNTAX_ERRORS: usize = 50;

pub use genom_model::loader::{FsLoader, LoadError, Loader, MemoryLoader};

/// What loading produces, before lowering.
#[derive(Debug, Default)]
pub struct Loaded {
    /// Every file.
    pub sources: SourceMap,
    /// Statements of all files, in preprocessor order.
    pub ast: Ast,
    /// Every `#pragma`, in preprocessor order.
    pub pragmas: Vec<Pragma>,
    /// Preprocessor, include and syntax diagnostics.
    pub diagnostics: Vec<Diagnostic>,
    /// For each included file, the `#include` line that first loaded it.
    pub included_at: BTreeMap<FileId, Span>,
}

struct Session<'a> {
    loader: &'a dyn Loader,
    search: &'a [PathBuf],
    out: Loaded,
    /// Files being loaded (cycle detection), by normalised path.
    stack: Vec<PathBuf>,
    /// Per file: its statements (with start offset) and its includes (offset,
    /// loaded file).
    files: BTreeMap<FileId, FileParts>,
    /// The limits (`--timeout`, `--max-memory`).
    watch: Watch,
    /// A limit passed: nothing more is read.
    stopped: bool,
}

/// How much text is parsed between two looks at the clock and the heap: a
/// file smaller than this is always read whole.
/// Deepest bracket nesting accepted (modules, structs, parentheses,
/// `sequence<…>`), checked over a whole file before it is parsed. Real
/// components nest fewer than ten levels; the bound keeps every recursive
/// step (parsing, building, lowering, rendering) far from the stack's end
/// and its memory linear. Constant expressions have their own, lower bound
/// (256 parentheses, see the builder).
pub const MAX_NESTING: usize = 1024;

const CLOCK_BYTES: usize = 64 * 1024;

#[derive(Default)]
struct FileParts {
    statements: Vec<(u32, Statement)>,
    includes: Vec<(u32, FileId)>,
}

/// Loads `path` (already read as `text`) and everything it includes, then
/// `extra` virtual files (the built-in `genom` interface) after it.
pub fn load_all(
    path: &Path,
    text: String,
    search: &[PathBuf],
    loader: &dyn Loader,
    extra: &[(&str, &str)],
    watch: Watch,
) -> Loaded {
    let mut session = Session {
        loader,
        search,
        out: Loaded::default(),
        stack: Vec::new(),
        files: BTreeMap::new(),
        watch,
        stopped: false,
    };
    let mut defines = preprocess::Macros::new();
    let root = session.out.sources.add(path, text);
    session.stack.push(normalise(path));
    session.file(root, &mut defines);
    session.stack.pop();
    let mut roots = vec![root];
    for (name, text) in extra {
        let id = session.out.sources.add(name, (*text).to_owned());
        session.file(id, &mut defines);
        roots.push(id);
    }
    let mut statements = Vec::new();
    for r in roots {
        session.flatten(r, &mut statements);
    }
    session.out.ast = Ast { statements };
    session.out
}

impl Session<'_> {
    fn file(&mut self, id: FileId, defines: &mut preprocess::Macros) {
        let Some(file) = self.out.sources.file(id) else {
            return;
        };
        let (text, base, dir) = (
            file.text.clone(),
            file.base,
            file.path
                .parent()
                .map(Path::to_path_buf)
                .unwrap_or_default(),
        );
        let mut includes = Vec::new();
        let scanned = preprocess::scan(&text, base, defines, &mut |inc, defs| {
            if let Some(child) = self.include(&dir, inc, defs) {
                includes.push((inc.span.start, child));
            }
        });
        self.out.pragmas.extend(scanned.pragmas);
        self.out.diagnostics.extend(scanned.diagnostics);
        let statements = match nesting::excessive_nesting(&scanned.text, MAX_NESTING) {
            Some(at) => {
                let at = base + u32::try_from(at).unwrap_or(u32::MAX);
                let span = Span::new(at, at.saturating_add(1));
                self.out
                    .diagnostics
                    .push(nesting::too_deep(span, MAX_NESTING));
                Vec::new()
            }
            None => self.parse(&scanned.text, base),
        };
        self.files.insert(
            id,
            FileParts {
                statements,
                includes,
            },
        );
    }

    fn include(
        &mut self,
        dir: &Path,
        inc: &Include,
        defines: &mut preprocess::Macros,
    ) -> Option<FileId> {
        // Expanding includes looks at the clock and the memory too: a chain
        // of thousands of files, or a diamond of unguarded includes (2^n
        // inclusions), stops at the limit like parsing does.
        if self.stopped {
            return None;
        }
        if let Some(limit) = self.watch.exceeded() {
            self.stopped = true;
            self.out
                .diagnostics
                .push(genom_model::limits::parsing_stopped(inc.span, limit));
            return None;
        }
        let mut searched = Vec::new();
        let mut found = None;
        let written = Path::new(&inc.path);
        let candidates = std::iter::once(dir.to_path_buf()).chain(self.search.iter().cloned());
        for folder in candidates {
            let candidate = if written.is_absolute() {
                written.to_path_buf()
            } else {
                folder.join(written)
            };
            searched.push(display_dir(&folder));
            if self.loader.exists(&candidate) {
                found = Some(candidate);
                break;
            }
        }
        let Some(path) = found else {
            self.out.diagnostics.push(diagnostics::include_not_found(
                inc.span, &inc.path, &searched,
            ));
            return None;
        };
        let key = normalise(&path);
        if self.stack.contains(&key) {
            self.out
                .diagnostics
                .push(diagnostics::include_cycle(inc.span, &inc.path));
            return None;
        }
        let text = match self.loader.load(&path) {
            Ok(t) => t,
            Err(e) => {
                self.out.diagnostics.push(diagnostics::include_unreadable(
                    inc.span,
                    &inc.path,
                    &e.to_string(),
                ));
                return None;
            }
        };
        let id = self.out.sources.add(&path, text);
        self.out.included_at.insert(id, inc.span);
        self.stack.push(key);
        self.file(id, defines);
        self.stack.pop();
        Some(id)
    }

    /// Parses blanked text one statement at a time, resuming after errors.
    fn parse(&mut self, text: &str, base: u32) -> Vec<(u32, Statement)> {
        let mut out = Vec::new();
        let mut pos = 0usize;
        let mut errors = 0usize;
        let mut next_look = CLOCK_BYTES;
        while pos < text.len() && !self.stopped {
            if pos >= next_look {
                next_look = pos + CLOCK_BYTES;
                if let Some(limit) = self.watch.exceeded() {
                    self.stopped = true;
                    let at = Span::point(base + u32::try_from(pos).unwrap_or(u32::MAX));
                    self.out
                        .diagnostics
                        .push(genom_model::limits::parsing_stopped(at, limit));
                    break;
                }
            }
            let rest = &text[pos..];
            let here = base + u32::try_from(pos).unwrap_or(u32::MAX);
            match Genom3Parser::parse(Rule::next_statement, rest) {
                Ok(mut pairs) => {
                    let Some(top) = pairs.next() else { break };
                    let Some(stmt) = top.into_inner().find(|p| p.as_rule() == Rule::statement)
                    else {
                        break;
                    };
                    let end = stmt.as_span().end();
                    let start = here + u32::try_from(stmt.as_span().start()).unwrap_or(0);
                    let builder = Builder { base: here };
                    if let Some(s) = builder.statement(&stmt) {
                        out.push((start, s));
                    }
                    if end == 0 {
                        break;
                    }
                    pos += end;
                }
                Err(err) => {
                    let (diag, at) = syntax::error(&err, rest, here);
                    self.out.diagnostics.push(diag);
                    errors += 1;
                    if errors >= MAX_SYNTAX_ERRORS {
                        break;
                    }
                    pos += syntax::resume_after(rest, at).max(1);
                }
            }
        }
        out
    }

    fn flatten(&mut self, id: FileId, into: &mut Vec<(FileId, Statement)>) {
        let Some(parts) = self.files.remove(&id) else {
            return;
        };
        let mut includes = parts.includes.into_iter().peekable();
        for (offset, stmt) in parts.statements {
            while let Some((_, child)) = includes.next_if(|(at, _)| *at < offset) {
                self.flatten(child, into);
            }
            into.push((id, stmt));
        }
        for (_, child) in includes {
            self.flatten(child, into);
        }
    }
}

/// A path without `.` components, for cycle detection.
fn normalise(path: &Path) -> PathBuf {
    path.components()
        .filter(|c| !matches!(c, std::path::Component::CurDir))
        .collect()
}

fn display_dir(p: &Path) -> String {
    let s = genom_model::span::display_path(p);
    if s.is_empty() { ".".to_owned() } else { s }
}
