//! The GenoM3 front end of genom-check: reads a GenoM3 `.gen` file (the
//! dialect of LAAS-CNRS's `genom3`) with the files it includes, and lowers it
//! into the one resolved model, [`genom_model::component::Component`].
//!
//! # API
//!
//! - [`load()`]`(path, &Genom3Options) -> Result<Genom3Return, LoadError>`:
//!   the whole pipeline on the file system (fails only when `path` itself
//!   cannot be read). [`load_text`] takes the text already read,
//!   [`load_with`] a [`Loader`] and the text.
//! - [`Genom3Options`]: `include_dirs` (the `-I` folders, in order),
//!   `use_env_include_path` (also search `GENOM_INCLUDE_PATH`; on by
//!   default), `wcet_file`.
//! - [`Genom3Return`]: `sources` (one `FileId` per file: the checked file
//!   first, then its includes in load order, then the built-in `genom`
//!   interface, then the WCET file), `component` (`None` when the files
//!   define no component), `diagnostics` (sorted, deduplicated), `pragmas`
//!   (`#pragma require/provides/masquerade`, in order), `is_interface_only`
//!   (no component but interfaces or IDL definitions, and no syntax error:
//!   not an error, as in genom3; only a file with nothing at all gets
//!   `missing-component`), `ast`.
//! - The lowered component follows the mapping documented in
//!   `genom_model::component::genom3` (tasks → threads, activities →
//!   services with one codel per state, functions/attributes → control-only
//!   services, `ids` → one IDS structure, ports → import/export
//!   structures); GenoM3-only facts are in `Component::genom3`.
//! - [`Genom3Return::is_complete`]: false when a file is missing or does not
//!   parse; resolution diagnostics are then left out (they would only be
//!   the cascade of the missing names) and the component may be partial.
//! - [`looks_like_genom3`]`(text) -> bool`: dialect detection by syntax.
//! - [`add_wcet_file`], [`wcet::parse_wcet`], [`wcet::apply_wcets`]: the
//!   WCET side file (`OWNER.STATE DURATION` lines).
//! - [`explain::explanation`]: long texts of the codes this crate adds.
//! - [`Genom3Frontend`]: all of this behind the one front-end interface,
//!   [`genom_model::frontend::Frontend`] (the WCET file read through the
//!   same loader as the includes).
//!
//! # Pipeline
//!
//! `load.rs` reads files and includes (search order: the including file's
//! folder, each `-I` folder, then `GENOM_INCLUDE_PATH`), `preprocess.rs`
//! handles directives in process keeping offsets exact, `grammar.pest` +
//! `build.rs` give one AST per file, `lower/` resolves names into the model
//! and runs GenoM3's own static checks, `wcet.rs` reads WCETs. A diagnostic
//! in an included file points into that file and carries the include chain
//! as secondary labels.

pub mod ast;
mod build;
mod builtin;
mod detect;
mod diagnostics;
pub mod explain;
mod frontend;
mod grammar;
pub mod load;
pub mod lower;
pub mod preprocess;
mod syntax;
pub mod wcet;
pub mod wcet_template;

use std::path::{Path, PathBuf};

use genom_model::component::Component;
use genom_model::limits::Watch;
use genom_model::{Code, Diagnostic, FileId, SourceMap, Span, sort_diagnostics};

pub use detect::looks_like_genom3;
pub use frontend::Genom3Frontend;
pub use load::{FsLoader, LoadError, Loader, MemoryLoader};
pub use preprocess::Pragma;
pub use wcet_template::wcet_template;

/// Options of a GenoM3 load. The default searches no `-I` folder, does
/// search `GENOM_INCLUDE_PATH`, and reads no WCET file.
#[derive(Debug, Clone)]
pub struct Genom3Options {
    /// `-I` folders, searched in order after the including file's folder.
    pub include_dirs: Vec<PathBuf>,
    /// Also search the folders of the `GENOM_INCLUDE_PATH` environment
    /// variable (`:`-separated) after `include_dirs`.
    pub use_env_include_path: bool,
    /// A WCET side file to apply to the component.
    pub wcet_file: Option<PathBuf>,
    /// When to stop reading (`--timeout`, `--max-memory`): looked at every
    /// 64 KiB of text.
    pub watch: Watch,
}

