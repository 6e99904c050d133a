//! The WCET side file (GenoM3 has no WCET syntax): one entry per line,
//! `OWNER.STATE DURATION`, `#` starts a comment. OWNER is a service (STATE
//! one of its codel states, or `validate` / `codel` for the control-task
//! codels of a function or attribute) or a task (STATE a state of its
//! permanent codels). Durations are exact: `400us`, `1ms`, `2.5ms`, `10ns`,
//! `1s`, at most one day ([`MAX_DURATION_NS`]); `?` is a placeholder (a
//! codel not measured yet, as a template from `genom-check wcet-template`
//! writes it): its owner and state are checked, and the codel stays
//! without WCET. Unknown owners or states, a duration too long, and a codel
//! given twice are `bad-wcet` errors pointing into the WCET file. A
//! byte-order mark at its start is skipped.

use std::collections::BTreeMap;

use genom_model::component::{Component, Duration};
use genom_model::limits::{MAX_DURATION_NS, duration_too_long};
use genom_model::{Diagnostic, FileId, SourceMap, Span};

use crate::diagnostics;
use crate::lower::closest_hint;

/// One line of the WCET file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WcetEntry {
    /// The service or task.
    pub owner: String,
    /// Where the owner is written.
    pub owner_span: Span,
    /// The state (or `validate`, `codel`).
    pub state: String,
    /// Where the state is written.
    pub state_span: Span,
    /// The WCET in nanoseconds; `None` for the placeholder `?`.
    pub ns: Option<u64>,
    /// Where the duration is written.
    pub span: Span,
}

/// The entries of a WCET file and its syntax diagnostics.
#[derive(Debug, Clone, Default)]
pub struct WcetReturn {
    /// Well-formed entries in file order.
    pub entries: Vec<WcetEntry>,
    /// Malformed lines.
    pub diagnostics: Vec<Diagnostic>,
}

/// Exact nanoseconds of `400us`, `2.5ms`...
pub fn duration_ns(text: &str) -> Option<u64> {
    let split = text.find(|c: char| c.is_ascii_alphabetic())?;
    let (number, unit) = text.split_at(split);
    let scale: u128 = match unit {
        "ns" => 1,
        "us" => 1_000,
        "ms" => 1_000_000,
        "s" => 1_000_000_000,
        _ => return None,
    };
    let (int, frac) = number.split_once('.').unwrap_or((number, ""));
    if int.is_empty() && frac.is_empty()
        || !int.chars().chain(frac.chars()).all(|c| c.is_ascii_digit())
    {
        return None;
    }
    let int: u128 = if int.is_empty() { 0 } else { int.parse().ok()? };
    let mut ns = int.checked_mul(scale)?;
    let mut unit_scale = scale;
    for d in frac.chars() {
        if unit_scale % 10 != 0 {
            return None;
        }
        unit_scale /= 10;
        ns = ns.checked_add(u128::from(d.to_digit(10)?) * unit_scale)?;
    }
    u64::try_from(ns).ok()
}

/// Parses the WCET file `file` of `sources`.
pub fn parse_wcet(sources: &SourceMap, file: FileId) -> WcetReturn {
    let mut out = WcetReturn::default();
    let Some(f) = sources.file(file) else {
        return out;
    };
    let mut offset = 0usize;
    let mut first: BTreeMap<(String, String), Span> = BTreeMap::new();
    for line in f.text.split_inclusive('\n') {
        let start = offset;
        offset += line.len();
        let content = line.split('#').next().unwrap_or("");
        // The BOM is skipped (offsets stay those of the line).
        let content = if start == 0 {
            content.strip_prefix('\u{feff}').unwrap_or(content)
        } else {
            content
        };
        let at = |local: usize, len: usize| {
            let s = f.base + u32::try_from(start + local).unwrap_or(0);
            Span::new(s, s + u32::try_from(len).unwrap_or(0))
        };
        let words: Vec<(usize, &str)> = content
            .split_whitespace()
            .map(|w| (w.as_ptr() as usize - line.as_ptr() as usize, w))
            .collect();
        match words.as_slice() {
            [] => {}
            [(o1, key), (o2, dur)] => {
                let Some((owner, state)) = key.split_once('.') else {
                    out.diagnostics.push(diagnostics::bad_wcet(
                        at(*o1, key.len()),
                        format!("expected `OWNER.STATE`, found `{key}`"),
                        None,
                    ));
                    continue;
                };
                let ns = if *dur == "?" { None } else { duration_ns(dur) };
                if ns.is_none() && *dur != "?" {
                    out.diagnostics.push(diagnostics::bad_wcet(
                        at(*o2, dur.len()),
                        format!(
                            "expected a duration such as `400us` (or `?`, not measured yet), found `{dur}`"
                        ),
                        None,
                    ));
                    continue;
                }
                if ns.is_some_and(|ns| ns > MAX_DURATION_NS) {
                    let d = diagnostics::bad_wcet(at(*o2, dur.len()), duration_too_long(dur), None);
                    out.diagnostics.push(d);
                    continue;
                }
                let here = at(*o1, key.len());
                let key_of = (owner.to_owned(), state.to_owned());
                if let Some(&before) = first.get(&key_of) {
                    let d = diagnostics::bad_wcet(
                        here,
                        format!("`{key}` is given twice in the WCET file"),
                        None,
                    )
                    .with_label(before, "first given here")
                    .with_help("keep one line per codel: which one holds is not guessed");
                    out.diagnostics.push(d);
                    continue;
                }
                first.insert(key_of, here);
                out.entries.push(WcetEntry {
                    owner: owner.to_owned(),
                    owner_span: at(*o1, owner.len()),
                    state: state.to_owned(),
                    state_span: at(*o1 + owner.len() + 1, state.len()),
                    ns,
                    span: at(*o2, dur.len()),
                });
            }
            _ => out.diagnostics.push(diagnostics::bad_wcet(
                at(
                    words[0].0,
                    (content.as_ptr() as usize - line.as_ptr() as usize + content.trim_end().len())
                        .saturating_sub(words[0].0),
                ),
                "expected `OWNER.STATE DURATION`".to_owned(),
                None,
            )),
        }
    }
    out
}

