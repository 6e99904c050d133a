//! Identifiers and keyword renaming: the reserved words of TChecker and
//! UPPAAL, and a consistent renaming of the identifiers that clash with
//! them, the same in both exports.

use std::collections::{BTreeMap, BTreeSet};

use crate::timed_automata::Network;

/// Reserved words of TChecker and UPPAAL (declarations, statements,
/// queries and built-in functions). An identifier of the network equal to
/// one of them is renamed with `_` suffixes, the same way in both exports.
pub const KEYWORDS: &[&str] = &[
    "A",
    "E",
    "M",
    "abs",
    "and",
    "assign",
    "bool",
    "break",
    "broadcast",
    "case",
    "chan",
    "clock",
    "commit",
    "committed",
    "const",
    "continue",
    "control",
    "deadlock",
    "default",
    "do",
    "double",
    "edge",
    "else",
    "end",
    "event",
    "exists",
    "false",
    "for",
    "forall",
    "guard",
    "if",
    "imply",
    "init",
    "int",
    "local",
    "location",
    "max",
    "meta",
    "min",
    "new",
    "nop",
    "not",
    "or",
    "pow",
    "priority",
    "process",
    "return",
    "scalar",
    "select",
    "sqrt",
    "state",
    "string",
    "struct",
    "sum",
    "switch",
    "sync",
    "system",
    "then",
    "trans",
    "true",
    "typedef",
    "urgent",
    "void",
    "while",
];

/// A consistent renaming of identifiers that clash with [`KEYWORDS`].
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Renaming {
    map: BTreeMap<String, String>,
    pub(super) used: BTreeSet<String>,
    /// The renamed identifiers, in order: (original, new).
    pub renamed: Vec<(String, String)>,
}

impl Renaming {
    /// The renaming of every identifier of the network (globals and
    /// locations; location names never clash with globals' renamings as
    /// they are scoped by their process). `extra` are names the printer
    /// adds.
    pub fn new(net: &Network, extra: &[&str]) -> Renaming {
        let mut names: Vec<&str> = vec![net.name.as_str()];
        names.extend(net.events.iter().map(|e| e.name.as_str()));
        names.extend(net.clocks.iter().map(|c| c.name.as_str()));
        names.extend(net.vars.iter().map(|v| v.name.as_str()));
        names.extend(net.processes.iter().map(|p| p.name.as_str()));
        for p in &net.processes {
            names.extend(p.locations.iter().map(|l| l.name.as_str()));
        }
        names.extend(extra.iter().copied());
        let mut r = Renaming::default();
        for n in &names {
            if !KEYWORDS.contains(n) {
                r.used.insert((*n).to_owned());
            }
        }
        for n in names {
            r.get(n);
        }
        r
    }

    /// The printed identifier.
    pub fn get(&mut self, name: &str) -> String {
        if let Some(n) = self.map.get(name) {
            return n.clone();
        }
        if !KEYWORDS.contains(&name) {
            return name.to_owned();
        }
        let mut new = format!("{name}_");
        while self.used.contains(&new) || KEYWORDS.contains(&new.as_str()) {
            new.push('_');
        }
        self.used.insert(new.clone());
        self.map.insert(name.to_owned(), new.clone());
        self.renamed.push((name.to_owned(), new.clone()));
        new
    }

    /// The printed identifier (no new renaming: unknown names pass).
    pub fn name(&self, name: &str) -> String {
        self.map
            .get(name)
            .cloned()
            .unwrap_or_else(|| name.to_owned())
    }

    /// A fresh identifier for something the printer adds, unique among all.
    pub fn fresh(&mut self, want: &str) -> String {
        let mut new = want.to_owned();
        while self.used.contains(&new) || KEYWORDS.contains(&new.as_str()) {
            new.push('_');
        }
        self.used.insert(new.clone());
        new
    }
}
