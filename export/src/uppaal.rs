//! The `uppaal` export: the component's network of timed automata
//! ([`Network::build`](genom_translate::timed_automata::BuildNetwork::build),
//! the timed semantics of the zone engine) as an UPPAAL XML model, with its
//! query file.
//!
//! - `<declaration>`: every clock, bounded integer and array of the
//!   network (one comment line each), the urgent broadcast channel `hurry`
//!   and one function per edge with statements (its local variables,
//!   `if`/`while`, conditional clock resets);
//! - one `<template>` per process (the control thread, each execution
//!   thread, each watchdog), without parameters; committed locations are
//!   `<committed/>`; invariants, guards, assignments and synchronisations
//!   are labels;
//! - urgent edges (codel begins, rounds of aperiodic threads, arming of
//!   watchdogs) send on `hurry`, an `urgent broadcast chan` nobody
//!   receives: time cannot pass while one is enabled (their guards have
//!   no clock, as UPPAAL requires);
//! - `<instantiation>` makes one process of each template, `<system>`
//!   lists them;
//! - `<queries>` (and the companion `.q` file): `A[] not deadlock` (not
//!   for GenoM3, whose components may stop for good without fault), one
//!   `E<>` per codel label (over every location it marks: a GenoM3
//!   activity's codel in each of its slots), `A[] not S_watchdog.late`
//!   per service with a clocked watchdog (a max-time and no unbounded
//!   loop) and `A[] not T.overrun` per periodic thread.
//!
//! Identifiers that are UPPAAL or TChecker keywords are renamed with `_`
//! suffixes ([`Renaming`]), listed in an XML comment and in the
//! declaration.

use std::fmt::Write as _;

use genom_model::timed_automata::{
    ClockConstraint, Edge, Expr, LValue, LabelKind, Location, Network, Process, ProcessKind,
    Renaming, Stmt,
};

use crate::{ExportError, ExportInput, Exported};

/// Exports the component's network (and, when not the zone engine's, the
/// semantics it encodes) as an UPPAAL model and its queries.
pub fn export(
    input: &ExportInput<'_>,
    (net, semantics): (Network, Option<&'static str>),
) -> Result<Exported, ExportError> {
    let mut out = match semantics {
        Some(s) => render_genom3(&net, s),
        None => render(&net),
    };
    let verified = input.verification.verified;
    out.main = crate::mark_unverified(out.main, verified, ("<!-- ", " -->"));
    for (_, text) in &mut out.extra {
        *text = crate::mark_unverified(std::mem::take(text), verified, ("// ", ""));
    }
    Ok(out)
}

/// The printed model of a network of the zone engine: the XML and the
/// `.q` file.
pub fn render(net: &Network) -> Exported {
    render_as(net, "timed automata of the zone engine")
}

/// The printed model of a network; `semantics` says which one it encodes
/// (a header comment).
pub fn render_as(net: &Network, semantics: &str) -> Exported {
    printed(Printer::new(net, semantics))
}

/// The printed model of a GenoM3 network (`semantics`: which one, for the
/// header). Its queries are those that hold on a correct GenoM3
/// component: no `A[] not deadlock`, since a GenoM3 component can stop
/// for good without fault (a permanent codel that throws, or `kill`,
/// ends its tasks), and the overrun queries speak of tasks.
pub fn render_genom3(net: &Network, semantics: &str) -> Exported {
    printed(Printer {
        genom3: true,
        ..Printer::new(net, semantics)
    })
}

fn printed(mut p: Printer<'_>) -> Exported {
    let xml = p.xml();
    let queries = p.query_file();
    Exported {
        main: xml,
        extra: vec![(".q".to_owned(), queries)],
        notes: Vec::new(),
    }
}

/// One query: its formula and what it checks.
struct Query {
    formula: String,
    comment: String,
}

struct Printer<'a> {
    net: &'a Network,
    semantics: &'a str,
    names: Renaming,
    hurry: String,
    /// Template names, by process.
    templates: Vec<String>,
    /// Edge function names, by process and edge (`None`: no function).
    functions: Vec<Vec<Option<String>>>,
    /// A GenoM3 network: GenoM3's queries.
    genom3: bool,
}

