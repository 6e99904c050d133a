//! The `fiacre` export: the component as a Fiacre model (`.fcr`) for the
//! `frac` compiler, to be explored with TINA and checked with `selt`.
//!
//! The model is the component's Petri net ([`PetriNet::build`]), so it has
//! exactly genom-check's untimed semantics (LANGUAGE.md section 3,
//! docs/semantics.md section 4):
//!
//! - `type marking is array N of bool`: one boolean per place (the net is
//!   safe: no place ever holds two tokens, which genom-check's cross-check
//!   asserts), and one `const p_NAME : nat is K` per place naming its index;
//! - one function `level_L (m : marking) : bool` per priority level above
//!   0: whether some transition of that level is enabled;
//! - one process `engine` with one state `run` and the marking as its
//!   variable `m`; from `run`, a `select` with one alternative per net
//!   transition: `on` its enabling condition (pre and read places marked,
//!   inhibitor places empty) and no transition of a higher level enabled,
//!   then the marking update, then `loop`. The priorities are thus in the
//!   guards; no port, `wait` or component priority is needed, and the model
//!   is untimed (every transition may fire at any time once enabled);
//! - the root `component` runs `engine` in a `par`;
//! - properties: `deadlock_free` (`deadlockfree`: every reachable state has
//!   a successor) and, for each start, exec and inter codel that a position
//!   of its service runs, `reach_S_C`, the LTL formula `[] not (running)`
//!   over the places where it runs. Each is asserted with `-true`/`-false`
//!   messages: `reach_S_C` is *false* exactly when the codel is reachable
//!   (the counterexample is a witness run), *true* when it is dead.
//!
//! Identifiers are the net's names with every character other than a
//! letter, digit or `_` replaced by `_`, prefixed (`p_` for places), and
//! made unique. Every alternative carries the transition's name, label and
//! source location in a comment.

use std::collections::BTreeSet;
use std::fmt::Write as _;

use genom_model::behaviour::{Behaviour, Position};
use genom_model::component::{CodelId, Idx};
use genom_model::kinds::CodelKind;
use genom_model::petri::{PRIORITY_DROP, PetriNet, PlaceId, PlaceKind, Transition};
use genom_translate::petri::BuildPetriNet;

use crate::pnml::{level_name, location, tool_version};
use crate::{ExportError, ExportInput, Exported};

/// The name of the one process.
pub const PROCESS: &str = "engine";
/// The name of its one state.
pub const STATE: &str = "run";

/// Exports the component as a Fiacre model.
pub fn export(input: &ExportInput<'_>) -> Result<Exported, ExportError> {
    let c = input.component;
    let behaviour = Behaviour::new(c);
    let net = PetriNet::build(c, &behaviour);
    let mut names = Names::default();
    let reserved = [PROCESS, STATE, "m", "marking", "deadlock_free"];
    names.used.extend(reserved.iter().map(|s| (*s).to_owned()));
    names
        .used
        .extend((1..=PRIORITY_DROP).map(|k| format!("level_{k}")));
    let root = names.take("", &c.name.name);
    let places: Vec<String> = net
        .places
        .iter()
        .map(|p| names.take("p_", &p.name))
        .collect();
    let model = Model {
        input,
        net: &net,
        behaviour: &behaviour,
        places,
        root,
    };
    let mut out = String::new();
    model.header(&mut out);
    model.declarations(&mut out);
    model.levels(&mut out);
    model.process(&mut out);
    model.component(&mut out);
    model.properties(&mut out, &mut names);
    Ok(Exported::single(out))
}

/// What the printer reads.
struct Model<'a> {
    input: &'a ExportInput<'a>,
    net: &'a PetriNet,
    behaviour: &'a Behaviour,
    /// The constant naming each place's index.
    places: Vec<String>,
    /// The root component's name.
    root: String,
}

