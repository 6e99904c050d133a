//! Exports of a verified component: models for the established checkers
//! (UPPAAL, Fiacre/TINA, TChecker, PNML/TINA Petri nets), the verified
//! runtime configuration for the execution engine, and diagrams. Every
//! export is built from the same resolved model, local machines, Petri net
//! and timed-automata network as the internal engines, so it means what
//! genom-check verified. Exports return text; only the binary writes files.

pub mod config;
pub mod dot;
pub mod fiacre;
pub mod fiacre_genom3;
pub mod pnml;
pub mod promela;
pub mod promela_genom3;
pub mod svg;
pub mod tchecker;
pub mod tina;
pub mod uppaal;
pub mod verify;

use std::fmt::Write as _;

use genom_model::behaviour::Behaviour;
use genom_model::component::Component;
use genom_model::timed_automata::Network;
use genom_model::{Assumption, Counts, Dialect, ResponseTime, SourceMap};
use genom_translate::timed_automata::BuildNetwork;

/// An output format of `genom-check export`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Format {
    /// UPPAAL XML model, with its query file.
    Uppaal,
    /// Fiacre model for the frac compiler and TINA.
    Fiacre,
    /// TChecker timed automata.
    Tchecker,
    /// PNML Petri net.
    Pnml,
    /// TINA `.net` Petri net.
    Tina,
    /// Verified runtime configuration (JSON).
    Config,
    /// Graphviz diagrams.
    Dot,
    /// SVG diagrams rendered in-process.
    Svg,
    /// Promela model of the untimed semantics, for SPIN.
    Promela,
}

impl Format {
    /// Every format, in the order of the documentation.
    pub const ALL: [Format; 9] = [
        Format::Uppaal,
        Format::Fiacre,
        Format::Tchecker,
        Format::Pnml,
        Format::Tina,
        Format::Config,
        Format::Dot,
        Format::Svg,
        Format::Promela,
    ];

    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Format::Uppaal => "uppaal",
            Format::Fiacre => "fiacre",
            Format::Tchecker => "tchecker",
            Format::Pnml => "pnml",
            Format::Tina => "tina",
            Format::Config => "config",
            Format::Dot => "dot",
            Format::Svg => "svg",
            Format::Promela => "promela",
        }
    }

    /// The language whose execution semantics the export of a component
    /// written in `dialect` encodes: the one place an export's translation
    /// is chosen by language. The timed automata (`uppaal`, `tchecker`),
    /// `promela`, the Petri nets (`pnml`, `tina`: GenoM3's untimed), Fiacre
    /// (LANGUAGE.md's untimed net; GenoM3's timed semantics) and the
    /// runtime configuration (`config`) encode each language's own; the
    /// diagrams draw the structure, the same in both.
    pub fn semantics(self, dialect: Dialect) -> Dialect {
        match self {
            Format::Uppaal
            | Format::Tchecker
            | Format::Promela
            | Format::Config
            | Format::Pnml
            | Format::Tina
            | Format::Dot
            | Format::Svg
            | Format::Fiacre => dialect,
        }
    }

    /// The usual file extension of the main output.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Uppaal => "xml",
            Format::Fiacre => "fcr",
            Format::Tchecker => "tck",
            Format::Pnml => "pnml",
            Format::Tina => "net",
            Format::Config => "json",
            Format::Dot => "dot",
            Format::Svg => "svg",
            Format::Promela => "pml",
        }
    }
}

/// What verification established, recorded in exports that carry it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Verification {
    /// No error, and exploration was complete.
    pub verified: bool,
    /// Diagnostics by severity.
    pub counts: Counts,
    /// States explored.
    pub states: u64,
    /// Transitions fired.
    pub transitions: u64,
    /// Whether exploration covered the whole state space.
    pub complete: bool,
    /// The properties proven (empty when not verified): `kind` or
    /// `kind:subject`, see [`verify`].
    pub properties: Vec<String>,
    /// The distinct codes of the error diagnostics, sorted (what makes an
    /// `--allow-unverified` export unverified, with `complete`).
    pub error_codes: Vec<String>,
    /// genom-check's version.
    pub tool_version: String,
    /// What the verdicts rest on besides the text (the WCET file, the
    /// instance bound), from the check's statistics.
    pub assumptions: Vec<Assumption>,
    /// The worst-case response times the check computed, by service name
    /// (empty when it computed none).
    pub response_times: Vec<ResponseTime>,
}

/// Everything an export needs.
#[derive(Debug, Clone, Copy)]
pub struct ExportInput<'a> {
    /// The resolved component.
    pub component: &'a Component,
    /// The checked file and its includes (for hashes and names).
    pub sources: &'a SourceMap,
    /// The verification results.
    pub verification: &'a Verification,
}