impl<'a> Printer<'a> {
    fn new(net: &'a Network, semantics: &'a str) -> Self {
        let mut names = Renaming::new(net, &[]);
        let hurry = names.fresh("hurry");
        let templates = net
            .processes
            .iter()
            .map(|p| names.fresh(&template_name(p)))
            .collect();
        let mut functions = Vec::new();
        for p in &net.processes {
            let proc_name = names.name(&p.name);
            let mut row = Vec::new();
            for (i, e) in p.edges.iter().enumerate() {
                let needed = e.statements.iter().any(|s| !matches!(s, Stmt::Reset(_)));
                row.push(needed.then(|| names.fresh(&format!("{proc_name}_step{i}"))));
            }
            functions.push(row);
        }
        Printer {
            net,
            semantics,
            names,
            hurry,
            templates,
            functions,
            genom3: false,
        }
    }

    fn n(&self, name: &str) -> String {
        self.names.name(name)
    }

    fn xml(&mut self) -> String {
        let mut out = String::new();
        out.push_str("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n");
        out.push_str("<!DOCTYPE nta PUBLIC '-//Uppaal Team//DTD Flat System 1.1//EN' 'http://www.it.uu.se/research/group/darts/uppaal/flat-1_2.dtd'>\n");
        out.push_str("<nta>\n");
        let _ = writeln!(
            out,
            "<!-- genom-check: component {}, {}; one time unit is {} ns -->",
            comment_text(&self.net.name),
            comment_text(self.semantics),
            self.net.unit_ns
        );
        if !self.names.renamed.is_empty() {
            let list = self.renamed_list();
            let _ = writeln!(out, "<!-- renamed (keywords): {} -->", comment_text(&list));
        }
        let _ = writeln!(
            out,
            "<declaration>{}</declaration>",
            escape(&self.declaration())
        );
        for k in 0..self.net.processes.len() {
            out.push_str(&self.template(k));
        }
        let _ = writeln!(
            out,
            "<instantiation>{}</instantiation>",
            escape(&self.instantiation())
        );
        let _ = writeln!(out, "<system>{}</system>", escape(&self.system()));
        out.push_str("<queries>\n");
        for q in self.queries() {
            let _ = writeln!(
                out,
                "<query>\n<formula>{}</formula>\n<comment>{}</comment>\n</query>",
                escape(&q.formula),
                escape(&q.comment)
            );
        }
        out.push_str("</queries>\n</nta>\n");
        out
    }

    fn renamed_list(&self) -> String {
        self.names
            .renamed
            .iter()
            .map(|(a, b)| format!("{a} -> {b}"))
            .collect::<Vec<_>>()
            .join(", ")
    }

    // ----- declarations -----------------------------------------------------

    fn declaration(&self) -> String {
        let net = self.net;
        let mut out = String::new();
        let _ = writeln!(
            out,
            "\n// Component {}: one time unit is {} ns.",
            net.name, net.unit_ns
        );
        if !self.names.renamed.is_empty() {
            let _ = writeln!(out, "// Renamed (keywords): {}.", self.renamed_list());
        }
        out.push_str("\n// Clocks.\n");
        for c in &net.clocks {
            let _ = writeln!(out, "clock {}; // {}", self.n(&c.name), c.description);
        }
        out.push_str("\n// Discrete state.\n");
        for v in &net.vars {
            let name = self.n(&v.name);
            let range = format!("int[{},{}]", v.min, v.max);
            let line = if v.array {
                let init = vec![v.init.to_string(); v.size as usize].join(",");
                format!("{range} {name}[{}] = {{{init}}};", v.size)
            } else {
                format!("{range} {name} = {};", v.init)
            };
            let _ = writeln!(out, "{line} // {}", v.description);
        }
        let _ = writeln!(
            out,
            "\n// Urgent edges send on this channel: time cannot pass while one is enabled.\nurgent broadcast chan {};",
            self.hurry
        );
        out.push_str("\n// The statements of the edges (one atomic step of the engine each).\n");
        for (k, p) in net.processes.iter().enumerate() {
            for (i, e) in p.edges.iter().enumerate() {
                if let Some(f) = &self.functions[k][i] {
                    out.push_str(&self.function(f, e));
                }
            }
        }
        out
    }

