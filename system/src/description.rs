//! The system file (`genom-check check --system FILE`): a TOML file that
//! names the components of a functional layer (each `.gen` with its WCET
//! file), wires their ports, declares the external sources and the
//! cause-effect chains to bound. Every name and value keeps its span in
//! the file, so that each diagnostic points into it.
//!
//! ```toml
//! include = ["include"]              # -I folders, relative to this file
//!
//! [component.uavatt]
//! file = "uavatt.gen"                # relative to this file
//! wcet = "uavatt.wcet"
//! steady = ["servo"]                 # services clients call in flight
//!
//! [external.pose]
//! period = "1ms"
//! feeds = ["uavatt.state"]
//!
//! [[connect]]
//! from = "uavatt.rotor_input"
//! to = "rotorcraft.rotor_input"
//!
//! [[chain]]
//! from = "pose"                      # optional: every source
//! to = "rotorcraft.rotor_input"      # or `rotorcraft`: its every input
//! deadline = "5ms"                   # optional
//! ```

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use genom_model::{Code, Diagnostic, Span};
use serde::Deserialize;
use toml::Spanned;

/// `component.port`, as written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Endpoint {
    /// The component (or, for a chain's `from`, maybe an external source).
    pub component: String,
    /// The port; `None` when only a name was written.
    pub port: Option<String>,
    /// The whole string in the file.
    pub span: Span,
}

impl Endpoint {
    /// `component.port`, or the bare name.
    pub fn text(&self) -> String {
        match &self.port {
            Some(p) => format!("{}.{p}", self.component),
            None => self.component.clone(),
        }
    }
}

/// One `[component.NAME]`.
#[derive(Debug, Clone)]
pub struct ComponentEntry {
    /// The name the system file gives it.
    pub name: String,
    /// Where that name is written.
    pub span: Span,
    /// The `.gen` file, resolved against the system file's folder.
    pub file: PathBuf,
    /// Where `file` is written.
    pub file_span: Span,
    /// The WCET file, resolved likewise.
    pub wcet: Option<PathBuf>,
    /// Services clients call in the steady state (`None`: all of them).
    pub steady: Option<Vec<(String, Span)>>,
}

/// One `[external.NAME]`: a source outside the components (a pose
/// estimator), publishing at a period.
#[derive(Debug, Clone)]
pub struct External {
    /// Its name.
    pub name: String,
    /// Where the name is written.
    pub span: Span,
    /// Its period, in nanoseconds (`None`: unknown).
    pub period_ns: Option<u64>,
    /// The input ports it feeds.
    pub feeds: Vec<Endpoint>,
}

/// One `[[connect]]`: an output port feeding an input port.
#[derive(Debug, Clone)]
pub struct Connection {
    /// The output.
    pub from: Endpoint,
    /// The input.
    pub to: Endpoint,
}

/// One chain request (`[[chain]]` or `--chain`).
#[derive(Debug, Clone)]
pub struct ChainSpec {
    /// The source (an external's name or `component.port`); `None`: every
    /// source.
    pub from: Option<Endpoint>,
    /// The sink: `component.port`, or a component (its every input).
    pub to: Endpoint,
    /// A deadline on the data age and the reaction time, in nanoseconds.
    pub deadline_ns: Option<u64>,
    /// Where the request is written (its `to`).
    pub span: Span,
}

