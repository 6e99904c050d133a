//! The genom-check front end of the LANGUAGE.md dialect: reads a `.gen`
//! file and the IDL files it includes, and returns the AST of every file
//! with all syntax diagnostics (`ParserReturn { sources, ast, diagnostics }`,
//! as in oxc); then lowers the AST into the component model ([`resolve`],
//! [`lower`]), with the diagnostics resolution raises ([`checks`]).
//! [`GenFrontend`] is this front-end behind the one front-end interface,
//! [`genom_model::frontend::Frontend`].
//!
//! Parsing never stops at the first error: each top-level item is parsed on
//! its own and, after an error, parsing resumes at the next line that starts
//! an item. Includes are resolved relative to the including file; cycles and
//! missing files are diagnostics that point at the `include` line.

pub mod ast;
mod build;
pub mod checks;
pub mod diagnostics;
mod frontend;
mod grammar;
pub mod literal;
pub use genom_model::loader;
pub mod resolve;
mod syntax;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use genom_model::component::Component;
use genom_model::limits::{Limit, Watch};
use genom_model::span::display_path as display;
use genom_model::{Code, Diagnostic, FileId, SourceMap, Span, sort_diagnostics};
use pest::Parser as _;

pub use ast::Ast;
pub use frontend::GenFrontend;
pub use loader::{FsLoader, LoadError, Loader, MemoryLoader};
pub use resolve::{ResolveReturn, resolve};
pub use syntax::MAX_NESTING;

use ast::{Item, Unit};
use build::{Builder, to_u32};
use grammar::{GenParser, Rule};

/// Syntax errors reported per file before parsing gives up on it.
pub const MAX_SYNTAX_ERRORS: usize = 50;

/// What the parser produces: every loaded file, the AST of each, and all
/// diagnostics (sorted).
#[derive(Debug, Clone, Default)]
pub struct ParserReturn {
    /// The checked file first, then included files.
    pub sources: SourceMap,
    /// The trees.
    pub ast: Ast,
    /// Syntax, include and literal diagnostics.
    pub diagnostics: Vec<Diagnostic>,
}

impl ParserReturn {
    /// True when every file parsed completely and every include was found,
    /// so that semantic checks see the whole component.
    pub fn is_complete(&self) -> bool {
        !self.diagnostics.iter().any(|d| {
            matches!(
                d.code,
                Code::Syntax | Code::IncludeNotFound | Code::IncludeCycle | Code::Incomplete
            )
        })
    }
}

/// Parses `path` and everything it includes. Fails only when `path` itself
/// cannot be read (the caller reports that as an I/O problem).
pub fn parse_file(path: &Path, loader: &dyn Loader) -> Result<ParserReturn, LoadError> {
    let text = loader.load(path)?;
    Ok(parse_source(path, text, loader))
}

/// Parses already-loaded text as the checked file; includes go through
/// `loader`.
pub fn parse_source(path: &Path, text: String, loader: &dyn Loader) -> ParserReturn {
    parse_source_until(path, text, loader, Watch::unlimited())
}

/// [`parse_source`], stopping between two items once a limit of `watch`
/// passes: what is left is not read, and an `incomplete` error says where
/// parsing stopped.
pub fn parse_source_until(
    path: &Path,
    text: String,
    loader: &dyn Loader,
    watch: Watch,
) -> ParserReturn {
    let mut session = Session {
        loader,
        out: ParserReturn::default(),
        stack: Vec::new(),
        loaded: BTreeMap::new(),
        watch,
        stopped: false,
    };
    let file = session.out.sources.add(path, text);
    session.stack.push((loader.identity(path), display(path)));
    session.loaded.insert(loader.identity(path), file);
    session.load_unit(file, false);
    let mut out = session.out;
    sort_diagnostics(&mut out.diagnostics);
    out
}

/// Parses a single `.gen` text with no includes available (tests, fuzzing).
pub fn parse_str(path: &str, text: &str) -> ParserReturn {
    parse_source(Path::new(path), text.to_owned(), &MemoryLoader::new())
}

