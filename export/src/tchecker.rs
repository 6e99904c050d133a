//! The `tchecker` export: the component's network of timed automata
//! ([`Network::build`](genom_translate::timed_automata::BuildNetwork::build),
//! the timed semantics of the zone engine) in TChecker's text format, for
//! `tck-reach` and `tck-liveness`.
//!
//! - `system:` is the component's name; `event:` declares the network's
//!   events; `clock:1:` each clock; `int:SIZE:MIN:MAX:INIT:` each bounded
//!   integer or array;
//! - `process:` and `location:` per process, with `initial:`,
//!   `committed:`, `invariant:` and `labels:` attributes; `edge:` with
//!   `provided:` (clock constraints and the integer guard) and `do:` (the
//!   step's statements with `local`, `if`, `while`);
//! - TChecker expressions are conjunctions: a disjunction or a negated
//!   conjunction is written as an integer term `(if F then 1 else ...)`;
//! - **urgency**: TChecker has urgent locations but no urgent edges. An
//!   extra process `urgency` has two locations, `calm` (invariant: no
//!   urgent edge is enabled, [`Network::urgency`] is 0) and `hurry`
//!   (urgent; invariant: some urgent edge is enabled). Every edge of the
//!   network synchronises with one of its `tick` edges (`sync:` one per
//!   process and event), and the target invariants pick the location that
//!   matches the new state: time cannot pass while an urgent edge is
//!   enabled, exactly as with UPPAAL's urgent channels. The monitor starts
//!   `calm`: initially every service is idle, so no urgent edge is enabled.
//!
//! Labels, for `tck-reach -a reach -l LABEL`: `codel_SERVICE_CODEL` on the
//! location where the codel runs (`codel_SERVICE_control` for a control
//! codel), `overrun_THREAD` on a thread's overrun location and
//! `timeout_SERVICE` on its watchdog's `late` location. Identifiers that
//! are keywords are renamed ([`Renaming`]), listed in the header.

use std::collections::BTreeSet;
use std::fmt::Write as _;

use genom_model::timed_automata::{
    ClockConstraint, Edge, Expr, LValue, Location, Network, Process, Renaming, Stmt,
};

use crate::{ExportError, ExportInput, Exported};

/// Exports the component's network (and, when not the zone engine's, the
/// semantics it encodes) as a TChecker model.
pub fn export(
    input: &ExportInput<'_>,
    (net, semantics): (Network, Option<&'static str>),
) -> Result<Exported, ExportError> {
    let text = match semantics {
        Some(s) => render_as(&net, s),
        None => render(&net),
    };
    let verified = input.verification.verified;
    Ok(Exported::single(crate::mark_unverified(
        text,
        verified,
        ("# ", ""),
    )))
}

/// The TChecker text of a network of the zone engine.
pub fn render(net: &Network) -> String {
    render_as(net, "the timed automata of the zone engine")
}

/// The TChecker text of a network; `semantics` says which one it encodes
/// (a header comment).
pub fn render_as(net: &Network, semantics: &str) -> String {
    let mut names = Renaming::new(net, &[]);
    let monitor = Monitor {
        process: names.fresh("urgency"),
        calm: "calm".to_owned(),
        hurry: "hurry".to_owned(),
        tick: names.fresh("tick"),
    };
    let p = Printer {
        net,
        names,
        monitor,
        semantics,
    };
    p.text()
}

/// Flattened statements: the declarations of the condition variables,
/// then the statements.
struct Flat {
    next: usize,
    decls: Vec<String>,
    out: Vec<String>,
}

impl Flat {
    /// A new condition variable, declared at the start.
    fn local(&mut self) -> String {
        let name = format!("tmp{}", self.next);
        self.next += 1;
        self.decls.push(format!("local {name} = 0"));
        name
    }
}

/// The largest `N` of the `tmpN` local variables of the statements (the
/// builder's names, unique among all the network's names).
fn max_local(list: &[Stmt]) -> usize {
    let mut max = 0;
    for s in list {
        let m = match s {
            Stmt::Local(name, _) => name
                .strip_prefix("tmp")
                .and_then(|n| n.parse::<usize>().ok())
                .unwrap_or(0),
            Stmt::If(_, a, b) => max_local(a).max(max_local(b)),
            Stmt::While(_, body) => max_local(body),
            _ => 0,
        };
        max = max.max(m);
    }
    max
}

/// The names of the urgency monitor.
struct Monitor {
    process: String,
    calm: String,
    hurry: String,
    tick: String,
}

struct Printer<'a> {
    net: &'a Network,
    names: Renaming,
    monitor: Monitor,
    semantics: &'a str,
}