impl Default for Genom3Options {
    fn default() -> Self {
        Self {
            include_dirs: Vec::new(),
            use_env_include_path: true,
            wcet_file: None,
            watch: Watch::unlimited(),
        }
    }
}

/// What a GenoM3 load produces (`XReturn { value, diagnostics }`).
#[derive(Debug, Default)]
pub struct Genom3Return {
    /// Every loaded file, the checked file first.
    pub sources: SourceMap,
    /// The lowered component; `None` for an interface-only file, or when
    /// the file has no component.
    pub component: Option<Component>,
    /// Every diagnostic, sorted.
    pub diagnostics: Vec<Diagnostic>,
    /// `#pragma` lines in preprocessor order.
    pub pragmas: Vec<Pragma>,
    /// True when the files define interfaces and IDL but no component.
    pub is_interface_only: bool,
    /// The syntax trees.
    pub ast: ast::Ast,
}

impl Genom3Return {
    /// True when every file was found and parsed, so that the component is
    /// whole and its resolution diagnostics were reported. When false, the
    /// component (if any) is partial and only the load's own diagnostics
    /// (syntax, includes) are reported.
    pub fn is_complete(&self) -> bool {
        !self.diagnostics.iter().any(|d| {
            matches!(
                d.code,
                Code::Syntax | Code::IncludeNotFound | Code::IncludeCycle | Code::Incomplete
            )
        })
    }
}

impl Genom3Options {
    /// The folders searched for includes after the including file's: every
    /// `-I` folder in order, then those of `GENOM_INCLUDE_PATH` (when used).
    pub fn search_path(&self) -> Vec<PathBuf> {
        let mut search = self.include_dirs.clone();
        if self.use_env_include_path {
            if let Some(var) = std::env::var_os("GENOM_INCLUDE_PATH") {
                search.extend(std::env::split_paths(&var).filter(|p| !p.as_os_str().is_empty()));
            }
        }
        search
    }
}

/// Loads a GenoM3 file from the file system.
pub fn load(path: &Path, options: &Genom3Options) -> Result<Genom3Return, LoadError> {
    let text = FsLoader.load(path)?;
    load_text(path, text, options)
}

/// [`load`] of a file already read as `text` (includes and the WCET file
/// still come from the file system). Fails only when the WCET file cannot
/// be read.
pub fn load_text(
    path: &Path,
    text: String,
    options: &Genom3Options,
) -> Result<Genom3Return, LoadError> {
    let search = options.search_path();
    let mut out = load_watched(path, text, &search, &FsLoader, options.watch);
    if let Some(wcet_path) = &options.wcet_file {
        let text = FsLoader.load(wcet_path)?;
        add_wcet_file(&mut out, wcet_path, text);
    }
    Ok(out)
}

/// Reads `text` as `t.gen` and, given, `wcet` as its WCET file `t.wcet`,
/// without the environment's include path: the component when nothing
/// is an error, else the errors. For tests and tools that need a clean
/// component from a snippet.
pub fn load_clean(text: &str, wcet: Option<&str>) -> Result<Component, String> {
    let options = Genom3Options {
        use_env_include_path: false,
        ..Genom3Options::default()
    };
    let mut out =
        load_text(Path::new("t.gen"), text.to_owned(), &options).map_err(|e| e.to_string())?;
    if let Some(w) = wcet {
        add_wcet_file(&mut out, Path::new("t.wcet"), w.to_owned());
    }
    let errors: Vec<&Diagnostic> = out
        .diagnostics
        .iter()
        .filter(|d| d.severity == genom_model::Severity::Error)
        .collect();
    if !errors.is_empty() {
        return Err(format!("{errors:#?}"));
    }
    out.component.ok_or_else(|| "no component".to_owned())
}