/// A parsed system file.
#[derive(Debug, Clone, Default)]
pub struct SystemFile {
    /// Include folders, resolved.
    pub include: Vec<PathBuf>,
    /// The components, by name.
    pub components: Vec<ComponentEntry>,
    /// The external sources, by name.
    pub externals: Vec<External>,
    /// The connections, in file order.
    pub connections: Vec<Connection>,
    /// The chains, in file order.
    pub chains: Vec<ChainSpec>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Raw {
    #[serde(default)]
    include: Vec<Spanned<String>>,
    #[serde(default)]
    component: BTreeMap<Spanned<String>, RawComponent>,
    #[serde(default)]
    external: BTreeMap<Spanned<String>, RawExternal>,
    #[serde(default)]
    connect: Vec<RawConnect>,
    #[serde(default)]
    chain: Vec<RawChain>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawComponent {
    file: Spanned<String>,
    wcet: Option<Spanned<String>>,
    steady: Option<Vec<Spanned<String>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawExternal {
    period: Option<Spanned<String>>,
    #[serde(default)]
    feeds: Vec<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawConnect {
    from: Spanned<String>,
    to: Spanned<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawChain {
    from: Option<Spanned<String>>,
    to: Spanned<String>,
    deadline: Option<Spanned<String>>,
}

/// Parses the system file's `text`; `base` is its offset in the source
/// map (spans are global), `dir` its folder (paths are relative to it).
/// A file that does not parse is one `bad-system` diagnostic.
pub fn parse(text: &str, base: u32, dir: &Path) -> Result<SystemFile, Vec<Diagnostic>> {
    let at = |r: Range<usize>| -> Span {
        let clamp = |x: usize| u32::try_from(x.min(text.len())).unwrap_or(u32::MAX);
        Span::new(base + clamp(r.start), base + clamp(r.end))
    };
    let raw: Raw = toml::from_str(text).map_err(|e| {
        let span = e.span().map_or(Span::new(base, base), &at);
        vec![Diagnostic::new(
            Code::BadSystem,
            format!("the system file does not parse: {}", e.message()),
            span,
            "here",
        )]
    })?;
    let mut errors = Vec::new();
    let endpoint = |s: &Spanned<String>| -> Endpoint {
        let span = at(s.span());
        match s.get_ref().split_once('.') {
            Some((c, p)) => Endpoint {
                component: c.trim().to_owned(),
                port: Some(p.trim().to_owned()),
                span,
            },
            None => Endpoint {
                component: s.get_ref().trim().to_owned(),
                port: None,
                span,
            },
        }
    };
    let duration = |s: &Spanned<String>, errors: &mut Vec<Diagnostic>| -> Option<u64> {
        match parse_duration(s.get_ref()) {
            Ok(ns) => Some(ns),
            Err(m) => {
                errors.push(Diagnostic::new(
                    Code::BadSystem,
                    m,
                    at(s.span()),
                    "not a duration",
                ));
                None
            }
        }
    };
    let mut out = SystemFile {
        include: raw.include.iter().map(|i| dir.join(i.get_ref())).collect(),
        ..SystemFile::default()
    };
    for (name, c) in &raw.component {
        out.components.push(ComponentEntry {
            name: name.get_ref().clone(),
            span: at(name.span()),
            file: dir.join(c.file.get_ref()),
            file_span: at(c.file.span()),
            wcet: c.wcet.as_ref().map(|w| dir.join(w.get_ref())),
            steady: c.steady.as_ref().map(|v| {
                v.iter()
                    .map(|s| (s.get_ref().clone(), at(s.span())))
                    .collect()
            }),
        });
    }
    for (name, e) in &raw.external {
        let period_ns = e.period.as_ref().and_then(|p| duration(p, &mut errors));
        let feeds: Vec<Endpoint> = e.feeds.iter().map(endpoint).collect();
        for f in &feeds {
            if f.port.is_none() {
                errors.push(port_expected(f));
            }
        }
        out.externals.push(External {
            name: name.get_ref().clone(),
            span: at(name.span()),
            period_ns,
            feeds,
        });
    }
    for c in &raw.connect {
        let (from, to) = (endpoint(&c.from), endpoint(&c.to));
        for e in [&from, &to] {
            if e.port.is_none() {
                errors.push(port_expected(e));
            }
        }
        out.connections.push(Connection { from, to });
    }
    for c in &raw.chain {
        let deadline_ns = c.deadline.as_ref().and_then(|d| duration(d, &mut errors));
        let to = endpoint(&c.to);
        out.chains.push(ChainSpec {
            from: c.from.as_ref().map(endpoint),
            span: to.span,
            to,
            deadline_ns,
        });
    }
    if errors.is_empty() {
        Ok(out)
    } else {
        Err(errors)
    }
}

fn port_expected(e: &Endpoint) -> Diagnostic {
    Diagnostic::new(
        Code::BadSystem,
        format!("`{}` names no port", e.text()),
        e.span,
        "expected `component.port`",
    )
}

/// Parses a duration such as `1ms`, `2.5ms`, `400us`, `1s` or `100ns` into
/// nanoseconds.
pub fn parse_duration(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(t.len());
    let (number, unit) = t.split_at(split);
    let factor: f64 = match unit.trim() {
        "ns" => 1.0,
        "us" | "µs" => 1e3,
        "ms" => 1e6,
        "s" => 1e9,
        _ => {
            return Err(format!(
                "`{text}` is not a duration such as `1ms`, `400us` or `2.5ms`"
            ));
        }
    };
    let value: f64 = number
        .parse()
        .map_err(|_| format!("`{text}` is not a duration such as `1ms`, `400us` or `2.5ms`"))?;
    let ns = (value * factor).round();
    if !(0.0..=1e15).contains(&ns) {
        return Err(format!("`{text}` is out of range"));
    }
    // In range: the cast cannot truncate.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    Ok(ns as u64)
}

/// Parses a `--chain` argument: `FROM->TO`, `FROM->TO<=DURATION`, or
/// `TO` / `TO<=DURATION` (every source); `FROM` and `TO` as in the file.
/// Its spans are empty (it is not in the file).
pub fn parse_chain_arg(text: &str) -> Result<ChainSpec, String> {
    let (path, deadline) = match text.split_once("<=") {
        Some((p, d)) => (p, Some(parse_duration(d)?)),
        None => (text, None),
    };
    let (from, to) = match path.split_once("->") {
        Some((f, t)) => (Some(f.trim()), t.trim()),
        None => (None, path.trim()),
    };
    let endpoint = |s: &str| -> Endpoint {
        match s.split_once('.') {
            Some((c, p)) => Endpoint {
                component: c.to_owned(),
                port: Some(p.to_owned()),
                span: Span::default(),
            },
            None => Endpoint {
                component: s.to_owned(),
                port: None,
                span: Span::default(),
            },
        }
    };
    if to.is_empty() || from.is_some_and(str::is_empty) {
        return Err(format!(
            "`{text}` is not a chain such as `maneuver.desired->rotorcraft.rotor_input<=30ms`"
        ));
    }
    Ok(ChainSpec {
        from: from.map(endpoint),
        to: endpoint(to),
        deadline_ns: deadline,
        span: Span::default(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations() {
        assert_eq!(parse_duration("1ms"), Ok(1_000_000));
        assert_eq!(parse_duration("2.5ms"), Ok(2_500_000));
        assert_eq!(parse_duration("400us"), Ok(400_000));
        assert!(parse_duration("4 parsecs").is_err());
    }

    #[test]
    fn chain_arguments() {
        let c = parse_chain_arg("a.x->b.y<=30ms").expect("parses");
        assert_eq!(c.from.map(|e| e.text()), Some("a.x".to_owned()));
        assert_eq!(c.to.text(), "b.y");
        assert_eq!(c.deadline_ns, Some(30_000_000));
        let c = parse_chain_arg("b").expect("parses");
        assert!(c.from.is_none() && c.to.port.is_none());
        assert!(parse_chain_arg("->b").is_err());
    }

    #[test]
    fn bad_values_point_into_the_file() {
        let text = "[external.p]\nperiod = \"fast\"\nfeeds = [\"a\"]\n";
        let errs = parse(text, 100, Path::new(".")).expect_err("bad");
        assert_eq!(errs.len(), 2);
        let at = text.find("\"fast\"").expect("in text") as u32 + 100;
        assert_eq!(errs[0].span().start, at);
        assert!(errs.iter().all(|d| d.code == Code::BadSystem));
    }
}
