//! The `config` export: the verified runtime configuration of the component
//! as one JSON document, for the execution engine. It carries what the
//! engine needs to run the component as it was verified (threads with their
//! periods, services with their compatibility matrix, codels with their
//! outcome tables and WCETs, the lock groups) and the evidence of the
//! verification (verdict, properties proven, SHA-256 of every source file).
//!
//! The document is described by Rust types deriving [`serde::Serialize`]
//! and [`schemars::JsonSchema`]; [`schema`] gives its JSON Schema, committed
//! as `export/schema/runtime-config.schema.json`. The output is
//! deterministic: fields in declaration order, lists in source order, maps
//! with sorted keys, no timestamp.

use genom_model::Counts;
use genom_model::SourceMap;
use genom_model::component::types::TypeTable;
use genom_model::component::{
    Codel, CodelId, Component, DataPath, DataRoot, Outcome, Param, ServiceId, StructureId, Value,
};
use genom_model::kinds::{CodelKind, DataKind, ServiceKind};
use sha2::{Digest, Sha256};

use crate::{ExportError, ExportInput, Exported};

/// The value of the `format` field.
pub const FORMAT: &str = "genom-check/runtime-config";

/// The version of the document layout (`format_version`).
pub const FORMAT_VERSION: u32 = 1;

/// The name of the implicit control thread, as used in `lock_groups`.
pub const CONTROL_THREAD: &str = "control";

mod document;
pub mod genom3;
mod genom3_document;

pub use document::*;
pub use genom3_document::*;

/// Exports the component as its runtime configuration (JSON): a GenoM3
/// component's in GenoM3's terms ([`genom3::build`]), a LANGUAGE.md
/// component's as [`build`] writes it.
pub fn export(input: &ExportInput<'_>) -> Result<Exported, ExportError> {
    let text = match &input.component.genom3 {
        Some(g) => serde_json::to_string_pretty(&genom3::build(input, g)),
        None => serde_json::to_string_pretty(&build(input)),
    };
    let mut text = text.map_err(|e| ExportError::Unsupported {
        format: "config",
        reason: e.to_string(),
    })?;
    text.push('\n');
    Ok(Exported::single(text))
}

/// The JSON Schema of the LANGUAGE.md document, pretty-printed with a
/// final newline.
pub fn schema() -> String {
    schema_text(&schemars::schema_for!(RuntimeConfig))
}

/// The JSON Schema of the GenoM3 document ([`Genom3Config`]),
/// pretty-printed with a final newline.
pub fn genom3_schema() -> String {
    schema_text(&schemars::schema_for!(Genom3Config))
}

fn schema_text(schema: &schemars::Schema) -> String {
    let mut text = serde_json::to_string_pretty(schema).unwrap_or_default();
    text.push('\n');
    text
}

/// Builds the document.
pub fn build(input: &ExportInput<'_>) -> RuntimeConfig {
    let c = input.component;
    RuntimeConfig {
        format: FORMAT.to_owned(),
        format_version: FORMAT_VERSION,
        verified: input.verification.verified,
        component: component(c),
        threads: c
            .threads
            .values()
            .map(|t| ThreadInfo {
                name: t.name.name.clone(),
                period_ns: t.period.map(|d| d.ns),
                priority: t.priority,
                stack_bytes: t.stack,
                start_hook: t.start_hook.as_ref().map(|h| h.name.clone()),
                stop_hook: t.stop_hook.as_ref().map(|h| h.name.clone()),
            })
            .collect(),
        services: c.services.ids().map(|id| service(c, id)).collect(),
        codels: c.codels.iter().map(|(id, k)| codel(c, id, k)).collect(),
        lock_groups: lock_groups(c),
        verification: verification(input),
    }
}

fn component(c: &Component) -> ComponentInfo {
    ComponentInfo {
        name: c.name.name.clone(),
        category: c
            .category
            .as_ref()
            .map_or_else(|| "default".to_owned(), |n| n.name.clone()),
        lang: c.lang.as_ref().map(|n| n.name.clone()),
        version: c.version.clone(),
        doc: c.doc.clone(),
        credentials: c.credentials.iter().map(|n| n.name.clone()).collect(),
    }
}