/// The text of an export: the main file and companion files (a suffix such
/// as `.q` and their text), written next to the main one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Exported {
    /// The main output.
    pub main: String,
    /// Companion files: (file-name suffix replacing the extension, text).
    pub extra: Vec<(String, String)>,
    /// What the user should know about the model (the CLI prints each on
    /// stderr as a `note:`), e.g. that it reads the component untimed.
    pub notes: Vec<String>,
}

impl Exported {
    /// A single-file export.
    pub fn single(main: String) -> Self {
        Exported {
            main,
            extra: Vec::new(),
            notes: Vec::new(),
        }
    }
}

/// Why an export could not be produced.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ExportError {
    /// The format cannot express something in this component.
    #[error("cannot export to {format}: {reason}")]
    Unsupported {
        /// The format.
        format: &'static str,
        /// Why.
        reason: String,
    },
}

/// The mark written at the top of an export made with `--allow-unverified`
/// from a component whose verification has errors or is incomplete.
pub const UNVERIFIED: &str = "NOT verified: verification has errors or is incomplete (exported with the allow-unverified option)";

/// `text` with the [`UNVERIFIED`] mark as a comment of the format, after
/// the XML declaration when there is one; unchanged when `verified`.
pub(crate) fn mark_unverified(text: String, verified: bool, comment: (&str, &str)) -> String {
    if verified {
        return text;
    }
    let line = format!("{}{UNVERIFIED}{}\n", comment.0, comment.1);
    match text.split_once('\n') {
        Some((first, rest)) if first.starts_with("<?xml") => format!("{first}\n{line}{rest}"),
        _ => format!("{line}{text}"),
    }
}

/// The first lines of a Promela model (both dialects'): what it models (`what`), of which
/// component, by which version, and whether it is verified.
pub(crate) fn promela_opening(out: &mut String, input: &ExportInput<'_>, what: &str) {
    let version = if input.verification.tool_version.is_empty() {
        env!("CARGO_PKG_VERSION")
    } else {
        input.verification.tool_version.as_str()
    };
    let _ = writeln!(
        out,
        "/* {what} of component {}, generated by genom-check {version}.",
        input.component.name.name
    );
    let _ = writeln!(
        out,
        " * Verification: {}.",
        if input.verification.verified {
            "verified (no error, complete exploration)"
        } else {
            "NOT verified"
        }
    );
}

/// The network of timed automata the `uppaal` and `tchecker` exports
/// print: in GenoM3's timed semantics ([`Network::build_genom3`],
/// genom-check's default instances: one per activity, plus the request
/// restarting one that interrupts itself), or in the LANGUAGE.md zone
/// engine's ([`Network::build`]). The second value, for GenoM3's, says
/// which semantics for the exports' headers.
fn timed_network(
    component: &Component,
    semantics: Dialect,
    format: &'static str,
) -> Result<(Network, Option<&'static str>), ExportError> {
    if semantics == Dialect::Gen {
        let net = Network::build(component, &Behaviour::new(component));
        return Ok((net, None));
    }
    let net = Network::build_genom3(component).map_err(|e| ExportError::Unsupported {
        format,
        reason: e.to_string(),
    })?;
    Ok((
        net,
        Some(
            "GenoM3's timed semantics (docs/genom3-semantics.md section 15), one instance per activity and one more for an activity that interrupts itself (a client restarting it), as genom-check's --max-instances 1",
        ),
    ))
}

/// Exports the component in `format`, in the translation of
/// [`Format::semantics`] for the component's language.
pub fn export(format: Format, input: &ExportInput<'_>) -> Result<Exported, ExportError> {
    let c = input.component;
    match (format, format.semantics(c.dialect())) {
        (Format::Uppaal, s) => uppaal::export(input, timed_network(c, s, "uppaal")?),
        (Format::Tchecker, s) => tchecker::export(input, timed_network(c, s, "tchecker")?),
        (Format::Promela, Dialect::Gen) => promela::export(input),
        (Format::Promela, Dialect::Genom3) => promela_genom3::export(input),
        (Format::Fiacre, Dialect::Gen) => fiacre::export(input),
        (Format::Fiacre, Dialect::Genom3) => fiacre_genom3::export(input),
        (Format::Pnml, _) => pnml::export(input),
        (Format::Tina, _) => tina::export(input),
        (Format::Config, _) => config::export(input),
        (Format::Dot, _) => dot::export(input),
        (Format::Svg, _) => svg::export(input),
    }
}
