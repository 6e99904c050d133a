//! The `fiacre` export of a **GenoM3** component: a Fiacre model (`.fcr`,
//! for `frac` and TINA) of GenoM3's semantics as genom-check's GenoM3
//! engines read it (docs/genom3-semantics.md sections 1-10 and 15),
//! shaped like LAAS's Fiacre template for GenoM3 (a client, a control
//! task, per task a timer and a task manager, per instance slot a process
//! whose codels `wait [0,WCET]`), plus one overrun watcher per periodic
//! task. Timed with the codels' WCETs; without them, the untimed reading
//! (every codel `wait [0,...[`, no watcher, codel reachability only),
//! which the header and a note say. docs/exports/fiacre.md ("GenoM3
//! components") describes the translation process by process.
//!
//! - [`layout`]: the names, shared variables and time unit;
//! - [`process`]: a process as it is built, and its declaration;
//! - [`processes`]: the text of every process but the control task's;
//! - [`control`]: the control task, the locks and the resource FIFO;
//! - [`stops`]: interruption, the end of an instance, `kill` and the
//!   shutdown;
//! - this file: what the translation refuses, and the component, the
//!   header and the properties.
//!
//! The component is read through the timed network's reading of it
//! ([`genom_translate::timed_automata::genom3::read`]: slots, state
//! machines, interruptions, exclusion lists), the same reading the
//! `uppaal` and `tchecker` exports print, and its rules are those the
//! network's statements apply.

mod control;
mod layout;
mod process;
mod processes;
mod stops;

use std::fmt::Write as _;

use genom_model::component::Component;
use genom_translate::timed_automata::genom3::read::{self, Read};

use crate::fiacre::quoted;
use crate::{ExportError, ExportInput, Exported};

use layout::Layout;
use process::Proc;

/// Exports a GenoM3 component as a timed Fiacre model.
pub fn export(input: &ExportInput<'_>) -> Result<Exported, ExportError> {
    let c = input.component;
    let g = c
        .genom3
        .as_deref()
        .filter(|g| !g.is_interface)
        .ok_or_else(|| unsupported("not a GenoM3 component".to_owned()))?;
    let timed = has_wcets(c);
    let r = read::read(c, g);
    refuse(&r)?;
    let layout = Layout::new(input, &r, instance_bound(input), timed);
    let procs = layout.processes();
    let mut out = String::new();
    header(&layout, &mut out);
    for p in &procs {
        p.print(&layout, &mut out);
    }
    component(&layout, &procs, &mut out);
    properties(&layout, &procs, &mut out);
    let mut e = Exported::single(out);
    if !timed {
        e.notes.push(UNTIMED.to_owned());
    }
    Ok(e)
}

/// What the model of a component without WCETs is, on stderr.
const UNTIMED: &str = "no WCET file (--wcet FILE): the Fiacre model is the untimed reading of the component, every codel taking any duration ([0,...[), without overrun watchers; its properties are the codels' reachability only";

fn unsupported(reason: String) -> ExportError {
    ExportError::Unsupported {
        format: "fiacre",
        reason,
    }
}

/// Whether some codel has a WCET (from the side file).
fn has_wcets(c: &Component) -> bool {
    let fsm = c.genom3.as_deref().is_some_and(|g| {
        g.tasks
            .iter()
            .flat_map(|t| &t.codels)
            .any(|k| k.wcet.is_some())
    });
    fsm || c.codels.iter().any(|(_, k)| k.wcet.is_some())
}

/// The instance bound the check ran with (`--max-instances`, default 1).
fn instance_bound(input: &ExportInput<'_>) -> usize {
    input
        .verification
        .assumptions
        .iter()
        .find(|a| a.kind == "instances")
        .and_then(|a| a.bound)
        .unwrap_or(1)
        .max(1)
}

/// What this translation does not model: a task with more instance
/// slots than GenoM3's pool of 32 (a request could find it full, 3.3), as
/// the UPPAAL/TChecker network.
fn refuse(r: &Read) -> Result<(), ExportError> {
    for t in &r.tasks {
        if t.slots.len() > 32 {
            return Err(unsupported(format!(
                "task {} needs more instance slots than GenoM3's 32, which the Fiacre model of GenoM3 does not model",
                t.name
            )));
        }
    }
    Ok(())
}