/// How references to whole structures are written (`demoExport.state`).
fn structure_names(
    c: &Component,
    refs: &[genom_model::component::Ref<StructureId>],
) -> Vec<String> {
    refs.iter()
        .filter_map(|r| c.structures.get(r.id))
        .map(genom_model::component::Structure::path)
        .collect()
}

fn service(c: &Component, id: ServiceId) -> ServiceInfo {
    let s = &c.services[id];
    let codel_name =
        |k: Option<CodelId>| k.and_then(|k| c.codels.get(k)).map(|k| k.name.name.clone());
    let compatibility = c
        .services
        .iter()
        .map(|(other, o)| (o.name.name.clone(), compatibility(c, id, other)))
        .collect();
    let init = c.init_service();
    ServiceInfo {
        name: s.name.name.clone(),
        kind: match s.kind {
            ServiceKind::Plain => ServiceKindInfo::Plain,
            ServiceKind::Init => ServiceKindInfo::Init,
            ServiceKind::Auto => ServiceKindInfo::Auto,
        },
        doc: s.doc.clone(),
        thread: s
            .thread
            .and_then(|t| c.threads.get(t.id))
            .map(|t| t.name.name.clone()),
        max_time_ns: s.max_time.map(|d| d.ns),
        credential: c.credential_name(s.credential).to_owned(),
        requires_init: init.is_some_and(|i| i != id),
        reports: s.reports.iter().map(|r| r.name.clone()).collect(),
        inputs: s.inputs.iter().map(|p| param(c, p)).collect(),
        outputs: s.outputs.iter().map(|p| param(c, p)).collect(),
        imports: structure_names(c, &s.imports),
        exports: structure_names(c, &s.exports),
        control_codel: codel_name(s.control),
        start_codel: codel_name(s.start),
        codels: s
            .codels
            .iter()
            .filter_map(|&k| c.codels.get(k))
            .map(|k| k.name.name.clone())
            .collect(),
        compatibility,
    }
}

/// How a request of `this` is handled while `other` has an instance,
/// in the order of the request-handling steps of LANGUAGE.md section 3.
fn compatibility(c: &Component, this: ServiceId, other: ServiceId) -> Compatibility {
    let lists = |list: &[genom_model::component::Ref<ServiceId>], x: ServiceId| {
        list.iter().any(|r| r.id == x)
    };
    let (s, o) = (&c.services[this], &c.services[other]);
    let entry = Compatibility {
        request: RequestOutcome::Concurrent,
        stops: lists(&s.stops, other),
        delays: lists(&s.delays, other),
        forbids: lists(&s.forbids, other),
        stopped_by: lists(&o.stops, this),
        delayed_by: lists(&o.delays, this),
        forbidden_by: lists(&o.forbids, this),
    };
    let same = this == other;
    let request = if entry.forbidden_by && !same {
        RequestOutcome::Forbidden
    } else if same && !entry.stops {
        RequestOutcome::Busy
    } else if entry.stops {
        RequestOutcome::Interrupts
    } else if entry.delayed_by && !same {
        RequestOutcome::Waits
    } else {
        RequestOutcome::Concurrent
    };
    Compatibility { request, ..entry }
}

fn param(c: &Component, p: &Param) -> ParamInfo {
    ParamInfo {
        name: p.name.name.clone(),
        ty: c.types.display(&p.ty),
        default: p.default.as_ref().map(json_value),
        doc: p.doc.clone(),
        data: p.data.as_ref().and_then(|d| data_ref(c, d)),
    }
}

