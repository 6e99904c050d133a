//! The `config` export of a GenoM3 component ([`Genom3Config`]): what
//! GenoM3's execution engine runs, as the check verified it. Each codel
//! is listed once as written (its C function and the states it runs in),
//! with the WCET assumed in each state and what it locks (GenoM3's
//! `param_mutex`: the ids members and ports of its parameters); each
//! service with its worst-case response time when the check computed it;
//! the WCET file and the instance bound the verdicts rest on, with the
//! file's SHA-256.

use genom_model::component::genom3::{FsmCodel, Genom3Info, ParamSource};
use genom_model::component::{CodelId, Component, Service, ServiceId};
use genom_model::kinds::CodelKind;
use genom_model::response::Bound;

use super::genom3_document::*;
use super::{SourceHash, param, sha256_hex, verification};
use crate::ExportInput;
use genom_model::component::types::TypeTable;

/// The value of the `format` field of a GenoM3 configuration.
pub const FORMAT: &str = "genom-check/genom3-runtime-config";

/// Builds the document of a GenoM3 component (`g`: its GenoM3 facts).
pub fn build(input: &ExportInput<'_>, g: &Genom3Info) -> Genom3Config {
    let c = input.component;
    Genom3Config {
        format: FORMAT.to_owned(),
        format_version: super::FORMAT_VERSION,
        verified: input.verification.verified,
        component: component(c, g),
        ports: g
            .ports
            .iter()
            .map(|p| G3Port {
                name: p.name.name.clone(),
                direction: if p.is_out {
                    PortDirection::Out
                } else {
                    PortDirection::In
                },
                multiple: p.multiple,
                ty: c.types.display(&p.ty),
            })
            .collect(),
        tasks: tasks(c, g),
        services: c.services.ids().map(|id| service(input, g, id)).collect(),
        assumptions: assumptions(input),
        verification: verification(input),
    }
}

fn component(c: &Component, g: &Genom3Info) -> G3ComponentInfo {
    let names =
        |list: &[genom_model::component::Named]| list.iter().map(|n| n.name.clone()).collect();
    G3ComponentInfo {
        name: c.name.name.clone(),
        version: c.version.clone(),
        lang: c.lang.as_ref().map(|n| n.name.clone()),
        email: g.email.clone(),
        doc: c.doc.clone(),
        require: g.require.clone(),
        codels_require: g.codels_require.clone(),
        clock_rate_ns: g.clock_rate.map(|d| d.ns),
        provides: names(&g.provides),
        uses: names(&g.uses),
    }
}

fn tasks(c: &Component, g: &Genom3Info) -> Vec<G3Task> {
    c.threads
        .iter()
        .map(|(tid, t)| {
            let info = g.tasks.iter().find(|k| k.thread == tid);
            let codels = info.map_or_else(Vec::new, |k| {
                k.codels
                    .iter()
                    .map(|f| codel(f, |_| f.wcet.map(|d| d.ns)))
                    .collect()
            });
            G3Task {
                name: t.name.name.clone(),
                period_ns: t.period.map(|d| d.ns),
                delay_ns: info.and_then(|k| k.delay).map_or(0, |d| d.ns),
                priority: t.priority,
                stack_bytes: t.stack,
                scheduling: if info.is_some_and(|k| k.real_time) {
                    Scheduling::RealTime
                } else {
                    Scheduling::Default
                },
                throws: info.map_or_else(Vec::new, |k| {
                    k.throws.iter().map(|n| n.name.clone()).collect()
                }),
                codels,
                activities: c
                    .services
                    .values()
                    .filter(|s| s.thread.is_some_and(|r| r.id == tid))
                    .map(|s| s.name.name.clone())
                    .collect(),
            }
        })
        .collect()
}

fn service(input: &ExportInput<'_>, g: &Genom3Info, id: ServiceId) -> G3Service {
    let c = input.component;
    let s = &c.services[id];
    let info = g.services.iter().find(|i| i.service == id);
    let names = |ids: &mut dyn Iterator<Item = ServiceId>| -> Vec<String> {
        ids.filter_map(|x| c.services.get(x))
            .map(|x| x.name.name.clone())
            .collect()
    };
    let interrupts_all = info.is_some_and(|i| i.interrupts_all);
    let (validate, codels) = service_codels(c, g, s);
    G3Service {
        name: s.name.name.clone(),
        kind: match info.map(|i| i.kind.as_str()) {
            Some("activity") => G3ServiceKind::Activity,
            Some("attribute") => G3ServiceKind::Attribute,
            _ => G3ServiceKind::Function,
        },
        doc: s.doc.clone(),
        task: s
            .thread
            .and_then(|r| c.threads.get(r.id))
            .map(|t| t.name.name.clone()),
        interrupts: names(&mut s.stops.iter().map(|r| r.id)),
        interrupts_all,
        after: names(&mut info.iter().flat_map(|i| i.after.iter().map(|r| r.id))),
        before: names(&mut info.iter().flat_map(|i| i.before.iter().map(|r| r.id))),
        throws: s.reports.iter().map(|r| r.name.clone()).collect(),
        inputs: s.inputs.iter().map(|p| param(c, p)).collect(),
        outputs: s.outputs.iter().map(|p| param(c, p)).collect(),
        validate,
        codels,
        response_time: input
            .verification
            .response_times
            .iter()
            .find(|r| r.service == s.name.name)
            .map(|r| G3ResponseTime {
                status: match r.worst {
                    Bound::Exact(_) => ResponseStatus::Exact,
                    Bound::AtMost(_) => ResponseStatus::AtMost,
                    Bound::Above(_) => ResponseStatus::Above,
                    Bound::Unbounded => ResponseStatus::Unbounded,
                    Bound::Unknown => ResponseStatus::Unknown,
                },
                worst_ns: r.worst.ns(),
                note: r.note.clone(),
            }),
    }
}