impl Model<'_> {
    fn header(&self, out: &mut String) {
        opening(out, self.input, "component");
        out.push_str(
            "\n   The component's Petri net (docs/semantics.md section 4), untimed: the\n   \
             marking is the array m of the process engine (one boolean per place), and\n   \
             each alternative of its select is one transition, guarded by its arcs and by\n   \
             the priority rule (no transition of a higher level enabled: functions\n   \
             level_1 .. level_4). The reachable states whose marking has no transition\n   \
             above priority 0 enabled are exactly the configurations genom-check explores.\n\n   \
             Compile and check (TINA toolbox):\n     \
             frac MODEL.fcr MODEL.tts\n     \
             tina MODEL.tts MODEL.ktz\n     \
             selt MODEL.ktz MODEL.tts/MODEL.ltl\n   \
             reach_S_C is false exactly when codel S::C is reachable.\n*/\n\n",
        );
    }

    fn declarations(&self, out: &mut String) {
        let _ = writeln!(
            out,
            "/* The marking: one boolean per place (the net is safe). */\ntype marking is array {} of bool\n",
            self.net.places.len().max(1)
        );
        out.push_str("/* Place indices. */\n");
        for (k, place) in self.net.places.iter().enumerate() {
            let _ = writeln!(
                out,
                "const {} : nat is {k}   /* {}{} */",
                self.places[k],
                comment(&place.label),
                self.at(place.span)
            );
        }
        out.push('\n');
    }

    /// ` (file.gen:12:5)` or nothing.
    fn at(&self, span: genom_model::Span) -> String {
        location(self.input.sources, span)
            .map_or_else(String::new, |(f, l, col)| format!(" ({f}:{l}:{col})"))
    }

    fn levels(&self, out: &mut String) {
        for level in 1..=PRIORITY_DROP {
            let _ = writeln!(
                out,
                "/* Whether a transition of level {level} ({}) is enabled. */",
                level_name(level)
            );
            let _ = writeln!(
                out,
                "function level_{level} (m : marking) : bool is\n  begin"
            );
            let terms: Vec<String> = self
                .net
                .transitions
                .iter()
                .filter(|t| t.priority == level)
                .map(|t| format!("({})", self.enabling(t)))
                .collect();
            if terms.is_empty() {
                out.push_str("    return false\n");
            } else {
                let _ = writeln!(out, "    return {}", terms.join("\n      or "));
            }
            out.push_str("  end\n\n");
        }
    }

    /// The arcs of `t` as a condition on `m`.
    fn enabling(&self, t: &Transition) -> String {
        let place = |p: PlaceId| self.places[p.index()].as_str();
        let mut atoms: Vec<String> = Vec::new();
        for &(p, _) in t.pre.iter().chain(&t.read) {
            let atom = format!("m[{}]", place(p));
            if !atoms.contains(&atom) {
                atoms.push(atom);
            }
        }
        for &(p, _) in &t.inhibit {
            atoms.push(format!("not m[{}]", place(p)));
        }
        if atoms.is_empty() {
            "true".to_owned()
        } else {
            atoms.join(" and ")
        }
    }

    /// The guard of `t`: its arcs and no higher level enabled.
    fn guard(&self, t: &Transition) -> String {
        let mut guard = self.enabling(t);
        for level in t.priority.saturating_add(1)..=PRIORITY_DROP {
            let _ = write!(guard, "\n        and not level_{level} (m)");
        }
        guard
    }

    /// The marking update of `t`: consumed places emptied, then produced
    /// places marked.
    fn update(&self, t: &Transition) -> Vec<String> {
        let place = |p: PlaceId| self.places[p.index()].as_str();
        let mut stmts = Vec::new();
        for &(p, _) in &t.pre {
            if !t.post.iter().any(|&(q, _)| q == p) {
                stmts.push(format!("m[{}] := false", place(p)));
            }
        }
        for &(p, _) in &t.post {
            stmts.push(format!("m[{}] := true", place(p)));
        }
        stmts
    }

    fn process(&self, out: &mut String) {
        let initial: Vec<&str> = (0..self.net.places.len().max(1))
            .map(|k| {
                if self.net.initial.get(k).copied().unwrap_or(0) > 0 {
                    "true"
                } else {
                    "false"
                }
            })
            .collect();
        let _ = writeln!(
            out,
            "/* The component: one alternative per transition of the net. */\n\
             process {PROCESS} is\n  states {STATE}\n  var m : marking := [{}]\n  init to {STATE}\n  from {STATE}",
            initial.join(", ")
        );
        if self.net.transitions.is_empty() {
            out.push_str("    on false; loop\n\n");
            return;
        }
        out.push_str("    select\n");
        for (k, t) in self.net.transitions.iter().enumerate() {
            let sep = if k == 0 { "      " } else { "    [] " };
            let _ = writeln!(
                out,
                "{sep}/* {} (priority {} {}): {}{} */",
                comment(&t.name),
                t.priority,
                level_name(t.priority),
                comment(&t.label),
                self.at(t.span)
            );
            let _ = writeln!(out, "      on {};", self.guard(t));
            for stmt in self.update(t) {
                let _ = writeln!(out, "      {stmt};");
            }
            out.push_str("      loop\n");
        }
        out.push_str("    end\n\n");
    }

    fn component(&self, out: &mut String) {
        let _ = writeln!(
            out,
            "/* The root component. */\ncomponent {} is\n  par * in\n    {PROCESS}\n  end\n\n{}\n",
            self.root, self.root
        );
    }

    fn properties(&self, out: &mut String, names: &mut Names) {
        out.push_str("/* Properties (frac 1.7 and later). */\n");
        out.push_str(
            "/* Every reachable state has a successor. (genom-check's deadlock verdict, a cycle of\n   \
             pending instances delayed by one another, is a different check.) */\n",
        );
        out.push_str("property deadlock_free is deadlockfree\n");
        out.push_str(
            "assert deadlock_free -true \"no reachable state without successor\" -false \"a reachable state has no successor\"\n\n",
        );
        out.push_str(
            "/* Codel reachability: reach_S_C says that codel S::C never runs, so it is FALSE exactly\n   \
             when the codel is reachable (the counterexample runs it). Control codels run inside the\n   \
             request transition and have no place: genom-check reports them. */\n",
        );
        let c = self.input.component;
        for (k, codel) in c.codels.iter() {
            if codel.kind == CodelKind::Control {
                continue;
            }
            let label = c.codel_label(k);
            let name = names.take(
                "reach_",
                &format!(
                    "{}_{}",
                    c.services[codel.service].name.name, codel.name.name
                ),
            );
            let running = self.running_places(k);
            if running.is_empty() {
                let _ = writeln!(
                    out,
                    "/* {name}: no position of the service runs {} (it is dead by construction). */",
                    comment(&label)
                );
                continue;
            }
            let cond: Vec<String> = running.iter().map(|p| format!("m[{p}]")).collect();
            let _ = writeln!(
                out,
                "property {name} is ltl [] not ({}/1/value ({}))",
                self.root,
                cond.join(" or ")
            );
            let _ = writeln!(
                out,
                "assert {name} -true \"{} is unreachable\" -false \"{} is reachable\"",
                quoted(&label),
                quoted(&label)
            );
        }
    }

    /// The constants of the places where codel `k` runs.
    fn running_places(&self, k: CodelId) -> Vec<&str> {
        let mut out = Vec::new();
        for (i, place) in self.net.places.iter().enumerate() {
            let PlaceKind::Position(s, pid) = place.kind else {
                continue;
            };
            let position = self
                .behaviour
                .machine(s)
                .positions
                .get(usize::from(pid))
                .copied();
            let runs = matches!(
                position,
                Some(Position::Running { codel, .. } | Position::StopRunning { codel })
                    if codel == k
            );
            if runs {
                out.push(self.places[i].as_str());
            }
        }
        out
    }
}