/// A model value as JSON: enum values by name, structs as objects with
/// their fields in declaration order.
fn json_value(v: &Value) -> serde_json::Value {
    use serde_json::Value as J;
    match v {
        Value::Int(i) => {
            if let Ok(n) = i64::try_from(*i) {
                J::from(n)
            } else if let Ok(n) = u64::try_from(*i) {
                J::from(n)
            } else {
                J::String(i.to_string())
            }
        }
        Value::Float(f) => serde_json::Number::from_f64(*f).map_or(J::Null, J::Number),
        Value::Bool(b) => J::Bool(*b),
        Value::Str(s) | Value::Enum(s) => J::String(s.clone()),
        Value::Struct(fields) => J::Object(
            fields
                .iter()
                .map(|(k, v)| (k.clone(), json_value(v)))
                .collect(),
        ),
        Value::List(items) => J::Array(items.iter().map(json_value).collect()),
    }
}

fn data_kind(kind: DataKind) -> DataKindInfo {
    match kind {
        DataKind::Ids => DataKindInfo::Ids,
        DataKind::Export => DataKindInfo::Export,
        DataKind::Import => DataKindInfo::Import,
    }
}

fn data_ref(c: &Component, d: &DataPath) -> Option<DataRef> {
    Some(match d.root {
        DataRoot::Structure(id) => {
            let s = c.structures.get(id)?;
            DataRef::Structure {
                structure: s.path(),
                kind: data_kind(s.kind),
                path: d.text.clone(),
            }
        }
        DataRoot::Param {
            service,
            output,
            index,
        } => {
            let s = c.services.get(service)?;
            let list = if output { &s.outputs } else { &s.inputs };
            let param = list.get(index)?.name.name.clone();
            if output {
                DataRef::Output {
                    param,
                    path: d.text.clone(),
                }
            } else {
                DataRef::Input {
                    param,
                    path: d.text.clone(),
                }
            }
        }
    })
}

/// The thread running a codel: `control` for control codels.
fn codel_thread(c: &Component, k: &Codel) -> Option<String> {
    if k.kind == CodelKind::Control {
        return Some(CONTROL_THREAD.to_owned());
    }
    let t = c.services.get(k.service)?.thread?;
    c.threads.get(t.id).map(|t| t.name.name.clone())
}

/// The outcome table of a codel (empty for a control codel).
fn outcomes(c: &Component, k: &Codel) -> Vec<OutcomeInfo> {
    if k.kind == CodelKind::Control {
        return Vec::new();
    }
    let service = c.services.get(k.service);
    k.outcomes()
        .into_iter()
        .filter_map(|o| match o {
            Outcome::Codel(target) => c.codels.get(target).map(|t| OutcomeInfo::Codel {
                codel: t.name.name.clone(),
            }),
            Outcome::Report(r) => {
                service
                    .and_then(|s| s.reports.get(r))
                    .map(|r| OutcomeInfo::Report {
                        report: r.name.clone(),
                    })
            }
            Outcome::End => Some(OutcomeInfo::End),
        })
        .collect()
}

fn codel(c: &Component, id: CodelId, k: &Codel) -> CodelInfo {
    let service = c.services.get(k.service);
    CodelInfo {
        id: c.codel_label(id),
        service: service.map(|s| s.name.name.clone()).unwrap_or_default(),
        kind: match k.kind {
            CodelKind::Start => CodelKindInfo::Start,
            CodelKind::Control => CodelKindInfo::Control,
            CodelKind::Exec => CodelKindInfo::Exec,
            CodelKind::Inter => CodelKindInfo::Inter,
        },
        name: k.name.name.clone(),
        thread: codel_thread(c, k),
        function: k.call.as_ref().map(|call| call.function.name.clone()),
        args: k
            .call
            .iter()
            .flat_map(|call| call.args.iter())
            .map(|a| ArgInfo {
                is_const: a.is_const,
                ty: a.data.as_ref().map(|d| c.types.display(&d.ty)),
                data: a.data.as_ref().and_then(|d| data_ref(c, d)),
            })
            .collect(),
        update: k.update.iter().filter_map(|d| data_ref(c, d)).collect(),
        on_inter: k
            .on_inter
            .and_then(|r| c.codels.get(r.id))
            .map(|t| t.name.name.clone()),
        wcet_ns: k.wcet.map(|d| d.ns),
        next: outcomes(c, k),
    }
}

/// A codel, its thread and the structures it uses (`true`: writes).
type CodelUse = (CodelId, Option<String>, Vec<(StructureId, bool)>);

