//! GenoM3's own static checks on every state machine (an activity's codels,
//! or a task's permanent codels): a `codel<start>` exists, every yield
//! names a state (or `ether`), every state is reachable from `start`,
//! `stop` can reach `ether`; and an `async` codel shares no ids member with
//! a codel of another task.

use std::collections::{BTreeMap, BTreeSet, VecDeque};

use genom_model::Span;
use genom_model::component::ThreadId;
use genom_model::component::genom3::{FsmCodel, ParamSource};

use super::closest_hint;
use super::component::Ctx;
use crate::diagnostics;

/// Runs every check on the machines collected while lowering.
pub(crate) fn run(ctx: &mut Ctx<'_>) {
    let machines = std::mem::take(&mut ctx.machines);
    for (owner, span, codels, _) in &machines {
        let what = if ctx.c.thread_named(owner).is_some() && ctx.c.service_named(owner).is_none() {
            "task"
        } else {
            "activity"
        };
        machine(ctx, what, owner, *span, codels);
    }
    async_sharing(ctx, &machines);
    prototypes(ctx, &machines);
    ctx.machines = machines;
}

fn machine(ctx: &mut Ctx<'_>, what: &str, owner: &str, span: Span, codels: &[FsmCodel]) {
    if codels.is_empty() {
        return;
    }
    let mut states: BTreeMap<&str, Span> = BTreeMap::new();
    for c in codels {
        for s in &c.states {
            states.entry(s.name.as_str()).or_insert(s.span);
        }
    }
    if !states.contains_key("start") {
        ctx.diags
            .push(diagnostics::missing_start(what, owner, span));
    }
    let names: Vec<String> = states.keys().map(|s| (*s).to_owned()).collect();
    for c in codels {
        for y in &c.yields {
            let n = y.state.name.as_str();
            if n != "ether" && !states.contains_key(n) {
                let hint = closest_hint(n, names.iter());
                ctx.diags.push(diagnostics::unknown_state(
                    n,
                    y.state.span,
                    owner,
                    hint.as_deref(),
                ));
            }
        }
    }
    let reach = |from: &str| reachable(codels, from);
    let reach_states = |from: &str| -> BTreeSet<String> {
        let mut out: BTreeSet<String> = reach(from)
            .iter()
            .flat_map(|&i| codels[i].yields.iter().map(|y| y.state.name.clone()))
            .collect();
        out.insert(from.to_owned());
        out
    };
    // A codel is reached when one of its states is: it then runs in all of
    // them.
    let mut reached = reach("start");
    reached.extend(reach("stop"));
    for (i, c) in codels.iter().enumerate() {
        if !reached.contains(&i) {
            for s in &c.states {
                ctx.diags
                    .push(diagnostics::unreachable_state(&s.name, s.span, owner));
            }
        }
    }
    if let Some(stop) = states.get("stop") {
        if !reach_states("stop").contains("ether") {
            ctx.diags.push(diagnostics::stop_no_ether(owner, *stop));
        }
    }
}

/// The ids members (first path element) a codel uses, with whether it may
/// write them.
fn ids_members(c: &FsmCodel) -> BTreeMap<String, bool> {
    let mut out: BTreeMap<String, bool> = BTreeMap::new();
    for p in c.params.iter().filter(|p| p.source == ParamSource::Ids) {
        let root = p
            .path
            .split(['.', '['])
            .next()
            .unwrap_or_default()
            .to_owned();
        *out.entry(root).or_default() |= p.dir != "in";
    }
    out
}

/// A shared member where at least one side writes.
fn conflict(a: &BTreeMap<String, bool>, b: &BTreeMap<String, bool>) -> Option<String> {
    a.iter()
        .find(|(m, w)| b.get(*m).is_some_and(|v| **w || *v) || (m.is_empty() && !b.is_empty()))
        .map(|(m, _)| {
            if m.is_empty() {
                "ids".to_owned()
            } else {
                m.clone()
            }
        })
}