/// What the front end produces: every loaded file, the AST of each, the
/// lowered model and all diagnostics found on the way.
#[derive(Debug, Clone, Default)]
pub struct LowerReturn {
    /// The checked file first, then included files.
    pub sources: SourceMap,
    /// The trees.
    pub ast: Ast,
    /// Syntax, include and literal diagnostics (sorted), then resolution,
    /// structure and type diagnostics (in the order found).
    pub diagnostics: Vec<Diagnostic>,
    /// The resolved model, when every file parsed completely and every
    /// include was found (possibly partial when resolution found errors).
    pub model: Option<Component>,
    /// Whether the checked file has a `component` item.
    pub has_component: bool,
}

/// Parses `path` and everything it includes, then resolves it. Fails only
/// when `path` itself cannot be read.
pub fn lower_file(path: &Path, loader: &dyn Loader) -> Result<LowerReturn, LoadError> {
    let text = loader.load(path)?;
    Ok(lower(path, text, loader))
}

/// Parses already-loaded text as the checked file (includes go through
/// `loader`) and, when every file parsed completely, resolves it into the
/// component model.
pub fn lower(path: &Path, text: String, loader: &dyn Loader) -> LowerReturn {
    lower_until(path, text, loader, Watch::unlimited())
}

/// [`lower`], parsing until a limit of `watch` passes at most (see
/// [`parse_source_until`]); a stopped parse is not resolved.
pub fn lower_until(path: &Path, text: String, loader: &dyn Loader, watch: Watch) -> LowerReturn {
    let parsed = parse_source_until(path, text, loader, watch);
    let mut diagnostics = parsed.diagnostics.clone();
    let mut model = None;
    let mut has_component = false;
    if parsed.is_complete() {
        let start = parsed
            .sources
            .file(FileId(0))
            .map_or(Span::default(), |f| Span::point(f.base));
        let mut resolved = resolve(&parsed.ast, start);
        // An IDL file given alone is checked for its types; it has no
        // component to miss.
        if is_idl(path) {
            resolved
                .diagnostics
                .retain(|d| d.code != Code::MissingComponent);
        }
        diagnostics.extend(resolved.diagnostics);
        has_component = resolved.has_component;
        model = Some(resolved.component);
    }
    LowerReturn {
        sources: parsed.sources,
        ast: parsed.ast,
        diagnostics,
        model,
        has_component,
    }
}

/// Whether `path` names an IDL file (`.idl`, any case).
fn is_idl(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("idl"))
}

/// How much text is parsed between two looks at the clock and the heap: a
/// file smaller than this is never cut by `--timeout` (parsing it takes
/// milliseconds).
const CLOCK_BYTES: usize = 64 * 1024;

struct Session<'l> {
    loader: &'l dyn Loader,
    out: ParserReturn,
    /// Files being parsed, outermost first: identity and display path.
    stack: Vec<(PathBuf, String)>,
    /// Files already loaded, by identity.
    loaded: BTreeMap<PathBuf, FileId>,
    /// When to stop parsing (`--timeout`, `--max-memory`).
    watch: Watch,
    /// A limit passed: nothing more is parsed.
    stopped: bool,
}

