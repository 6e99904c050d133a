//! `genom-check.toml`: a project's configuration, found by walking up from
//! the checked file's folder (as ruff and clippy find theirs), or named with
//! `--config`. It gives defaults that command-line options override:
//!
//! ```toml
//! dialect = "genom3"                    # default --dialect
//! include = ["include", "../idl"]       # -I folders, from this file's folder
//!
//! [wcet]                                # --wcet file of each component file
//! "nhfc.gen" = "wcet/nhfc.wcet"
//!
//! [limits]
//! max-states = 1000000
//! timeout = "60s"
//! max-instances = 2
//!
//! [levels]                              # allow | warn | deny, per code
//! missing-wcet = "allow"
//! unpaused-loop = "deny"
//! ```
//!
//! Unknown keys, codes, levels and malformed values are errors pointing at
//! the TOML (exit 2). docs/configuration.md is the user's page.

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use genom_model::Code;
use serde::Deserialize;
use toml::Spanned;

/// The file name looked for.
pub const FILE_NAME: &str = "genom-check.toml";

/// What a code's diagnostics become.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Level {
    /// Not reported.
    Allow,
    /// Reported as warnings.
    Warn,
    /// Reported as errors.
    Deny,
}

/// A loaded configuration, paths resolved from its folder.
#[derive(Debug, Clone, Default)]
pub struct Config {
    /// Default dialect.
    pub dialect: Option<genom_model::Dialect>,
    /// Include folders (GenoM3), in order.
    pub include_dirs: Vec<PathBuf>,
    /// WCET file of each component file.
    pub wcet: BTreeMap<PathBuf, PathBuf>,
    /// `--max-states`.
    pub max_states: Option<usize>,
    /// `--timeout`.
    pub timeout: Option<std::time::Duration>,
    /// `--max-instances`.
    pub max_instances: Option<usize>,
    /// Levels by code.
    pub levels: BTreeMap<Code, Level>,
}

/// The file as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Raw {
    dialect: Option<Spanned<String>>,
    include: Option<Vec<String>>,
    wcet: Option<BTreeMap<String, String>>,
    limits: Option<RawLimits>,
    levels: Option<BTreeMap<Spanned<String>, Spanned<String>>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
struct RawLimits {
    max_states: Option<usize>,
    timeout: Option<Spanned<String>>,
    max_instances: Option<Spanned<usize>>,
}

/// A configuration that cannot be used, with where in its text.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
#[error("{message}")]
pub struct ConfigError {
    message: String,
    #[source_code]
    src: miette::NamedSource<String>,
    #[label("{label}")]
    span: Option<miette::SourceSpan>,
    label: String,
    #[help]
    help: Option<String>,
}

impl ConfigError {
    fn new(path: &Path, text: &str, span: Option<Range<usize>>, message: String) -> Box<Self> {
        Box::new(ConfigError {
            message,
            src: miette::NamedSource::new(path.display().to_string(), text.to_owned()),
            span: span.map(Into::into),
            label: "here".to_owned(),
            help: None,
        })
    }

    fn help(mut self: Box<Self>, help: Option<String>) -> Box<Self> {
        self.help = help;
        self
    }

    /// The error as the terminal shows it (a snippet of the TOML).
    pub fn render(&self) -> String {
        let mut out = String::new();
        let handler =
            miette::GraphicalReportHandler::new_themed(miette::GraphicalTheme::unicode_nocolor());
        if handler.render_report(&mut out, self).is_err() {
            return format!("error: {}", self.message);
        }
        format!("error: {}", out.trim_start_matches(['×', ' ']))
    }
}

/// The configuration for a file at `checked`: `explicit` if given, else
/// the first `genom-check.toml` in its folder or a parent. `Ok(None)` when
/// there is none.
pub fn for_file(
    checked: &Path,
    explicit: Option<&Path>,
) -> Result<Option<Config>, Box<ConfigError>> {
    let path = match explicit {
        Some(p) => p.to_path_buf(),
        None => match find(checked) {
            Some(p) => p,
            None => return Ok(None),
        },
    };
    let text = read_bounded(&path).map_err(|why| {
        ConfigError::new(
            &path,
            "",
            None,
            format!("cannot read `{}`: {why}", path.display()),
        )
    })?;
    parse(&path, &text).map(Some)
}

/// The most bytes a configuration file may hold.
const MAX_CONFIG_BYTES: u64 = 1 << 20;

