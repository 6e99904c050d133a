//! The languages genom-check reads, and what a file says about itself
//! outside its component (GenoM3's `#pragma` lines).

use crate::span::Span;

/// The language a file was read as.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
pub enum Dialect {
    /// The dialect of `LANGUAGE.md` (the 2004 proposal).
    #[default]
    Gen,
    /// GenoM3, as LAAS-CNRS's `genom3` reads it.
    Genom3,
}

impl Dialect {
    /// The name used by `--dialect` and in JSON: `gen` or `genom3`.
    pub fn as_str(self) -> &'static str {
        match self {
            Dialect::Gen => "gen",
            Dialect::Genom3 => "genom3",
        }
    }

    /// The name shown to people: `LANGUAGE.md` or `GenoM3`.
    pub fn title(self) -> &'static str {
        match self {
            Dialect::Gen => "LANGUAGE.md",
            Dialect::Genom3 => "GenoM3",
        }
    }

    /// What the language calls a thread of execution: `thread`, or
    /// GenoM3's `task`.
    pub fn thread_word(self) -> &'static str {
        match self {
            Dialect::Gen => "thread",
            Dialect::Genom3 => "task",
        }
    }

    /// Where the language writes a codel's WCET, as a remedy: its codels'
    /// `max-time`, or GenoM3's `--wcet` side file.
    pub fn wcet_remedy(self) -> &'static str {
        match self {
            Dialect::Gen => "give every codel a `max-time`",
            Dialect::Genom3 => "give every codel a WCET in a `--wcet` file",
        }
    }

    /// The attribute a codel's WCET is written in, when the text has one:
    /// `max-time` (GenoM3's WCETs are in a side file).
    pub fn wcet_attribute(self) -> Option<&'static str> {
        match self {
            Dialect::Gen => Some("max-time"),
            Dialect::Genom3 => None,
        }
    }
}

/// A `#pragma` line of a GenoM3 file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Pragma {
    /// `require`, `provides`, `masquerade` or another word.
    pub kind: String,
    /// The rest of the line, trimmed.
    pub args: String,
    /// The directive line.
    pub span: Span,
}
