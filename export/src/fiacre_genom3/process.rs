//! A process of the GenoM3 Fiacre model as it is built: its name, what it
//! models, the shared variables it takes by reference, its states and the
//! text of its `from` clauses, and its declaration.

use std::collections::BTreeSet;
use std::fmt::Write as _;

use super::layout::Layout;
use crate::fiacre::comment;

/// A process: its name, what it models, its shared variables and its
/// `from` clauses.
pub(super) struct Proc {
    pub name: String,
    pub about: String,
    /// Its shared variables (indices into [`Layout::vars`]).
    pub params: BTreeSet<usize>,
    pub states: Vec<String>,
    pub froms: String,
}

impl Proc {
    pub(super) fn new(name: &str, about: String, states: &[&str]) -> Self {
        Proc {
            name: name.to_owned(),
            about,
            params: BTreeSet::new(),
            states: states.iter().map(|s| (*s).to_owned()).collect(),
            froms: String::new(),
        }
    }

    /// The name of shared variable `v`, now a parameter of the process.
    pub(super) fn v(&mut self, l: &Layout<'_>, v: usize) -> String {
        self.params.insert(v);
        l.vars[v].name.clone()
    }

    /// A `from` clause: one alternative, or a `select` of several.
    pub(super) fn from(&mut self, state: &str, note: &str, alts: &[String]) {
        if alts.is_empty() {
            return;
        }
        let note = if note.is_empty() {
            String::new()
        } else {
            format!("  /* {} */", comment(note))
        };
        let _ = writeln!(self.froms, "  from {state}{note}");
        if let [one] = alts {
            let _ = writeln!(self.froms, "    {one}");
            return;
        }
        let _ = writeln!(self.froms, "    select");
        for (i, a) in alts.iter().enumerate() {
            if i > 0 {
                let _ = writeln!(self.froms, "    []");
            }
            let _ = writeln!(self.froms, "      {a}");
        }
        let _ = writeln!(self.froms, "    end");
    }

    /// The process declaration.
    pub fn print(&self, l: &Layout<'_>, out: &mut String) {
        let _ = writeln!(out, "/* {} */", comment(&self.about));
        let params: Vec<String> = self
            .params
            .iter()
            .map(|&v| format!("&{} : {}", l.vars[v].name, l.vars[v].ty))
            .collect();
        let _ = writeln!(out, "process {} ({}) is", self.name, params.join(", "));
        let _ = writeln!(out, "  states {}", self.states.join(", "));
        out.push_str(&self.froms);
        out.push('\n');
    }
}