    fn function(&self, name: &str, e: &Edge) -> String {
        let mut out = format!("// {}\nvoid {name}()\n{{\n", e.description);
        let body: Vec<Stmt> = e
            .statements
            .iter()
            .filter(|s| !matches!(s, Stmt::Reset(_)))
            .cloned()
            .collect();
        // UPPAAL declares local variables at the start of the body.
        let mut locals = Vec::new();
        collect_locals(&body, &mut locals);
        if !locals.is_empty() {
            let _ = writeln!(out, "    int {};", locals.join(", "));
        }
        self.stmts(&body, 1, &mut out);
        out.push_str("}\n");
        out
    }

    fn stmts(&self, list: &[Stmt], depth: usize, out: &mut String) {
        let pad = "    ".repeat(depth);
        for s in list {
            match s {
                Stmt::Local(name, e) => {
                    let _ = writeln!(out, "{pad}{name} = {};", self.int(e));
                }
                Stmt::Assign(lv, e) => {
                    let _ = writeln!(out, "{pad}{} = {};", self.lvalue(lv), self.int(e));
                }
                Stmt::Reset(c) => {
                    let _ = writeln!(out, "{pad}{} = 0;", self.n(&self.net.clock(*c).name));
                }
                Stmt::If(c, a, b) => {
                    let _ = writeln!(out, "{pad}if ({}) {{", self.boolean(c));
                    self.stmts(a, depth + 1, out);
                    if !b.is_empty() {
                        let _ = writeln!(out, "{pad}}} else {{");
                        self.stmts(b, depth + 1, out);
                    }
                    let _ = writeln!(out, "{pad}}}");
                }
                Stmt::While(c, body) => {
                    let _ = writeln!(out, "{pad}while ({}) {{", self.boolean(c));
                    self.stmts(body, depth + 1, out);
                    let _ = writeln!(out, "{pad}}}");
                }
            }
        }
    }

    fn lvalue(&self, lv: &LValue) -> String {
        match lv {
            LValue::Var(v) => self.n(&self.net.var(*v).name),
            LValue::Elem(v, i) => format!("{}[{}]", self.n(&self.net.var(*v).name), self.int(i)),
            LValue::Local(n) => n.clone(),
        }
    }

    // ----- expressions ------------------------------------------------------

    /// The expression in an integer context.
    fn int(&self, e: &Expr) -> String {
        if e.is_boolean() && e.as_const().is_none() {
            return format!("({} ? 1 : 0)", self.boolean(e));
        }
        self.raw(e)
    }

    /// The expression in a boolean context.
    fn boolean(&self, e: &Expr) -> String {
        match e {
            Expr::Const(c) => (if *c != 0 { "true" } else { "false" }).to_owned(),
            _ if e.is_boolean() => self.raw(e),
            _ => format!("({} != 0)", self.raw(e)),
        }
    }

    fn raw(&self, e: &Expr) -> String {
        match e {
            Expr::Const(c) => c.to_string(),
            Expr::Var(v) => self.n(&self.net.var(*v).name),
            Expr::Elem(v, i) => format!("{}[{}]", self.n(&self.net.var(*v).name), self.int(i)),
            Expr::Local(n) => n.clone(),
            Expr::Add(items) => {
                let parts: Vec<String> = items.iter().map(|x| self.int(x)).collect();
                format!("({})", parts.join(" + "))
            }
            Expr::Sub(a, b) => format!("({} - {})", self.int(a), self.int(b)),
            Expr::Cmp(op, a, b) => format!("{} {} {}", self.int(a), op.symbol(), self.int(b)),
            Expr::Not(x) => format!("!({})", self.boolean(x)),
            Expr::And(items) => self.join(items, " && "),
            Expr::Or(items) => self.join(items, " || "),
            Expr::Ite(c, a, b) => {
                format!("({} ? {} : {})", self.boolean(c), self.int(a), self.int(b))
            }
        }
    }

    fn join(&self, items: &[Expr], op: &str) -> String {
        let parts: Vec<String> = items
            .iter()
            .map(|x| format!("({})", self.boolean(x)))
            .collect();
        format!("({})", parts.join(op))
    }

