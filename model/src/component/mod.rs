//! The resolved component model: every name of the description bound to a
//! typed id, every type resolved through typedefs and modules, every data
//! reference bound to a lockable structure and a member path with its type.
//! The behavioural models (Petri net, timed automata) and the exports are
//! built from this, never from the AST.
//!
//! A reference that did not resolve (already diagnosed) is simply absent
//! (`None`, or left out of a list), so every consumer can walk the model
//! without checking for errors again.

pub mod genom3;
pub mod idx;
mod timing;
pub mod types;

use serde::Serialize;

pub use idx::{IdVec, Idx};
pub use timing::uses_conflict;
pub use types::{Field, Ty, TypeDef, TypeKind, Value};

use crate::define_id;
use crate::kinds::{CodelKind, DataKind, ServiceKind};
use crate::span::Span;

define_id!(
    /// A named type (struct, enum or alias; IDS blocks are anonymous structs).
    TypeId
);
define_id!(
    /// A lockable structure: an IDS block, an export item or an import item.
    StructureId
);
define_id!(
    /// An execution thread (the control thread is implicit and has no id).
    ThreadId
);
define_id!(
    /// A service.
    ServiceId
);
define_id!(
    /// A codel (ids are global to the component).
    CodelId
);

/// A name with the span where it is written.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize)]
pub struct Named {
    /// The name.
    pub name: String,
    /// Where it is written.
    #[serde(skip)]
    pub span: Span,
}

/// A resolved reference with the span of the name that refers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ref<I> {
    /// The target.
    pub id: I,
    /// Where the reference is written.
    pub span: Span,
}

/// A duration in nanoseconds with its span.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Duration {
    /// Nanoseconds (positive).
    pub ns: u64,
    /// Where it is written.
    pub span: Span,
}

/// The default credential order.
pub const DEFAULT_CREDENTIALS: [&str; 3] = ["none", "user", "admin"];

/// A whole component.
#[derive(Debug, Clone, Default)]
pub struct Component {
    /// Its name (span of the name in the `component` item).
    pub name: Named,
    /// `category`, default `default`.
    pub category: Option<Named>,
    /// `lang`.
    pub lang: Option<Named>,
    /// `version`.
    pub version: Option<String>,
    /// `doc`.
    pub doc: Option<String>,
    /// The credential classes, weakest first (`none < user < admin` unless
    /// declared). A service's credential is an index in this list.
    pub credentials: Vec<Named>,
    /// Named types, including one anonymous struct per IDS block.
    pub types: IdVec<TypeId, TypeDef>,
    /// IDL constants.
    pub constants: Vec<Constant>,
    /// Lockable structures.
    pub structures: IdVec<StructureId, Structure>,
    /// Execution threads.
    pub threads: IdVec<ThreadId, Thread>,
    /// Services in source order.
    pub services: IdVec<ServiceId, Service>,
    /// Codels of all services, grouped by service in source order.
    pub codels: IdVec<CodelId, Codel>,
    /// GenoM3-only facts (`None` for a LANGUAGE.md component).
    pub genom3: Option<Box<genom3::Genom3Info>>,
}

/// An IDL constant.
#[derive(Debug, Clone, PartialEq)]
pub struct Constant {
    /// Qualified name (`geo::MAX`).
    pub name: String,
    /// Declared type.
    pub ty: Ty,
    /// Value, when it could be evaluated.
    pub value: Option<Value>,
    /// Where the name is written.
    pub span: Span,
}

/// One lockable structure: an IDS block, or one item of an export or import
/// block.
#[derive(Debug, Clone, PartialEq)]
pub struct Structure {
    /// Which kind of block it comes from.
    pub kind: DataKind,
    /// The IDS block name, or the item name.
    pub name: String,
    /// The block name (the same as `name` for IDS blocks).
    pub block: String,
    /// Where the name is written.
    pub span: Span,
    /// Its type (for an IDS block, the block's anonymous struct).
    pub ty: Ty,
    /// Its initial value, when given.
    pub init: Option<Value>,
    /// Its documentation string.
    pub doc: Option<String>,
}

impl Structure {
    /// How a reference to the whole structure is written: `demoIds`,
    /// `demoExport.state`.
    pub fn path(&self) -> String {
        match self.kind {
            DataKind::Ids => self.name.clone(),
            DataKind::Export | DataKind::Import => format!("{}.{}", self.block, self.name),
        }
    }
}

/// An execution thread.
#[derive(Debug, Clone, PartialEq)]
pub struct Thread {
    /// Its name and span.
    pub name: Named,
    /// Priority (higher runs first; 0 is normal).
    pub priority: i64,
    /// Period; `None` for an aperiodic thread.
    pub period: Option<Duration>,
    /// Stack size in bytes.
    pub stack: Option<u64>,
    /// Hook called at thread creation.
    pub start_hook: Option<Named>,
    /// Hook called at thread deletion.
    pub stop_hook: Option<Named>,
}