/// The text of a configuration file: a regular file (not a FIFO or a
/// device, which could block or never end) of at most
/// [`MAX_CONFIG_BYTES`], in UTF-8.
fn read_bounded(path: &Path) -> Result<String, String> {
    use std::io::Read as _;
    let meta = std::fs::metadata(path).map_err(|e| e.to_string())?;
    if !meta.is_file() {
        return Err("it is not a regular file (a device, FIFO or socket)".to_owned());
    }
    if meta.len() > MAX_CONFIG_BYTES {
        return Err(format!("it is larger than {MAX_CONFIG_BYTES} bytes"));
    }
    let mut text = String::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(MAX_CONFIG_BYTES).read_to_string(&mut text))
        .map_err(|e| e.to_string())?;
    Ok(text)
}

/// The nearest `genom-check.toml` above `checked` (standard input: from
/// the current folder).
fn find(checked: &Path) -> Option<PathBuf> {
    let start = if genom_check::is_stdin(checked) {
        std::env::current_dir().ok()?
    } else {
        let abs = std::path::absolute(checked).ok()?;
        abs.parent()?.to_path_buf()
    };
    start
        .ancestors()
        .map(|d| d.join(FILE_NAME))
        // Any entry of that name counts, even one that cannot be read (a
        // symlink into an unreadable folder): reading it then fails with
        // exit 2, rather than its settings being silently ignored.
        .find(|p| p.symlink_metadata().is_ok())
}

/// Parses the text of a configuration file read from `path`.
pub fn parse(path: &Path, text: &str) -> Result<Config, Box<ConfigError>> {
    let raw: Raw = toml::from_str(text)
        .map_err(|e| ConfigError::new(path, text, e.span(), e.message().to_owned()))?;
    let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let err =
        |span: Range<usize>, message: String| ConfigError::new(path, text, Some(span), message);
    let dialect = match &raw.dialect {
        None => None,
        Some(d) => Some(match d.get_ref().as_str() {
            "gen" => genom_model::Dialect::Gen,
            "genom3" => genom_model::Dialect::Genom3,
            other => {
                return Err(err(d.span(), format!("unknown dialect `{other}`"))
                    .help(Some("the dialects are `gen` and `genom3`".to_owned())));
            }
        }),
    };
    let mut config = Config {
        dialect,
        include_dirs: raw.include.iter().flatten().map(|d| dir.join(d)).collect(),
        wcet: raw
            .wcet
            .iter()
            .flatten()
            .map(|(g, w)| (normal(&dir.join(g)), dir.join(w)))
            .collect(),
        ..Config::default()
    };
    if let Some(l) = &raw.limits {
        config.max_states = l.max_states;
        if let Some(t) = &l.timeout {
            let d = crate::cli::parse_duration(t.get_ref()).map_err(|m| err(t.span(), m))?;
            config.timeout = Some(d);
        }
        if let Some(n) = &l.max_instances {
            let n_text = n.get_ref().to_string();
            let v = crate::cli::parse_instances(&n_text).map_err(|m| err(n.span(), m))?;
            config.max_instances = Some(v);
        }
    }
    for (code, level) in raw.levels.iter().flatten() {
        let c = code_named(code.get_ref()).ok_or_else(|| {
            let names = Code::ALL.iter().map(|c| c.as_str());
            let hint = genom_model::diagnostic::closest(code.get_ref(), names)
                .map(|n| format!("did you mean `{n}`?"));
            err(code.span(), format!("unknown code `{}`", code.get_ref())).help(hint)
        })?;
        let l = match level.get_ref().as_str() {
            "allow" => Level::Allow,
            "warn" => Level::Warn,
            "deny" => Level::Deny,
            other => {
                return Err(err(level.span(), format!("unknown level `{other}`"))
                    .help(Some("the levels are `allow`, `warn` and `deny`".to_owned())));
            }
        };
        if !allowable(c) && l != Level::Deny {
            return Err(err(code.span(), format!("`{}` cannot be lowered", c.as_str()))
                .help(Some("it says that a verdict is missing: hiding it would let a check pass unverified".to_owned())));
        }
        config.levels.insert(c, l);
    }
    Ok(config)
}

/// Whether `code` may be allowed or lowered to a warning: not
/// `incomplete`, which says that a verdict is missing (hiding it would let
/// a check pass unverified).
pub fn allowable(code: Code) -> bool {
    code != Code::Incomplete
}

/// The code with this stable name.
pub fn code_named(name: &str) -> Option<Code> {
    Code::ALL.iter().copied().find(|c| c.as_str() == name)
}

/// A path made absolute and without `.`/`..` where possible, to compare a
/// checked file with the `[wcet]` keys.
pub fn normal(p: &Path) -> PathBuf {
    std::fs::canonicalize(p)
        .or_else(|_| std::path::absolute(p))
        .unwrap_or_else(|_| p.to_path_buf())
}

impl Config {
    /// The WCET file the configuration gives for `checked`.
    pub fn wcet_for(&self, checked: &Path) -> Option<&PathBuf> {
        self.wcet.get(&normal(checked))
    }
}