/// Sets the WCET of every codel named by `entries` (a placeholder `?`
/// sets none); returns the `bad-wcet` errors for unknown owners and
/// states.
pub fn apply_wcets(c: &mut Component, entries: &[WcetEntry]) -> Vec<Diagnostic> {
    let mut diags = Vec::new();
    for e in entries {
        let wcet = e.ns.map(|ns| Duration { ns, span: e.span });
        if let Some(sid) = c.service_named(&e.owner) {
            match c.codel_named(sid, &e.state) {
                Some(codel) => {
                    let Some(wcet) = wcet else { continue };
                    c.codels[codel].wcet = Some(wcet);
                    if let Some(info) = c
                        .genom3
                        .as_mut()
                        .and_then(|g| g.codels.iter_mut().find(|i| i.codel == codel))
                    {
                        info.fsm.wcet = Some(wcet);
                    }
                }
                None => {
                    let states: Vec<String> = c.services[sid]
                        .codels
                        .iter()
                        .map(|&k| c.codels[k].name.name.clone())
                        .collect();
                    let hint = closest_hint(&e.state, states.iter());
                    diags.push(diagnostics::bad_wcet(
                        e.state_span,
                        format!("service `{}` has no codel state `{}`", e.owner, e.state),
                        hint.as_deref(),
                    ));
                }
            }
            continue;
        }
        if let Some(tid) = c.thread_named(&e.owner) {
            let task = c
                .genom3
                .as_mut()
                .and_then(|g| g.tasks.iter_mut().find(|t| t.thread == tid));
            let mut states = Vec::new();
            let mut found = false;
            if let Some(task) = task {
                for codel in &mut task.codels {
                    if codel.states.iter().any(|s| s.name == e.state) {
                        if wcet.is_some() {
                            codel.wcet = wcet;
                        }
                        found = true;
                    }
                    states.extend(codel.states.iter().map(|s| s.name.clone()));
                }
            }
            if !found {
                let hint = closest_hint(&e.state, states.iter());
                diags.push(diagnostics::bad_wcet(
                    e.state_span,
                    format!("task `{}` has no codel state `{}`", e.owner, e.state),
                    hint.as_deref(),
                ));
            }
            continue;
        }
        let mut owners: Vec<String> = c.services.values().map(|s| s.name.name.clone()).collect();
        owners.extend(c.threads.values().map(|t| t.name.name.clone()));
        let hint = closest_hint(&e.owner, owners.iter());
        diags.push(diagnostics::bad_wcet(
            e.owner_span,
            format!("no service or task named `{}`", e.owner),
            hint.as_deref(),
        ));
    }
    diags
}

#[cfg(test)]
mod tests {
    use super::duration_ns;

    #[test]
    fn durations_are_exact() {
        assert_eq!(duration_ns("400us"), Some(400_000));
        assert_eq!(duration_ns("1ms"), Some(1_000_000));
        assert_eq!(duration_ns("2.5ms"), Some(2_500_000));
        assert_eq!(duration_ns("1s"), Some(1_000_000_000));
        assert_eq!(duration_ns("0.5ns"), None);
        assert_eq!(duration_ns("10"), None);
        assert_eq!(duration_ns("ms"), None);
        assert_eq!(duration_ns("1h"), None);
    }
}
