//! The hover texts (Markdown): what the resolved model says about a
//! service, a thread (GenoM3 task) or a codel.

use std::fmt::Write as _;

use genom_model::component::{CodelId, Component, Duration, Outcome, Ref, ServiceId, ThreadId};

/// `attribute`, `function` or `activity` for GenoM3, `init`/`auto`
/// services, else `service`.
pub fn service_kind(c: &Component, id: ServiceId) -> String {
    if let Some(info) = c
        .genom3
        .as_ref()
        .and_then(|g| g.services.iter().find(|i| i.service == id))
    {
        return info.kind.clone();
    }
    let keyword = c.services.get(id).map_or("", |s| s.kind.keyword());
    if keyword.is_empty() {
        "service".to_owned()
    } else {
        format!("{keyword} service")
    }
}

/// `task` for GenoM3, else `thread`.
pub fn thread_kind(c: &Component) -> String {
    c.dialect().thread_word().to_owned()
}

fn time(d: &Duration) -> String {
    humantime::format_duration(std::time::Duration::from_nanos(d.ns)).to_string()
}

fn names<I>(c: &Component, refs: &[Ref<I>], name: impl Fn(&Component, I) -> String) -> String
where
    I: Copy,
{
    let all: Vec<String> = refs
        .iter()
        .map(|r| format!("`{}`", name(c, r.id)))
        .collect();
    all.join(", ")
}

fn service_name(c: &Component, id: ServiceId) -> String {
    c.services
        .get(id)
        .map_or_else(String::new, |s| s.name.name.clone())
}

/// A list item when `value` is not empty.
fn item(out: &mut String, key: &str, value: &str) {
    if !value.is_empty() {
        let _ = writeln!(out, "- {key}: {value}");
    }
}

/// The service's kind, thread, max-time, stops, delays, forbids,
/// interruptions, codels and reports.
pub fn service(c: &Component, id: ServiceId) -> String {
    let Some(s) = c.services.get(id) else {
        return String::new();
    };
    let mut out = format!("**{}** `{}`\n\n", service_kind(c, id), s.name.name);
    let thread = s.thread.and_then(|t| c.threads.get(t.id));
    item(
        &mut out,
        &thread_kind(c),
        &thread.map_or_else(String::new, |t| format!("`{}`", t.name.name)),
    );
    item(
        &mut out,
        "max-time",
        &s.max_time.as_ref().map(time).unwrap_or_default(),
    );
    if s.credential != 0 {
        item(&mut out, "credential", c.credential_name(s.credential));
    }
    item(&mut out, "stops", &names(c, &s.stops, service_name));
    item(&mut out, "delays", &names(c, &s.delays, service_name));
    item(&mut out, "forbids", &names(c, &s.forbids, service_name));
    if let Some(info) = c
        .genom3
        .as_ref()
        .and_then(|g| g.services.iter().find(|i| i.service == id))
    {
        if info.interrupts_all {
            item(&mut out, "interrupts", "all");
        }
        item(&mut out, "before", &names(c, &info.before, service_name));
        item(&mut out, "after", &names(c, &info.after, service_name));
    }
    let codels: Vec<String> = s.codels.iter().filter_map(|&k| codel_short(c, k)).collect();
    item(&mut out, "codels", &codels.join(", "));
    let reports: Vec<String> = s.reports.iter().map(|r| format!("`{}`", r.name)).collect();
    item(&mut out, "reports", &reports.join(", "));
    if let Some(doc) = &s.doc {
        let _ = write!(out, "\n{doc}\n");
    }
    out
}

/// `name` with its WCET.
fn codel_short(c: &Component, id: CodelId) -> Option<String> {
    let k = c.codels.get(id)?;
    Some(match &k.wcet {
        Some(w) => format!("`{}` ({})", k.name.name, time(w)),
        None => format!("`{}`", k.name.name),
    })
}

/// The thread's period, priority, stack, GenoM3 delay and the services
/// that run on it.
pub fn thread(c: &Component, id: ThreadId) -> String {
    let Some(t) = c.threads.get(id) else {
        return String::new();
    };
    let mut out = format!("**{}** `{}`\n\n", thread_kind(c), t.name.name);
    item(
        &mut out,
        "period",
        &t.period
            .as_ref()
            .map_or_else(|| "none (aperiodic)".to_owned(), time),
    );
    if t.priority != 0 {
        item(&mut out, "priority", &t.priority.to_string());
    }
    item(
        &mut out,
        "stack",
        &t.stack.map(|b| format!("{b} bytes")).unwrap_or_default(),
    );
    if let Some(task) = c
        .genom3
        .as_ref()
        .and_then(|g| g.tasks.iter().find(|k| k.thread == id))
    {
        item(
            &mut out,
            "delay",
            &task.delay.as_ref().map(time).unwrap_or_default(),
        );
        item(&mut out, "task codels", &task.codels.len().to_string());
    }
    let services: Vec<String> = c
        .services
        .values()
        .filter(|s| s.thread.is_some_and(|r| r.id == id))
        .map(|s| format!("`{}`", s.name.name))
        .collect();
    item(&mut out, "services", &services.join(", "));
    out
}

/// The codel's service, function, WCET, outcomes and cleanup codel.
pub fn codel(c: &Component, id: CodelId) -> String {
    let Some(k) = c.codels.get(id) else {
        return String::new();
    };
    let mut out = format!("**{} codel** `{}`\n\n", k.kind.keyword(), c.codel_label(id));
    let function = k.call.as_ref().map(|f| format!("`{}`", f.function.name));
    item(&mut out, "function", &function.unwrap_or_default());
    item(
        &mut out,
        "wcet",
        &k.wcet.as_ref().map(time).unwrap_or_default(),
    );
    let service = c.services.get(k.service);
    let outcomes: Vec<String> = k
        .outcomes()
        .into_iter()
        .map(|o| match o {
            Outcome::Codel(next) => c
                .codels
                .get(next)
                .map_or_else(String::new, |n| format!("`{}`", n.name.name)),
            Outcome::Report(r) => service
                .and_then(|s| s.reports.get(r))
                .map_or_else(String::new, |n| format!("`{}`", n.name)),
            Outcome::End => "`end`".to_owned(),
        })
        .collect();
    item(&mut out, "next", &outcomes.join(", "));
    let on_inter = k
        .on_inter
        .and_then(|r| c.codels.get(r.id))
        .map(|n| format!("`{}`", n.name.name));
    item(&mut out, "on-inter", &on_inter.unwrap_or_default());
    if let Some(info) = c
        .genom3
        .as_ref()
        .and_then(|g| g.codels.iter().find(|i| i.codel == id))
    {
        let yields: Vec<String> = info
            .fsm
            .yields
            .iter()
            .map(|y| format!("`{}{}`", if y.pause { "pause::" } else { "" }, y.state.name))
            .collect();
        item(&mut out, "yields", &yields.join(", "));
        if info.fsm.is_async {
            item(&mut out, "async", "yes");
        }
    }
    out
}