/// Reads a WCET side file (already loaded as `text`) into `out`: the file
/// joins `out.sources`, its entries set the component's codel WCETs, and
/// its `bad-wcet` errors join `out.diagnostics`.
pub fn add_wcet_file(out: &mut Genom3Return, path: &Path, text: String) {
    let file = out.sources.add(path, text);
    let parsed = wcet::parse_wcet(&out.sources, file);
    out.diagnostics.extend(parsed.diagnostics);
    if let Some(c) = out.component.as_mut() {
        out.diagnostics
            .extend(wcet::apply_wcets(c, &parsed.entries));
    }
    sort_diagnostics(&mut out.diagnostics);
}

/// Loads already-read text as the checked file; includes go through
/// `loader` and are searched in `search` after the including file's folder.
pub fn load_with(
    path: &Path,
    text: String,
    search: &[PathBuf],
    loader: &dyn Loader,
) -> Genom3Return {
    load_watched(path, text, search, loader, Watch::unlimited())
}

/// [`load_with`], reading until a limit of `watch` passes at most: the
/// rest is not read, an `incomplete` error says where reading stopped, and
/// nothing is lowered.
pub fn load_watched(
    path: &Path,
    text: String,
    search: &[PathBuf],
    loader: &dyn Loader,
    watch: Watch,
) -> Genom3Return {
    let loaded = load::load_all(
        path,
        text,
        search,
        loader,
        &[(builtin::PATH, builtin::GENOM_GEN)],
        watch,
    );
    let root = FileId(0);
    let builtin =
        FileId(u32::try_from(loaded.sources.files().count().saturating_sub(1)).unwrap_or(0));
    let lowered = lower::lower(&loaded.ast, builtin, &watch);
    let mut diagnostics = loaded.diagnostics;
    // With a file missing or unparsed, names it would define are unknown:
    // report only what stops the load, not the cascade.
    let complete = !diagnostics.iter().any(|d| {
        matches!(
            d.code,
            Code::Syntax | Code::IncludeNotFound | Code::IncludeCycle | Code::Incomplete
        )
    });
    if complete {
        diagnostics.extend(lowered.diagnostics);
    }
    add_include_chains(&loaded.sources, &loaded.included_at, &mut diagnostics);
    sort_diagnostics(&mut diagnostics);
    // As genom3 does, a file with interfaces or IDL only is accepted: only a
    // file with nothing at all (no component, interface or definition)
    // lacks a component.
    let empty = !ast_has_own_statement(&loaded.ast, builtin);
    if empty && !has_errors(&diagnostics) {
        let span = loaded.sources.file_span(root);
        diagnostics.push(diagnostics::missing_component(Span::point(span.start)));
    }
    Genom3Return {
        sources: loaded.sources,
        is_interface_only: !lowered.has_component && !empty && !has_errors(&diagnostics),
        component: lowered.component,
        diagnostics,
        pragmas: loaded.pragmas,
        ast: loaded.ast,
    }
}

/// Whether some statement comes from a file other than the built-in one.
fn ast_has_own_statement(ast: &ast::Ast, builtin: FileId) -> bool {
    ast.statements.iter().any(|(f, _)| *f != builtin)
}

fn has_errors(d: &[Diagnostic]) -> bool {
    d.iter().any(|d| d.code == Code::Syntax)
}

/// Appends "included from here" labels (innermost first) to diagnostics
/// whose primary span lies in an included file.
fn add_include_chains(
    sources: &SourceMap,
    included_at: &std::collections::BTreeMap<FileId, Span>,
    diagnostics: &mut [Diagnostic],
) {
    for d in diagnostics {
        let mut file = sources.file_of(d.span().start);
        let mut depth = 0;
        while let Some(at) = file.and_then(|f| included_at.get(&f)) {
            *d = d.clone().with_label(*at, "included from here");
            file = sources.file_of(at.start);
            depth += 1;
            if depth > 64 {
                break;
            }
        }
    }
}