/// A service.
#[derive(Debug, Clone, PartialEq)]
pub struct Service {
    /// Its name and span.
    pub name: Named,
    /// Plain, `init` or `auto`.
    pub kind: ServiceKind,
    /// Span of the `init`/`auto` keyword.
    pub kind_span: Option<Span>,
    /// `doc`.
    pub doc: Option<String>,
    /// The thread running its codels.
    pub thread: Option<Ref<ThreadId>>,
    /// Reports it may end with.
    pub reports: Vec<Named>,
    /// Deadline from acknowledgment to final reply.
    pub max_time: Option<Duration>,
    /// Index in [`Component::credentials`] of the weakest class allowed to
    /// request it (0, `none`, when absent).
    pub credential: usize,
    /// Where the credential is written.
    pub credential_span: Option<Span>,
    /// Services whose instances a request of this one interrupts.
    pub stops: Vec<Ref<ServiceId>>,
    /// Services that wait to start while this one has an instance.
    pub delays: Vec<Ref<ServiceId>>,
    /// Services rejected while this one has an instance.
    pub forbids: Vec<Ref<ServiceId>>,
    /// Input parameters.
    pub inputs: Vec<Param>,
    /// Output parameters.
    pub outputs: Vec<Param>,
    /// Imported structures it reads.
    pub imports: Vec<Ref<StructureId>>,
    /// Exported structures it produces.
    pub exports: Vec<Ref<StructureId>>,
    /// Its codels in source order.
    pub codels: Vec<CodelId>,
    /// Its start codel.
    pub start: Option<CodelId>,
    /// Its control codel.
    pub control: Option<CodelId>,
    /// Some `next` of its codels names nothing (already diagnosed): checks
    /// that need every outcome of the service (`unused-report`) skip it.
    pub unresolved_next: bool,
}

impl Service {
    /// A service with only its name and kind: no thread, codels or rules
    /// yet (each front-end fills them in as it resolves the body).
    pub fn empty(name: Named, kind: ServiceKind, kind_span: Option<Span>) -> Self {
        Service {
            name,
            kind,
            kind_span,
            doc: None,
            thread: None,
            reports: Vec::new(),
            max_time: None,
            credential: 0,
            credential_span: None,
            stops: Vec::new(),
            delays: Vec::new(),
            forbids: Vec::new(),
            inputs: Vec::new(),
            outputs: Vec::new(),
            imports: Vec::new(),
            exports: Vec::new(),
            codels: Vec::new(),
            start: None,
            control: None,
            unresolved_next: false,
        }
    }
}

impl Service {
    /// True when the service runs on an execution thread (has a start codel).
    pub fn runs_on_thread(&self) -> bool {
        self.start.is_some()
    }

    /// The report with this name.
    pub fn report(&self, name: &str) -> Option<usize> {
        self.reports.iter().position(|r| r.name == name)
    }
}

/// A service input or output parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    /// Its name: the declared name, or the last member of an IDS reference.
    pub name: Named,
    /// Its type.
    pub ty: Ty,
    /// For a reference into an IDS, the data it is stored into (input) or
    /// read from (output).
    pub data: Option<DataPath>,
    /// Default value.
    pub default: Option<Value>,
    /// Documentation string.
    pub doc: Option<String>,
}

/// A resolved data reference: a root and a member path, with its type.
#[derive(Debug, Clone, PartialEq)]
pub struct DataPath {
    /// What the path starts from.
    pub root: DataRoot,
    /// Member and index steps after the root structure.
    pub steps: Vec<Step>,
    /// The type of the designated data.
    pub ty: Ty,
    /// The reference as written (`demoExport.state.position`).
    pub text: String,
    /// Where it is written.
    pub span: Span,
}

impl DataPath {
    /// The lockable structure the path designates data in, if any.
    pub fn structure(&self) -> Option<StructureId> {
        match self.root {
            DataRoot::Structure(id) => Some(id),
            DataRoot::Param { .. } => None,
        }
    }
}

/// The root of a data reference.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum DataRoot {
    /// A lockable structure.
    Structure(StructureId),
    /// A parameter of the codel's own service.
    Param {
        /// The service.
        service: ServiceId,
        /// An output (else an input).
        output: bool,
        /// Its position in the service's inputs or outputs.
        index: usize,
    },
}

/// One step of a member path.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub enum Step {
    /// `.field`
    Field(String),
    /// `[n]`
    Index(u64),
}