impl Printer<'_> {
    fn n(&self, name: &str) -> String {
        self.names.name(name)
    }

    fn text(&self) -> String {
        let mut out = self.header();
        out.push_str(&self.declarations());
        for p in &self.net.processes {
            out.push_str(&self.process(p));
        }
        out.push_str(&self.monitor_process());
        out.push_str(&self.syncs());
        out
    }

    fn header(&self) -> String {
        let net = self.net;
        let mut out = format!(
            "# TChecker model of component {} (genom-check): {}.\n# One time unit is {} ns.\n",
            net.name, self.semantics, net.unit_ns
        );
        out.push_str("# Labels: codel_SERVICE_CODEL (the codel runs), overrun_THREAD (the thread overruns its period),\n# timeout_SERVICE (the service exceeds its max-time). Check one with: tck-reach -a reach -l LABEL FILE\n");
        if !self.names.renamed.is_empty() {
            let list: Vec<String> = self
                .names
                .renamed
                .iter()
                .map(|(a, b)| format!("{a} -> {b}"))
                .collect();
            let _ = writeln!(out, "# Renamed (keywords): {}", list.join(", "));
        }
        let _ = writeln!(out, "\nsystem:{}", self.n(&net.name));
        out
    }

    fn declarations(&self) -> String {
        let net = self.net;
        let mut out = String::from("\n# Events.\n");
        for e in &net.events {
            let _ = writeln!(out, "event:{} # {}", self.n(&e.name), e.description);
        }
        let _ = writeln!(
            out,
            "event:{} # the urgency monitor follows a step",
            self.monitor.tick
        );
        out.push_str("\n# Clocks.\n");
        for c in &net.clocks {
            let _ = writeln!(out, "# {}\nclock:1:{}", c.description, self.n(&c.name));
        }
        out.push_str("\n# Discrete state.\n");
        for v in &net.vars {
            let _ = writeln!(
                out,
                "# {}\nint:{}:{}:{}:{}:{}",
                v.description,
                v.size,
                v.min,
                v.max,
                v.init,
                self.n(&v.name)
            );
        }
        out
    }

    fn process(&self, p: &Process) -> String {
        let name = self.n(&p.name);
        let mut out = format!("\n# {}\nprocess:{name}\n", p.description);
        for l in &p.locations {
            let _ = writeln!(out, "# {}", l.description);
            let _ = writeln!(
                out,
                "location:{name}:{}{{{}}}",
                self.n(&l.name),
                self.location_attributes(l)
            );
        }
        for e in &p.edges {
            let _ = writeln!(out, "# {}", e.description);
            let _ = writeln!(
                out,
                "edge:{name}:{}:{}:{}{{{}}}",
                self.n(&p.locations[e.from.0 as usize].name),
                self.n(&p.locations[e.to.0 as usize].name),
                self.n(&self.net.event(e.event).name),
                self.edge_attributes(e)
            );
        }
        out
    }

    fn location_attributes(&self, l: &Location) -> String {
        let mut attrs = Vec::new();
        if l.initial {
            attrs.push("initial:".to_owned());
        }
        if l.committed {
            attrs.push("committed:".to_owned());
        }
        if l.urgent {
            attrs.push("urgent:".to_owned());
        }
        if !l.invariant.is_empty() {
            attrs.push(format!(
                "invariant: {}",
                self.constraints(&l.invariant).join(" && ")
            ));
        }
        if !l.labels.is_empty() {
            attrs.push(format!("labels: {}", l.labels.join(",")));
        }
        attrs.join(" : ")
    }

    fn edge_attributes(&self, e: &Edge) -> String {
        let mut guard = self.constraints(&e.clock_guard);
        if !e.guard.is_true() {
            guard.push(self.formula(&e.guard));
        }
        let mut attrs = Vec::new();
        if !guard.is_empty() {
            attrs.push(format!("provided: {}", guard.join(" && ")));
        }
        if !e.statements.is_empty() {
            attrs.push(format!("do: {}", self.stmts(&e.statements)));
        }
        attrs.join(" : ")
    }

    fn constraints(&self, cs: &[ClockConstraint]) -> Vec<String> {
        cs.iter()
            .map(|c| {
                format!(
                    "{}{}{}",
                    self.n(&self.net.clock(c.clock).name),
                    c.op.symbol(),
                    c.bound
                )
            })
            .collect()
    }

    /// The urgency monitor: `calm` while no urgent edge is enabled,
    /// `hurry` (urgent) while one is.
    fn monitor_process(&self) -> String {
        let m = &self.monitor;
        let urgency = self.term(&self.net.urgency);
        let mut out = format!(
            "\n# Urgency monitor: time cannot pass while an urgent edge (codel begin, round, watchdog arming) is enabled.\nprocess:{}\n",
            m.process
        );
        let _ = writeln!(
            out,
            "location:{}:{}{{initial: : invariant: {urgency} == 0}}",
            m.process, m.calm
        );
        let _ = writeln!(
            out,
            "location:{}:{}{{urgent: : invariant: {urgency} != 0}}",
            m.process, m.hurry
        );
        for from in [&m.calm, &m.hurry] {
            for to in [&m.calm, &m.hurry] {
                let _ = writeln!(out, "edge:{}:{from}:{to}:{}{{}}", m.process, m.tick);
            }
        }
        out
    }

    fn syncs(&self) -> String {
        let mut out = String::from("\n# Every step moves the urgency monitor.\n");
        for p in &self.net.processes {
            let events: BTreeSet<String> = p
                .edges
                .iter()
                .map(|e| self.n(&self.net.event(e.event).name))
                .collect();
            for e in events {
                let _ = writeln!(
                    out,
                    "sync:{}@{e}:{}@{}",
                    self.n(&p.name),
                    self.monitor.process,
                    self.monitor.tick
                );
            }
        }
        out
    }

    // ----- statements -------------------------------------------------------

    /// The statements of an edge, without `if`: TChecker's static analysis
    /// of clock updates doubles its work at every `if` (exponential in a
    /// sequence of them), so each condition is saved in a local variable
    /// and each assignment under it becomes `x = (if g==1 then e else x)`.
    /// Only conditional clock resets stay `if` statements (a few per step).
    fn stmts(&self, list: &[Stmt]) -> String {
        if list.is_empty() {
            return "nop".to_owned();
        }
        let mut f = Flat {
            next: max_local(list) + 1,
            decls: Vec::new(),
            out: Vec::new(),
        };
        self.flatten(list, None, &mut f);
        let mut all = f.decls;
        all.extend(f.out);
        if all.is_empty() {
            return "nop".to_owned();
        }
        all.join("; ")
    }

    fn flatten(&self, list: &[Stmt], guard: Option<&str>, f: &mut Flat) {
        let when = |g: Option<&str>| g.map(|g| format!("{g}==1 && ")).unwrap_or_default();
        for s in list {
            match s {
                Stmt::Local(name, e) => f.out.push(format!("local {name} = {}", self.term(e))),
                Stmt::Assign(lv, e) => {
                    let target = self.lvalue(lv);
                    f.out.push(match guard {
                        None => format!("{target} = {}", self.term(e)),
                        Some(g) => {
                            format!("{target} = (if {g}==1 then {} else {target})", self.term(e))
                        }
                    });
                }
                Stmt::Reset(c) => {
                    let x = self.n(&self.net.clock(*c).name);
                    f.out.push(match guard {
                        None => format!("{x} = 0"),
                        Some(g) => format!("if {g}==1 then {x} = 0 end"),
                    });
                }
                Stmt::If(c, a, b) => {
                    let then = f.local();
                    f.out.push(format!(
                        "{then} = (if {}{} then 1 else 0)",
                        when(guard),
                        self.formula(c)
                    ));
                    if !b.is_empty() {
                        let other = f.local();
                        f.out.push(format!(
                            "{other} = (if {}{then}==0 then 1 else 0)",
                            when(guard)
                        ));
                        self.flatten(a, Some(&then), f);
                        self.flatten(b, Some(&other), f);
                    } else {
                        self.flatten(a, Some(&then), f);
                    }
                }
                Stmt::While(c, body) => {
                    let mut inner = Flat {
                        next: f.next,
                        decls: Vec::new(),
                        out: Vec::new(),
                    };
                    self.flatten(body, None, &mut inner);
                    f.next = inner.next;
                    f.decls.extend(inner.decls);
                    let body = if inner.out.is_empty() {
                        "nop".to_owned()
                    } else {
                        inner.out.join("; ")
                    };
                    f.out.push(format!(
                        "while {}{} do {body} end",
                        when(guard),
                        self.formula(c)
                    ));
                }
            }
        }
    }

    fn lvalue(&self, lv: &LValue) -> String {
        match lv {
            LValue::Var(v) => self.n(&self.net.var(*v).name),
            LValue::Elem(v, i) => format!("{}[{}]", self.n(&self.net.var(*v).name), self.term(i)),
            LValue::Local(n) => n.clone(),
        }
    }

    // ----- expressions ------------------------------------------------------

    /// A conjunctive formula (TChecker's guards and conditions).
    fn formula(&self, e: &Expr) -> String {
        match e {
            Expr::And(items) => {
                let parts: Vec<String> = items.iter().map(|x| self.atomic(x)).collect();
                parts.join(" && ")
            }
            _ => self.atomic(e),
        }
    }

    /// An atomic formula: a comparison, or a term compared with 0.
    fn atomic(&self, e: &Expr) -> String {
        match e {
            Expr::Cmp(op, a, b) => format!("{}{}{}", self.term(a), op.symbol(), self.term(b)),
            Expr::Not(x) => format!("{}==0", self.term(x)),
            _ => format!("{}!=0", self.term(e)),
        }
    }

    /// An integer term (booleans are 0 or 1).
    fn term(&self, e: &Expr) -> String {
        match e {
            Expr::Const(c) if *c < 0 => format!("({c})"),
            Expr::Const(c) => c.to_string(),
            Expr::Var(v) => self.n(&self.net.var(*v).name),
            Expr::Elem(v, i) => format!("{}[{}]", self.n(&self.net.var(*v).name), self.term(i)),
            Expr::Local(n) => n.clone(),
            Expr::Add(items) => {
                let parts: Vec<String> = items.iter().map(|x| self.term(x)).collect();
                format!("({})", parts.join(" + "))
            }
            Expr::Sub(a, b) => format!("({} - {})", self.term(a), self.term(b)),
            Expr::Cmp(..) | Expr::And(_) => {
                format!("(if {} then 1 else 0)", self.formula(e))
            }
            Expr::Not(x) => format!("(if {} then 0 else 1)", self.formula(x)),
            Expr::Or(items) => self.disjunction(items),
            Expr::Ite(c, a, b) => format!(
                "(if {} then {} else {})",
                self.formula(c),
                self.term(a),
                self.term(b)
            ),
        }
    }

    /// `a || b || ...` as nested `if` terms.
    fn disjunction(&self, items: &[Expr]) -> String {
        match items.split_first() {
            None => "0".to_owned(),
            Some((first, [])) => self.term(first),
            Some((first, rest)) => format!(
                "(if {} then 1 else {})",
                self.formula(first),
                self.disjunction(rest)
            ),
        }
    }
}