/// Fiacre keywords (and words of the property language), which no
/// generated identifier may be.
const KEYWORDS: [&str; 72] = [
    "absent",
    "after",
    "and",
    "any",
    "append",
    "array",
    "assert",
    "before",
    "begin",
    "between",
    "bool",
    "case",
    "component",
    "const",
    "deadlockfree",
    "dequeue",
    "do",
    "else",
    "elsif",
    "empty",
    "end",
    "enqueue",
    "enter",
    "event",
    "false",
    "first",
    "foreach",
    "from",
    "full",
    "function",
    "if",
    "in",
    "infinitelyoften",
    "init",
    "int",
    "is",
    "leadsto",
    "leave",
    "loop",
    "ltl",
    "mortal",
    "nat",
    "none",
    "not",
    "null",
    "of",
    "on",
    "or",
    "out",
    "par",
    "port",
    "precedes",
    "present",
    "priority",
    "process",
    "property",
    "queue",
    "read",
    "record",
    "return",
    "select",
    "state",
    "states",
    "sync",
    "tag",
    "then",
    "to",
    "true",
    "type",
    "union",
    "unless",
    "until",
];

/// Unique Fiacre identifiers.
#[derive(Debug, Default)]
pub(crate) struct Names {
    pub(crate) used: BTreeSet<String>,
}