impl Session<'_> {
    /// Parses one file and, depth-first, the files it includes.
    fn load_unit(&mut self, file: FileId, is_idl: bool) {
        let index = self.out.ast.units.len();
        self.out.ast.units.push(Unit {
            file,
            is_idl,
            items: Vec::new(),
        });
        let mut items = if self.stopped {
            Vec::new()
        } else {
            self.parse_items(file, is_idl)
        };
        for item in &mut items {
            if let Item::Include(include) = item {
                include.file = self.include(file, &include.path.value, include.path.span);
            }
        }
        if let Some(unit) = self.out.ast.units.get_mut(index) {
            unit.items = items;
        }
    }

    fn include(&mut self, from: FileId, written: &str, span: Span) -> Option<FileId> {
        let including = self
            .out
            .sources
            .file(from)
            .map(|f| f.path.clone())
            .unwrap_or_default();
        let path = loader::resolve_include(&including, written);
        let identity = self.loader.identity(&path);
        if let Some(start) = self.stack.iter().position(|(id, _)| *id == identity) {
            let mut chain: Vec<String> =
                self.stack[start..].iter().map(|(_, d)| d.clone()).collect();
            chain.push(display(&path));
            self.out
                .diagnostics
                .push(diagnostics::include_cycle(span, &display(&path), &chain));
            return None;
        }
        if let Some(&file) = self.loaded.get(&identity) {
            return Some(file);
        }
        let text = match self.loader.load(&path) {
            Ok(text) => text,
            Err(e) => {
                self.out.diagnostics.push(diagnostics::include_not_found(
                    span,
                    &display(&path),
                    &e.to_string(),
                ));
                return None;
            }
        };
        let file = self.out.sources.add(&path, text);
        self.loaded.insert(identity.clone(), file);
        self.stack.push((identity, display(&path)));
        self.load_unit(file, true);
        self.stack.pop();
        Some(file)
    }

    /// The limit that has just passed (then parsing stops for good).
    /// Looked at every [`CLOCK_BYTES`] of text, so that a small file is
    /// always read whole.
    fn limit_passed(&mut self) -> Option<Limit> {
        if self.stopped {
            return None;
        }
        let limit = self.watch.exceeded();
        self.stopped = limit.is_some();
        limit
    }

    /// Parses the items of one file, resuming after each syntax error.
    fn parse_items(&mut self, file: FileId, is_idl: bool) -> Vec<Item> {
        let Some(source) = self.out.sources.file(file) else {
            return Vec::new();
        };
        let (text, base) = (source.text.clone(), source.base);
        if let Some(at) = genom_model::nesting::excessive_nesting(&text, MAX_NESTING) {
            let span = Span::new(base + to_u32(at), base + to_u32(at) + 1);
            self.out
                .diagnostics
                .push(genom_model::nesting::too_deep(span, MAX_NESTING));
            return Vec::new();
        }
        let rule = if is_idl {
            Rule::next_idl_item
        } else {
            Rule::next_item
        };
        let mut items = Vec::new();
        let mut errors = 0;
        let mut pos = 0;
        let mut next_look = CLOCK_BYTES;
        while pos <= text.len() {
            if pos >= next_look {
                next_look = pos + CLOCK_BYTES;
                if let Some(limit) = self.limit_passed() {
                    let at = Span::point(base + to_u32(pos));
                    self.out
                        .diagnostics
                        .push(diagnostics::limit_reached(at, limit));
                    break;
                }
            }
            match parse_one(rule, &text, pos, base, &mut self.out.diagnostics) {
                Step::Item(item, end) => {
                    items.extend(item);
                    pos = end;
                }
                Step::End => break,
                Step::Error(d, at) => {
                    errors += 1;
                    if errors > MAX_SYNTAX_ERRORS {
                        self.out
                            .diagnostics
                            .push(diagnostics::too_many_errors(d.span(), errors - 1));
                        break;
                    }
                    self.out.diagnostics.push(d);
                    match syntax::resume_point(&text, at, syntax::item_indent(&text, pos)) {
                        Some(next) => pos = next,
                        None => break,
                    }
                }
            }
        }
        items
    }
}

enum Step {
    Item(Option<Item>, usize),
    End,
    Error(Diagnostic, usize),
}

/// Parses one item of `text` starting at byte `pos`.
fn parse_one(
    rule: Rule,
    text: &str,
    pos: usize,
    base: u32,
    diagnostics: &mut Vec<Diagnostic>,
) -> Step {
    let rest = &text[pos..];
    let start = base + to_u32(pos);
    match GenParser::parse(rule, rest) {
        Err(e) => {
            let (d, at) = syntax::convert(&e, rest, start);
            Step::Error(d, pos + at)
        }
        Ok(mut pairs) => {
            let Some(top) = pairs.next() else {
                return Step::End;
            };
            let mut builder = Builder::new(start, diagnostics);
            for p in top.into_inner() {
                if matches!(p.as_rule(), Rule::item | Rule::idl_item) {
                    let end = pos + p.as_span().end();
                    return Step::Item(builder.build_item(p), end.max(pos + 1));
                }
            }
            Step::End
        }
    }
}