    fn constraints(&self, cs: &[ClockConstraint]) -> Vec<String> {
        cs.iter()
            .map(|c| {
                format!(
                    "{} {} {}",
                    self.n(&self.net.clock(c.clock).name),
                    c.op.symbol(),
                    c.bound
                )
            })
            .collect()
    }

    // ----- templates --------------------------------------------------------

    fn template(&self, k: usize) -> String {
        let p = &self.net.processes[k];
        let mut out = String::from("<template>\n");
        let _ = writeln!(out, "<name>{}</name>", escape(&self.templates[k]));
        let _ = writeln!(
            out,
            "<declaration>// {}\n</declaration>",
            escape(&p.description)
        );
        for (i, l) in p.locations.iter().enumerate() {
            out.push_str(&self.location(k, i, l));
        }
        if let Some(i) = p.locations.iter().position(|l| l.initial) {
            let _ = writeln!(out, "<init ref=\"{}\"/>", loc_id(k, i));
        }
        for (i, e) in p.edges.iter().enumerate() {
            out.push_str(&self.transition(k, i, e));
        }
        out.push_str("</template>\n");
        out
    }

    fn location(&self, k: usize, i: usize, l: &Location) -> String {
        let (x, y) = position(i);
        let mut out = format!(
            "<location id=\"{}\" x=\"{x}\" y=\"{y}\">\n<name x=\"{}\" y=\"{}\">{}</name>\n",
            loc_id(k, i),
            x - 20,
            y - 34,
            escape(&self.n(&l.name))
        );
        if !l.invariant.is_empty() {
            let _ = writeln!(
                out,
                "<label kind=\"invariant\" x=\"{}\" y=\"{}\">{}</label>",
                x - 20,
                y + 17,
                escape(&self.constraints(&l.invariant).join(" && "))
            );
        }
        let mut comment = l.description.clone();
        if !l.labels.is_empty() {
            let _ = write!(comment, " [labels: {}]", l.labels.join(", "));
        }
        let _ = writeln!(out, "<label kind=\"comments\">{}</label>", escape(&comment));
        if l.urgent {
            out.push_str("<urgent/>\n");
        }
        if l.committed {
            out.push_str("<committed/>\n");
        }
        out.push_str("</location>\n");
        out
    }

    fn transition(&self, k: usize, i: usize, e: &Edge) -> String {
        let mut out = format!(
            "<transition>\n<source ref=\"{}\"/>\n<target ref=\"{}\"/>\n",
            loc_id(k, e.from.0 as usize),
            loc_id(k, e.to.0 as usize)
        );
        let mut guard = self.constraints(&e.clock_guard);
        if !e.guard.is_true() {
            guard.push(self.boolean(&e.guard));
        }
        if !guard.is_empty() {
            let _ = writeln!(
                out,
                "<label kind=\"guard\">{}</label>",
                escape(&guard.join(" && "))
            );
        }
        if e.urgent {
            let _ = writeln!(
                out,
                "<label kind=\"synchronisation\">{}!</label>",
                escape(&self.hurry)
            );
        }
        let assignment = self.assignment(k, i, e);
        if !assignment.is_empty() {
            let _ = writeln!(
                out,
                "<label kind=\"assignment\">{}</label>",
                escape(&assignment.join(", "))
            );
        }
        let event = &self.net.event(e.event).name;
        let _ = writeln!(
            out,
            "<label kind=\"comments\">{}: {}</label>",
            escape(event),
            escape(&e.description)
        );
        out.push_str("</transition>\n");
        out
    }

    /// The assignment label: the edge's function, then its top-level clock
    /// resets (integer statements never read clocks).
    fn assignment(&self, k: usize, i: usize, e: &Edge) -> Vec<String> {
        let mut parts = Vec::new();
        if let Some(f) = &self.functions[k][i] {
            parts.push(format!("{f}()"));
        }
        for s in &e.statements {
            if let Stmt::Reset(c) = s {
                parts.push(format!("{} = 0", self.n(&self.net.clock(*c).name)));
            }
        }
        parts
    }