/// A service's `validate` and its other codels, each FSM codel once (in
/// the order of its first state), with the WCET of each state.
fn service_codels(c: &Component, g: &Genom3Info, s: &Service) -> (Option<G3Codel>, Vec<G3Codel>) {
    let wcet = |k: CodelId| c.codels.get(k).and_then(|k| k.wcet).map(|d| d.ns);
    let mut validate = None;
    let mut listed: Vec<(&FsmCodel, Vec<CodelId>)> = Vec::new();
    for &k in &s.codels {
        let Some(info) = g.codels.iter().find(|i| i.codel == k) else {
            continue;
        };
        let control = c
            .codels
            .get(k)
            .is_some_and(|m| m.kind == CodelKind::Control);
        if control && c.codels[k].name.name == "validate" {
            validate = Some(control_codel(&info.fsm, "validate", wcet(k)));
            continue;
        }
        if control {
            listed.push((&info.fsm, vec![k]));
        } else if let Some(entry) = listed.iter_mut().find(|(f, _)| f.span == info.fsm.span) {
            entry.1.push(k);
        } else {
            listed.push((&info.fsm, vec![k]));
        }
    }
    let codels = listed
        .into_iter()
        .map(|(fsm, states)| {
            if states.len() == 1 && c.codels[states[0]].kind == CodelKind::Control {
                control_codel(fsm, &c.codels[states[0]].name.name, wcet(states[0]))
            } else {
                let by_state = |name: &str| {
                    states
                        .iter()
                        .find(|&&k| c.codels[k].name.name == name)
                        .and_then(|&k| wcet(k))
                };
                codel(fsm, by_state)
            }
        })
        .collect();
    (validate, codels)
}

/// A control-task codel: it runs in one pseudo-state (`validate`,
/// `codel`, `codel2`...) and yields nothing.
fn control_codel(fsm: &FsmCodel, state: &str, wcet_ns: Option<u64>) -> G3Codel {
    G3Codel {
        states: vec![G3State {
            name: state.to_owned(),
            wcet_ns,
        }],
        yields: Vec::new(),
        ..codel(fsm, |_| None)
    }
}

/// An FSM codel, the WCET of each of its states by `wcet_of`.
fn codel(fsm: &FsmCodel, wcet_of: impl Fn(&str) -> Option<u64>) -> G3Codel {
    G3Codel {
        function: fsm.function.name.clone(),
        states: fsm
            .states
            .iter()
            .map(|st| G3State {
                name: st.name.clone(),
                wcet_ns: wcet_of(&st.name),
            })
            .collect(),
        yields: fsm
            .yields
            .iter()
            .map(|y| G3Yield {
                state: y.state.name.clone(),
                pause: y.pause,
            })
            .collect(),
        is_async: fsm.is_async,
        locks: if fsm.is_async { Vec::new() } else { locks(fsm) },
    }
}

/// The ids members, ports and remotes of a codel's parameters (`local`
/// parameters lock nothing).
fn locks(fsm: &FsmCodel) -> Vec<G3Lock> {
    fsm.params
        .iter()
        .filter_map(|p| {
            let kind = match p.source {
                ParamSource::Ids => LockKind::Ids,
                ParamSource::Port => LockKind::Port,
                ParamSource::Remote => LockKind::Remote,
                ParamSource::Local => return None,
            };
            let path = p
                .path
                .trim()
                .trim_start_matches("::ids")
                .trim_start_matches('.');
            let name = match kind {
                LockKind::Ids if path.is_empty() => "::ids".to_owned(),
                LockKind::Ids => path.to_owned(),
                // A port or remote is locked whole, whatever the member.
                LockKind::Port | LockKind::Remote => path
                    .split(['.', '['])
                    .next()
                    .unwrap_or(path)
                    .trim()
                    .to_owned(),
            };
            Some(G3Lock {
                kind,
                name,
                writes: p.dir != "in",
            })
        })
        .collect()
}

/// The WCET file (with its hash, from the loaded sources) and the
/// instance bound of the check's assumptions.
fn assumptions(input: &ExportInput<'_>) -> G3Assumptions {
    let list = &input.verification.assumptions;
    let wcet_file = list
        .iter()
        .find_map(|a| a.file.as_deref())
        .and_then(|path| {
            let (_, file) = input
                .sources
                .files()
                .find(|(_, f)| f.display_path() == path)?;
            Some(SourceHash {
                path: path.to_owned(),
                sha256: sha256_hex(file.text.as_bytes()),
            })
        });
    G3Assumptions {
        wcet_file,
        max_instances: list
            .iter()
            .find_map(|a| a.bound)
            .map(|n| u64::try_from(n).unwrap_or(u64::MAX)),
        statements: list.iter().map(|a| a.text.clone()).collect(),
    }
}