impl Names {
    /// A fresh identifier for `name` with `prefix`.
    pub(crate) fn take(&mut self, prefix: &str, name: &str) -> String {
        let mut base: String = prefix.to_owned();
        base.extend(name.chars().map(|ch| {
            if ch.is_ascii_alphanumeric() || ch == '_' {
                ch
            } else {
                '_'
            }
        }));
        if !base
            .chars()
            .next()
            .is_some_and(|ch| ch.is_ascii_alphabetic())
        {
            base.insert_str(0, "x_");
        }
        if KEYWORDS.contains(&base.to_ascii_lowercase().as_str()) {
            base.push_str("_c");
        }
        let mut id = base.clone();
        let mut n = 2;
        while self.used.contains(&id) {
            id = format!("{base}_{n}");
            n += 1;
        }
        self.used.insert(id.clone());
        id
    }
}

/// The first two lines of a Fiacre model (both dialects'): of which
/// component (`what`: "component", "GenoM3 component"), by which version,
/// and what verification established.
pub(crate) fn opening(out: &mut String, input: &ExportInput<'_>, what: &str) {
    let v = input.verification;
    let _ = writeln!(
        out,
        "/* Fiacre model of {what} {}, generated by genom-check {}.",
        comment(&input.component.name.name),
        comment(&tool_version(input))
    );
    let proven = if v.properties.is_empty() {
        "none".to_owned()
    } else {
        comment(&v.properties.join(", "))
    };
    let verified = if v.verified {
        "verified (no error, complete exploration)"
    } else {
        "NOT verified"
    };
    let _ = writeln!(
        out,
        "   Verification: {verified}; properties proven: {proven}."
    );
}

/// Text fit for a `/* */` comment.
pub(crate) fn comment(s: &str) -> String {
    s.replace("*/", "* /").replace(['\n', '\r'], " ")
}

/// Text fit for a Fiacre string literal.
pub(crate) fn quoted(s: &str) -> String {
    s.replace(['"', '\\', '\n', '\r'], "_")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_are_sanitised_and_unique() {
        let mut names = Names::default();
        assert_eq!(
            names.take("p_", "moveDistance.run.goto"),
            "p_moveDistance_run_goto"
        );
        assert_eq!(
            names.take("p_", "moveDistance.run.goto"),
            "p_moveDistance_run_goto_2"
        );
        assert_eq!(names.take("", "process"), "process_c");
        assert_eq!(names.take("", "9lives"), "x_9lives");
    }

    #[test]
    fn comments_cannot_be_closed_early() {
        assert_eq!(comment("a */ b\nc"), "a * / b c");
    }
}