fn lock_groups(c: &Component) -> LockGroups {
    let used: Vec<CodelUse> = c
        .codels
        .iter()
        .map(|(id, k)| (id, codel_thread(c, k), k.structures()))
        .collect();
    let structures = c
        .structures
        .iter()
        .map(|(sid, s)| LockGroup {
            structure: s.path(),
            kind: data_kind(s.kind),
            ty: c.types.display(&s.ty),
            users: used
                .iter()
                .filter_map(|(id, thread, list)| {
                    let &(_, writes) = list.iter().find(|(x, _)| *x == sid)?;
                    Some(LockUser {
                        codel: c.codel_label(*id),
                        thread: thread.clone(),
                        writes,
                    })
                })
                .collect(),
        })
        .collect();
    LockGroups {
        structures,
        conflicts: conflicts(c, &used),
    }
}

/// Every pair of codels of different threads that conflict, in codel order.
fn conflicts(c: &Component, used: &[CodelUse]) -> Vec<Conflict> {
    let mut conflicts = Vec::new();
    for (i, (a, ta, sa)) in used.iter().enumerate() {
        for (b, tb, sb) in used.iter().skip(i + 1) {
            if ta == tb {
                continue;
            }
            let shared: Vec<String> = sa
                .iter()
                .filter(|&&(s, wa)| sb.iter().any(|&(t, wb)| s == t && (wa || wb)))
                .filter_map(|&(s, _)| {
                    c.structures
                        .get(s)
                        .map(genom_model::component::Structure::path)
                })
                .collect();
            if !shared.is_empty() {
                conflicts.push(Conflict {
                    a: c.codel_label(*a),
                    b: c.codel_label(*b),
                    structures: shared,
                });
            }
        }
    }
    conflicts
}

fn verification(input: &ExportInput<'_>) -> VerificationInfo {
    let v = input.verification;
    let mut files = hashes(input.sources).into_iter();
    let source = files.next().unwrap_or_else(|| SourceHash {
        path: String::new(),
        sha256: sha256_hex(b""),
    });
    VerificationInfo {
        tool: "genom-check".to_owned(),
        tool_version: v.tool_version.clone(),
        source,
        includes: files.collect(),
        counts: counts(v.counts),
        states: v.states,
        transitions: v.transitions,
        complete: v.complete,
        error_codes: v.error_codes.clone(),
        properties: v
            .properties
            .iter()
            .map(|p| {
                let (property, subject, statement) = crate::verify::describe(input.component, p);
                PropertyInfo {
                    property,
                    subject,
                    statement,
                }
            })
            .collect(),
    }
}

fn counts(c: Counts) -> CountsInfo {
    let n = |x: usize| u64::try_from(x).unwrap_or(u64::MAX);
    CountsInfo {
        errors: n(c.errors),
        warnings: n(c.warnings),
        advice: n(c.advice),
    }
}

/// Every loaded file with the SHA-256 of its text, the checked file first.
fn hashes(sources: &SourceMap) -> Vec<SourceHash> {
    sources
        .files()
        .map(|(_, f)| SourceHash {
            path: f.display_path(),
            sha256: sha256_hex(f.text.as_bytes()),
        })
        .collect()
}

fn sha256_hex(bytes: &[u8]) -> String {
    use std::fmt::Write as _;
    let digest = Sha256::digest(bytes);
    let mut out = String::with_capacity(64);
    for b in &digest {
        let _ = write!(out, "{b:02x}");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sha256_of_empty_and_abc() {
        assert_eq!(
            sha256_hex(b""),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
        );
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }

    #[test]
    fn values_become_json() {
        let v = Value::Struct(vec![
            ("b".into(), Value::Int(-3)),
            (
                "a".into(),
                Value::List(vec![Value::Float(0.5), Value::Bool(true)]),
            ),
            ("m".into(), Value::Enum("RUN".into())),
        ]);
        assert_eq!(
            serde_json::to_string(&json_value(&v)).unwrap_or_default(),
            r#"{"b":-3,"a":[0.5,true],"m":"RUN"}"#
        );
    }
}