fn header(l: &Layout<'_>, out: &mut String) {
    crate::fiacre::opening(out, l.input, "GenoM3 component");
    if !l.timed {
        let _ = writeln!(
            out,
            "\n   UNTIMED READING: the component has no WCET (--wcet FILE), so every codel takes any\n   \
             duration in [0,...[ and no task can be said to overrun: no overrun watcher, and the\n   \
             properties are the codels' reachability only. GenoM3's semantics otherwise as in the\n   \
             timed model (docs/genom3-semantics.md sections 1-10 and 15; docs/exports/fiacre.md).\n   \
             Time unit: 1 = {} (the periods). {} instance(s) of each activity (--max-instances),\n   \
             one more for an activity that interrupts itself. */\n",
            genom_model::duration::format_ns(l.unit),
            l.instances
        );
        return;
    }
    let _ = writeln!(
        out,
        "\n   GenoM3's timed semantics (docs/genom3-semantics.md section 15), shaped like LAAS's\n   \
         Fiacre template for GenoM3 (docs/exports/fiacre.md). Time unit: 1 = {}; a codel\n   \
         takes any duration in [0, WCET] (0 without a WCET; an async codel at least its\n   \
         WCET, no upper bound), as in genom-check's engine. {} instance(s) of each activity\n   \
         (genom-check's --max-instances), one more for an activity that interrupts itself.\n   \
         The watcher of a periodic task reaches its state `overrun` when a tick finds the\n   \
         task's work unfinished and time passes: a thread-overrun. */\n",
        genom_model::duration::format_ns(l.unit),
        l.instances
    );
}

fn component(l: &Layout<'_>, procs: &[Proc], out: &mut String) {
    let _ = writeln!(
        out,
        "/* The root component: the shared variables and every process. */"
    );
    let _ = writeln!(out, "component {} is", l.root);
    for (i, v) in l.vars.iter().enumerate() {
        let lead = if i == 0 { "  var " } else { "      " };
        let end = if i + 1 == l.vars.len() { "" } else { "," };
        let _ = writeln!(out, "{lead}{} : {} := {}{end}", v.name, v.ty, v.init);
    }
    let _ = writeln!(out, "  par * in");
    for (i, p) in procs.iter().enumerate() {
        let args: Vec<String> = p
            .params
            .iter()
            .map(|&v| format!("&{}", l.vars[v].name))
            .collect();
        let sep = if i == 0 { "    " } else { " || " };
        let _ = writeln!(out, "{sep}{} ({})", p.name, args.join(", "));
    }
    let _ = writeln!(out, "  end\n\n{}\n", l.root);
}

/// `ROOT/K/state S` for process `name`'s state (1-based place in the `par`).
fn at_state(l: &Layout<'_>, procs: &[Proc], name: &str, state: &str) -> Option<String> {
    let k = procs.iter().position(|p| p.name == name)? + 1;
    Some(format!("{}/{k}/state {state}", l.root))
}

fn properties(l: &Layout<'_>, procs: &[Proc], out: &mut String) {
    out.push_str(
        "/* Properties (frac 1.7 and later). task_T_never_overruns is FALSE exactly when task T\n   \
         can overrun (the counterexample reaches it); codel_S_C_never_runs is FALSE exactly when\n   \
         codel C of activity S can run. */\n",
    );
    for t in &l.tasks {
        let Some(watch) = &t.watch else { continue };
        let Some(cond) = at_state(l, procs, watch, "overrun") else {
            continue;
        };
        let name = format!("task_{}_never_overruns", t.ident);
        let _ = writeln!(out, "property {name} is ltl [] not ({cond})");
        let _ = writeln!(
            out,
            "assert {name} -true \"task {} never overruns\" -false \"task {} can overrun\"",
            quoted(&t.name),
            quoted(&t.name)
        );
    }
    for (name, label, states) in l.codel_states() {
        let conds: Vec<String> = states
            .iter()
            .filter_map(|(p, s)| at_state(l, procs, p, s))
            .collect();
        if conds.is_empty() {
            continue;
        }
        let _ = writeln!(
            out,
            "property {name} is ltl [] not ({})",
            conds.join(" or ")
        );
        let _ = writeln!(
            out,
            "assert {name} -true \"{} never runs\" -false \"{} can run\"",
            quoted(&label),
            quoted(&label)
        );
    }
}