/// An `async` codel runs without its task's ids lock: it may share no ids
/// member (one side writing) with a codel of another task, or with a
/// control codel. A task's `start` codel and codels only reached from
/// `stop` do not run concurrently with it and are exempt.
fn async_sharing(ctx: &mut Ctx<'_>, machines: &[(String, Span, Vec<FsmCodel>, Option<ThreadId>)]) {
    let mut others: Vec<(String, Option<ThreadId>, &FsmCodel)> = Vec::new();
    for (owner, _, codels, thread) in machines {
        let is_task = ctx.c.service_named(owner).is_none();
        let from_start = reachable(codels, "start");
        for (i, c) in codels.iter().enumerate() {
            if is_task && (c.states.iter().any(|s| s.name == "start") || !from_start.contains(&i)) {
                continue;
            }
            others.push((owner.clone(), *thread, c));
        }
    }
    let controls: Vec<(String, FsmCodel)> = ctx
        .g
        .codels
        .iter()
        .filter(|i| {
            ctx.c
                .codels
                .get(i.codel)
                .is_some_and(|c| c.kind == genom_model::kinds::CodelKind::Control)
        })
        .map(|i| {
            (
                ctx.c.services[ctx.c.codels[i.codel].service]
                    .name
                    .name
                    .clone(),
                i.fsm.clone(),
            )
        })
        .collect();
    let mut found = Vec::new();
    for (owner, _, codels, thread) in machines {
        for c in codels.iter().filter(|c| c.is_async) {
            let mine = ids_members(c);
            let clash = others
                .iter()
                .filter(|(_, t, _)| t != thread)
                .map(|(o, _, x)| (o, *x))
                .chain(controls.iter().map(|(o, x)| (o, x)))
                .find_map(|(o, x)| {
                    conflict(&mine, &ids_members(x))
                        .map(|m| (o.clone(), x.function.name.clone(), x.span, m))
                });
            if let Some((other_owner, other_fn, other_span, member)) = clash {
                found.push(diagnostics::async_shared(
                    &format!("{owner}::{}", c.function.name),
                    &member,
                    c.span,
                    &format!("{other_owner}::{other_fn}"),
                    other_span,
                ));
            }
        }
    }
    ctx.diags.extend(found);
}

/// The codels (indices) reached from the codel running in state `from`,
/// following yields: linear in the machine's size (up to the index's log).
fn reachable(codels: &[FsmCodel], from: &str) -> BTreeSet<usize> {
    // The first codel running in each state, as a linear search would find.
    let mut owner: BTreeMap<&str, usize> = BTreeMap::new();
    for (i, c) in codels.iter().enumerate() {
        for s in &c.states {
            owner.entry(s.name.as_str()).or_insert(i);
        }
    }
    let mut seen = BTreeSet::new();
    let mut queue: VecDeque<usize> = owner.get(from).copied().into_iter().collect();
    while let Some(i) = queue.pop_front() {
        if !seen.insert(i) {
            continue;
        }
        queue.extend(
            codels[i]
                .yields
                .iter()
                .filter_map(|y| owner.get(y.state.name.as_str()).copied())
                .filter(|j| !seen.contains(j)),
        );
    }
    seen
}

/// One codel function used with different prototypes (number of
/// parameters or directions): genom3's "conflicting types for codel".
fn prototypes(ctx: &mut Ctx<'_>, machines: &[(String, Span, Vec<FsmCodel>, Option<ThreadId>)]) {
    let mut all: Vec<&FsmCodel> = machines.iter().flat_map(|m| m.2.iter()).collect();
    let controls: Vec<FsmCodel> = ctx.g.codels.iter().map(|i| i.fsm.clone()).collect();
    all.extend(controls.iter());
    let mut seen: BTreeMap<&str, &FsmCodel> = BTreeMap::new();
    let mut found = Vec::new();
    for c in all {
        let shape =
            |c: &FsmCodel| -> Vec<String> { c.params.iter().map(|p| p.dir.clone()).collect() };
        match seen.get(c.function.name.as_str()) {
            Some(first)
                if !std::ptr::eq(*first, c) && shape(first) != shape(c) && first.span != c.span =>
            {
                found.push(diagnostics::prototype_mismatch(
                    &c.function.name,
                    (c.function.span, c.params.len()),
                    (first.function.span, first.params.len()),
                ));
            }
            Some(_) => {}
            None => {
                seen.insert(c.function.name.as_str(), c);
            }
        }
    }
    ctx.diags.extend(found);
}