    // ----- system and queries -----------------------------------------------

    fn instantiation(&self) -> String {
        let mut out = String::from("\n");
        for (k, p) in self.net.processes.iter().enumerate() {
            let _ = writeln!(out, "{} = {}();", self.n(&p.name), self.templates[k]);
        }
        out
    }

    fn system(&self) -> String {
        let list: Vec<String> = self.net.processes.iter().map(|p| self.n(&p.name)).collect();
        format!("\nsystem {};\n", list.join(", "))
    }

    fn queries(&self) -> Vec<Query> {
        let net = self.net;
        let mut out = Vec::new();
        if !self.genom3 {
            out.push(Query {
                formula: "A[] not deadlock".to_owned(),
                comment: "no deadlock (a thread overrun or a missed max-time is a terminal state, so it shows here too)".to_owned(),
            });
        }
        let thread = if self.genom3 { "task" } else { "thread" };
        let place = |l: &genom_model::timed_automata::Label| {
            let p = net.process(l.process);
            format!(
                "{}.{}",
                self.n(&p.name),
                self.n(&p.locations[l.location.0 as usize].name)
            )
        };
        // One query per label name: a label on several locations (a GenoM3
        // activity's codel in each of its slots) asks about any of them.
        let mut asked: Vec<&str> = Vec::new();
        for l in &net.labels {
            if asked.contains(&l.name.as_str()) {
                continue;
            }
            asked.push(&l.name);
            let places: Vec<String> = net
                .labels
                .iter()
                .filter(|m| m.name == l.name)
                .map(place)
                .collect();
            let at = match places.as_slice() {
                [one] => one.clone(),
                many => format!("({})", many.join(" || ")),
            };
            let (formula, comment) = match l.kind {
                LabelKind::Codel(_) => (
                    format!("E<> {at}"),
                    format!(
                        "{}: the codel can run (fails exactly when genom-check warns it unreachable)",
                        l.name
                    ),
                ),
                LabelKind::Timeout(_) => (
                    format!("A[] not {at}"),
                    format!(
                        "{}: the service always ends (or is interrupted) within its max-time",
                        l.name
                    ),
                ),
                LabelKind::Overrun(_) => (
                    format!("A[] not {at}"),
                    format!("{}: the {thread} never overruns its period", l.name),
                ),
            };
            out.push(Query { formula, comment });
        }
        out
    }

    fn query_file(&self) -> String {
        let mut out = format!(
            "// Queries of the UPPAAL model of component {} (genom-check).\n",
            self.net.name
        );
        for q in self.queries() {
            let _ = write!(
                out,
                "\n/* {} */\n{}\n",
                q.comment.replace("*/", "* /"),
                q.formula
            );
        }
        out
    }
}

/// The local variables declared anywhere in `list`, in order.
fn collect_locals(list: &[Stmt], out: &mut Vec<String>) {
    for s in list {
        match s {
            Stmt::Local(name, _) if !out.contains(name) => out.push(name.clone()),
            Stmt::If(_, a, b) => {
                collect_locals(a, out);
                collect_locals(b, out);
            }
            Stmt::While(_, body) => collect_locals(body, out),
            _ => {}
        }
    }
}

/// The template name of a process: its kind.
fn template_name(p: &Process) -> String {
    match p.kind {
        ProcessKind::Control => "Control".to_owned(),
        ProcessKind::Thread(_) => format!("Thread_{}", p.name),
        ProcessKind::Watchdog(_) => format!("Watchdog_{}", p.name),
    }
}

fn loc_id(process: usize, location: usize) -> String {
    format!("id{process}_{location}")
}

/// A location's place in the editor: a grid.
fn position(i: usize) -> (i64, i64) {
    let i = i64::try_from(i).unwrap_or(0);
    ((i % 4) * 250, (i / 4) * 200)
}

/// XML text escaping.
fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '&' => out.push_str("&amp;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

/// Text allowed inside an XML comment (no `--`; entities are not
/// decoded there, so nothing else is escaped).
fn comment_text(s: &str) -> String {
    let mut out = s.to_owned();
    while out.contains("--") {
        out = out.replace("--", "- -");
    }
    out
}