/// A codel.
#[derive(Debug, Clone, PartialEq)]
pub struct Codel {
    /// The service it belongs to.
    pub service: ServiceId,
    /// Its kind.
    pub kind: CodelKind,
    /// Its name (`start` and `control` for those kinds) and the span of the
    /// name (of the kind keyword for start and control codels).
    pub name: Named,
    /// `exec: f(...)`.
    pub call: Option<Call>,
    /// Data it writes and publishes after running.
    pub update: Vec<DataPath>,
    /// Inter codel to run when interrupted at this codel.
    pub on_inter: Option<Ref<CodelId>>,
    /// Worst-case execution time.
    pub wcet: Option<Duration>,
    /// Its `next` outcomes as written (an absent or empty `next` means
    /// `end`; see [`Codel::outcomes`]).
    pub next: Vec<Next>,
    /// Where the `next` attribute is written.
    pub next_span: Option<Span>,
}

impl Codel {
    /// The possible outcomes: the written `next`, or `end` when empty.
    pub fn outcomes(&self) -> Vec<Outcome> {
        if self.next.is_empty() {
            vec![Outcome::End]
        } else {
            self.next.iter().map(|n| n.outcome).collect()
        }
    }

    /// The lockable structures the codel uses, each with whether it may
    /// write it (a non-`const` argument), sorted by structure.
    pub fn structures(&self) -> Vec<(StructureId, bool)> {
        let mut used: Vec<(StructureId, bool)> = Vec::new();
        for arg in self.call.iter().flat_map(|c| c.args.iter()) {
            let Some(id) = arg.data.as_ref().and_then(DataPath::structure) else {
                continue;
            };
            match used.iter_mut().find(|(s, _)| *s == id) {
                Some(entry) => entry.1 |= !arg.is_const,
                None => used.push((id, !arg.is_const)),
            }
        }
        used.sort();
        used
    }
}

/// `exec: f([const] a, ...)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Call {
    /// The codel function.
    pub function: Named,
    /// Its arguments.
    pub args: Vec<Arg>,
    /// Where the call is written.
    pub span: Span,
}

/// One codel argument.
#[derive(Debug, Clone, PartialEq)]
pub struct Arg {
    /// Passed read-only.
    pub is_const: bool,
    /// The data passed, when it resolved.
    pub data: Option<DataPath>,
    /// Where it is written.
    pub span: Span,
}

/// One `next` entry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Next {
    /// What it designates.
    pub outcome: Outcome,
    /// Where it is written.
    pub span: Span,
}

/// A codel outcome.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Outcome {
    /// Go to this codel of the same service.
    Codel(CodelId),
    /// End with this report (index in the service's reports).
    Report(usize),
    /// End successfully.
    End,
}

impl Component {
    /// The service with this name.
    pub fn service_named(&self, name: &str) -> Option<ServiceId> {
        self.services
            .iter()
            .find(|(_, s)| s.name.name == name)
            .map(|(id, _)| id)
    }

    /// The language the component was written in: GenoM3 when its
    /// front-end recorded GenoM3's facts, else LANGUAGE.md. Code that words
    /// a finding or picks a translation by language asks this rather than
    /// whether [`Component::genom3`] is set.
    pub fn dialect(&self) -> crate::Dialect {
        if self.genom3.is_some() {
            crate::Dialect::Genom3
        } else {
            crate::Dialect::Gen
        }
    }

    /// The thread with this name.
    pub fn thread_named(&self, name: &str) -> Option<ThreadId> {
        self.threads
            .iter()
            .find(|(_, t)| t.name.name == name)
            .map(|(id, _)| id)
    }

    /// The codel of `service` with this name.
    pub fn codel_named(&self, service: ServiceId, name: &str) -> Option<CodelId> {
        self.services
            .get(service)?
            .codels
            .iter()
            .copied()
            .find(|&c| self.codels.get(c).is_some_and(|k| k.name.name == name))
    }

    /// The `init` service, if any (the first one when several are declared).
    pub fn init_service(&self) -> Option<ServiceId> {
        self.services
            .iter()
            .find(|(_, s)| s.kind == ServiceKind::Init)
            .map(|(id, _)| id)
    }

    /// `service::codel`, for messages and traces.
    pub fn codel_label(&self, codel: CodelId) -> String {
        let c = &self.codels[codel];
        format!("{}::{}", self.services[c.service].name.name, c.name.name)
    }

    /// The name of a credential class.
    pub fn credential_name(&self, index: usize) -> &str {
        self.credentials
            .get(index)
            .map_or("none", |c| c.name.as_str())
    }

    /// Whether two codels conflict on some structure: both use it and at
    /// least one may write it (LANGUAGE.md section 3).
    pub fn conflicts(&self, a: CodelId, b: CodelId) -> bool {
        uses_conflict(&self.codels[a].structures(), &self.codels[b].structures())
    }
}
