//! Printing a [`Plan`] as the text of a GenoM3 `.gen` file.

use std::fmt::Write as _;

use super::plan::{ControlCodel, Fsm, Kind, Param, Plan, ServicePlan, TaskPlan};

/// The `.gen` text of the plan, after a header comment.
pub(crate) fn print(plan: &Plan, header: &str) -> String {
    let mut out = format!("/* {header} */\n");
    let _ = writeln!(out, "component {} {{", plan.name);
    out.push_str("  version \"1.0\";\n  lang \"c\";\n\n");
    let _ = writeln!(out, "  exception {};", plan.exceptions[0]);
    for e in &plan.exceptions[1..] {
        let _ = writeln!(out, "  exception {e} {{ long code; }};");
    }
    out.push_str("  struct g_pose { double x; double y; };\n");
    out.push_str("  struct g_cmd { long speed; g_pose target; };\n\n");
    out.push_str("  ids {\n");
    for (name, ty) in &plan.members {
        let _ = writeln!(out, "    {} {name};", ty.name());
    }
    out.push_str("  };\n");
    for p in &plan.ports {
        let dir = if p.out { "out" } else { "in" };
        let _ = writeln!(out, "  port {dir} g_pose {};", p.name);
    }
    for t in &plan.tasks {
        task(&mut out, t);
    }
    for s in &plan.services {
        service(&mut out, plan, s);
    }
    out.push_str("};\n");
    out
}

fn task(out: &mut String, t: &TaskPlan) {
    if t.period_ms.is_none() && t.fsm.is_none() {
        let _ = writeln!(out, "\n  task {};", t.name);
        return;
    }
    let _ = writeln!(out, "\n  task {} {{", t.name);
    if let Some(p) = t.period_ms {
        let _ = writeln!(out, "    period {p} ms;");
    }
    if let Some(d) = t.delay_ms {
        let _ = writeln!(out, "    delay {d} ms;");
    }
    if let Some(fsm) = &t.fsm {
        machine(out, fsm);
    }
    out.push_str("  };\n");
}

fn names(plan: &Plan, list: &[usize]) -> String {
    list.iter()
        .map(|&i| plan.services[i].name.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}

fn params(list: &[Param]) -> String {
    list.iter().map(Param::text).collect::<Vec<_>>().join(", ")
}

fn signature(s: &ServicePlan) -> String {
    s.params
        .iter()
        .map(|p| {
            let mut text = if p.ty.is_empty() {
                format!("{} {}", p.dir.text(), p.name)
            } else {
                format!("{} {} {}", p.dir.text(), p.ty, p.name)
            };
            if let Some(d) = &p.default {
                let _ = write!(text, " = {d} : \"{}\"", p.name);
            }
            text
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn service(out: &mut String, plan: &Plan, s: &ServicePlan) {
    let kind = match s.kind {
        Kind::Activity => "activity",
        Kind::Function => "function",
        Kind::Attribute => "attribute",
    };
    let _ = writeln!(out, "\n  {kind} {}({}) {{", s.name, signature(s));
    let _ = writeln!(out, "    doc \"generated {kind} {}\";", s.name);
    if let Some(t) = s.task {
        let _ = writeln!(out, "    task {};", plan.tasks[t].name);
    }
    if s.interrupts_all {
        out.push_str("    interrupts all;\n");
    } else if !s.interrupts.is_empty() {
        let _ = writeln!(out, "    interrupts {};", names(plan, &s.interrupts));
    }
    if !s.after.is_empty() {
        let _ = writeln!(out, "    after {};", names(plan, &s.after));
    }
    if !s.before.is_empty() {
        let _ = writeln!(out, "    before {};", names(plan, &s.before));
    }
    if !s.throws.is_empty() {
        let list: Vec<&str> = s
            .throws
            .iter()
            .map(|&e| plan.exceptions[e].as_str())
            .collect();
        let word = if s.kind == Kind::Activity {
            "throw"
        } else {
            "throws"
        };
        let _ = writeln!(out, "    {word} {};", list.join(", "));
    }
    if let Some(v) = &s.validate {
        control(out, "validate", v);
    }
    for c in &s.codels {
        control(out, "codel", c);
    }
    if let Some(fsm) = &s.fsm {
        machine(out, fsm);
    }
    out.push_str("  };\n");
}

fn control(out: &mut String, word: &str, c: &ControlCodel) {
    let _ = writeln!(out, "    {word} {}({});", c.function, params(&c.params));
}

fn machine(out: &mut String, fsm: &Fsm) {
    for c in &fsm.codels {
        let states: Vec<&str> = c.states.iter().map(|&i| fsm.states[i].as_str()).collect();
        let yields: Vec<String> = c
            .yields
            .iter()
            .map(|y| match y.to {
                None => "ether".to_owned(),
                Some(j) if y.pause => format!("pause::{}", fsm.states[j]),
                Some(j) => fsm.states[j].clone(),
            })
            .collect();
        let word = if c.is_async { "async codel" } else { "codel" };
        let _ = writeln!(
            out,
            "    {word}<{}> {}({})\n      yield {};",
            states.join(", "),
            c.function,
            params(&c.params),
            yields.join(", ")
        );
    }
}
