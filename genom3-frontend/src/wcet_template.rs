//! A WCET file to start from (`genom-check wcet-template`): one line per
//! codel that can take time, in the side file's syntax (`OWNER.STATE ?`,
//! [`crate::wcet`]), each with what it is as a comment: a task's permanent
//! codels (one line per codel function: GenoM3's permanent codels get one
//! WCET per function, whatever state runs it), each activity's states, the
//! control task's `validate` and function codels. Every value is the
//! placeholder `?` (not measured yet), which `--wcet` accepts as it is:
//! such a codel stays without WCET, and `missing-wcet` names it, until a
//! measured duration replaces the `?`.

use std::fmt::Write as _;

use genom_model::component::genom3::{FsmCodel, Genom3Info};
use genom_model::component::{Component, Service};
use genom_model::duration::format_ns;
use genom_model::kinds::CodelKind;

/// One line: its key (`OWNER.STATE`) and its comment.
struct Line {
    key: String,
    comment: String,
}

/// The template of `c` (`None` for a LANGUAGE.md component); `file` names
/// the checked file and `version` genom-check's, for the header.
pub fn wcet_template(c: &Component, file: &str, version: &str) -> Option<String> {
    let g = c.genom3.as_deref()?;
    let mut sections: Vec<(String, Vec<Line>)> = Vec::new();
    for (tid, t) in c.threads.iter() {
        let codels: Vec<&FsmCodel> = g
            .tasks
            .iter()
            .filter(|k| k.thread == tid)
            .flat_map(|k| k.codels.iter())
            .collect();
        let period = t.period.map_or_else(
            || "no period".to_owned(),
            |p| format!("period {}", format_ns(p.ns)),
        );
        let lines = codels
            .iter()
            .filter_map(|f| permanent(&t.name.name, f))
            .collect::<Vec<_>>();
        if !lines.is_empty() {
            sections.push((
                format!("task `{}` ({period}): permanent codels", t.name.name),
                lines,
            ));
        }
    }
    for (sid, s) in c.services.iter() {
        let lines = service_lines(c, g, s);
        if lines.is_empty() {
            continue;
        }
        let kind = g
            .services
            .iter()
            .find(|i| i.service == sid)
            .map_or("service", |i| i.kind.as_str());
        let title = match s.thread.and_then(|r| c.threads.get(r.id)) {
            Some(t) => format!("{kind} `{}` (task `{}`)", s.name.name, t.name.name),
            None => format!("{kind} `{}` (control task)", s.name.name),
        };
        sections.push((title, lines));
    }
    Some(render(c, file, version, &sections))
}

/// The line of a permanent codel function, keyed by its first state.
fn permanent(task: &str, f: &FsmCodel) -> Option<Line> {
    let first = f.states.first()?;
    let mut comment = f.function.name.clone();
    if f.states.len() > 1 {
        let others: Vec<&str> = f.states[1..].iter().map(|s| s.name.as_str()).collect();
        let _ = write!(
            comment,
            ", also in {}: one WCET for the function",
            others.join(", ")
        );
    }
    if f.is_async {
        comment.push_str(", async: the least time it takes");
    }
    Some(Line {
        key: format!("{task}.{}", first.name),
        comment,
    })
}

/// The lines of a service: an activity's states, or a function's or
/// attribute's control codels (`validate`, `codel`, `codel2`...).
fn service_lines(c: &Component, g: &Genom3Info, s: &Service) -> Vec<Line> {
    s.codels
        .iter()
        .filter_map(|&k| {
            let codel = c.codels.get(k)?;
            let info = g.codels.iter().find(|i| i.codel == k)?;
            let mut comment = info.fsm.function.name.clone();
            if codel.kind == CodelKind::Control && codel.name.name == "validate" {
                comment.push_str(", validate");
            }
            if info.fsm.is_async {
                comment.push_str(", async: the least time it takes");
            }
            Some(Line {
                key: format!("{}.{}", s.name.name, codel.name.name),
                comment,
            })
        })
        .collect()
}

fn render(c: &Component, file: &str, version: &str, sections: &[(String, Vec<Line>)]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# WCETs of component `{}` ({file}), a template written by genom-check {version}.",
        c.name.name
    );
    out.push_str(
        "# One `OWNER.STATE DURATION` per line (docs/genom3.md, \"WCET side file\"). Replace\n\
         # each `?` by the codel's measured worst-case execution time with a margin\n\
         # (`400us`, `2.5ms`). A line left at `?` counts as not given: the codel is taken\n\
         # as running in no time, and `missing-wcet` names it.\n\
         # Use: genom-check --wcet THIS_FILE COMPONENT.gen\n",
    );
    let width = sections
        .iter()
        .flat_map(|(_, lines)| lines.iter().map(|l| l.key.len()))
        .max()
        .unwrap_or(0);
    for (title, lines) in sections {
        let _ = writeln!(out, "\n# {title}");
        for l in lines {
            let _ = writeln!(out, "{:<width$}  ?    # {}", l.key, l.comment);
        }
    }
    out
}
