//! The document of the `config` export: the Rust types that serialise
//! to the runtime configuration and give its JSON Schema.

use std::collections::BTreeMap;

use schemars::JsonSchema;
use serde::Serialize;

/// The verified runtime configuration of one component.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[schemars(title = "genom-check runtime configuration")]
pub struct RuntimeConfig {
    /// Always `genom-check/runtime-config`.
    #[schemars(extend("const" = "genom-check/runtime-config"))]
    pub format: String,
    /// The layout version; fields may be added without a bump, never
    /// removed or renamed.
    pub format_version: u32,
    /// True only when the check found no error and explored the whole
    /// state space; false for an `--allow-unverified` export that was not
    /// (`verification.error_codes` and `verification.complete` say why).
    pub verified: bool,
    /// The component item.
    pub component: ComponentInfo,
    /// The declared execution threads, in source order (the implicit
    /// `control` thread is not listed).
    pub threads: Vec<ThreadInfo>,
    /// The services, in source order.
    pub services: Vec<ServiceInfo>,
    /// Every codel of every service, grouped by service in source order.
    pub codels: Vec<CodelInfo>,
    /// Which codels must not run at the same time.
    pub lock_groups: LockGroups,
    /// What genom-check established, and about which files.
    pub verification: VerificationInfo,
}

/// The `component` item.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct ComponentInfo {
    /// Its name.
    pub name: String,
    /// `category`, `default` when absent: selects the execution engine.
    pub category: String,
    /// `lang`, the language of the codels (null when absent).
    pub lang: Option<String>,
    /// `version` (null when absent).
    pub version: Option<String>,
    /// `doc` (null when absent).
    pub doc: Option<String>,
    /// The credential classes, weakest first.
    pub credentials: Vec<String>,
}

/// An execution thread.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct ThreadInfo {
    /// Its name.
    pub name: String,
    /// Period in nanoseconds; null for an aperiodic thread (codels back to
    /// back).
    pub period_ns: Option<u64>,
    /// Priority: higher runs first, 0 is normal.
    pub priority: i64,
    /// Stack size in bytes (null: the engine's default).
    pub stack_bytes: Option<u64>,
    /// Function called at thread creation (not a codel).
    pub start_hook: Option<String>,
    /// Function called at thread deletion (not a codel).
    pub stop_hook: Option<String>,
}

/// The kind of a service.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum ServiceKindInfo {
    /// Started on request.
    Plain,
    /// Must complete successfully before any other service is accepted.
    Init,
    /// Started by the component once initialised.
    Auto,
}

/// A service.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct ServiceInfo {
    /// Its name.
    pub name: String,
    /// `plain`, `init` or `auto`.
    pub kind: ServiceKindInfo,
    /// `doc` (null when absent).
    pub doc: Option<String>,
    /// The thread running its codels; null when it runs entirely in the
    /// control thread (no start codel).
    pub thread: Option<String>,
    /// Deadline from acknowledgment to final reply, in nanoseconds (null:
    /// none); enforced by the engine's watchdog.
    pub max_time_ns: Option<u64>,
    /// The weakest credential class allowed to request it.
    pub credential: String,
    /// Requests are rejected with `NOT_INITIALIZED` until the `init`
    /// service has completed successfully (false for the `init` service
    /// itself and in a component without one).
    pub requires_init: bool,
    /// The reports it may end with (besides `INTERRUPTED` and `TIMEOUT`).
    pub reports: Vec<String>,
    /// Input parameters, in order.
    pub inputs: Vec<ParamInfo>,
    /// Output parameters, in order.
    pub outputs: Vec<ParamInfo>,
    /// Imported structures it reads (`block.item`).
    pub imports: Vec<String>,
    /// Exported structures it produces (`block.item`).
    pub exports: Vec<String>,
    /// Its control codel's name (`control`), null when it has none.
    pub control_codel: Option<String>,
    /// Its start codel's name (`start`), null when it has none.
    pub start_codel: Option<String>,
    /// The names of its codels, in source order.
    pub codels: Vec<String>,
    /// For every service of the component (itself included), keyed by
    /// name: what a request of this service does while that one has an
    /// instance (`request`, resolved from both services' `stops`, `delays`
    /// and `forbids` as LANGUAGE.md section 3 orders them), and the
    /// declarations it comes from.
    pub compatibility: BTreeMap<String, Compatibility>,
}

/// What happens to a request of a service while another (or the same)
/// service has an instance (pending, active or stopping), after the
/// `init` rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum RequestOutcome {
    /// Rejected with `FORBIDDEN`: the other lists this one in `forbids`.
    Forbidden,
    /// Rejected with `BUSY`: the same service, which does not stop itself.
    Busy,
    /// Accepted (after the control codel); the other's instance is
    /// interrupted (unless already stopping) and this one starts once it
    /// has ended. For the same service: the new request replaces the
    /// running instance.
    Interrupts,
    /// Accepted, then pending until the other's instance has ended: the
    /// other lists this one in `delays`.
    Waits,
    /// Accepted; both run concurrently.
    Concurrent,
}

/// How a service relates to one service of the component.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
pub struct Compatibility {
    /// What a request of this service does while the other has an
    /// instance: the first that applies of `forbidden` (the other forbids
    /// this one), `busy` (the same service, not self-stopping),
    /// `interrupts` (this one stops the other), `waits` (the other delays
    /// this one), else `concurrent`.
    pub request: RequestOutcome,
    /// This service lists the other in `stops`.
    pub stops: bool,
    /// This service lists the other in `delays` (no effect on itself).
    pub delays: bool,
    /// This service lists the other in `forbids` (no effect on itself).
    pub forbids: bool,
    /// The other lists this one in `stops`.
    pub stopped_by: bool,
    /// The other lists this one in `delays`.
    pub delayed_by: bool,
    /// The other lists this one in `forbids`.
    pub forbidden_by: bool,
}

/// A service input or output parameter.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct ParamInfo {
    /// Its name (for an IDS reference, the last member).
    pub name: String,
    /// Its type, as IDL writes it.
    #[serde(rename = "type")]
    pub ty: String,
    /// Its default value (JSON: numbers, booleans, strings, enum values by
    /// name, structs as objects, arrays), null when none.
    pub default: Option<serde_json::Value>,
    /// Documentation string.
    pub doc: Option<String>,
    /// For a reference into an IDS, the data it is stored into (input, when
    /// the request is accepted) or read from (output, when the service
    /// ends); null for a plain parameter.
    pub data: Option<DataRef>,
}

/// A resolved data reference.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[serde(tag = "root", rename_all = "lowercase")]
pub enum DataRef {
    /// Data in a lockable structure.
    Structure {
        /// The structure (`demoIds`, `demoExport.state`).
        structure: String,
        /// Which kind of block it belongs to.
        kind: DataKindInfo,
        /// The reference as written (`demoIds.distRef`).
        path: String,
    },
    /// An input parameter of the codel's service.
    Input {
        /// The parameter's name.
        param: String,
        /// The reference as written.
        path: String,
    },
    /// An output parameter of the codel's service.
    Output {
        /// The parameter's name.
        param: String,
        /// The reference as written.
        path: String,
    },
}

/// The kind of a lockable structure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum DataKindInfo {
    /// An `ids` block.
    Ids,
    /// An item of an `export` block.
    Export,
    /// An item of an `import` block.
    Import,
}

/// The kind of a codel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum CodelKindInfo {
    /// The start codel, first run on the service's thread.
    Start,
    /// The control codel, run by the control thread to validate a request.
    Control,
    /// An exec codel.
    Exec,
    /// An inter codel, run after an interruption.
    Inter,
}

/// A codel.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct CodelInfo {
    /// `service::name`, unique in the component (used by `lock_groups`).
    pub id: String,
    /// Its service.
    pub service: String,
    /// Its kind.
    pub kind: CodelKindInfo,
    /// Its name (`start`, `control`, or the declared name).
    pub name: String,
    /// The thread running it: `control` for a control codel, else the
    /// service's thread (null when unknown).
    pub thread: Option<String>,
    /// The codel function (null when the codel has no `exec`).
    pub function: Option<String>,
    /// Its arguments, in order.
    pub args: Vec<ArgInfo>,
    /// Data written by the codel and refreshed/published after it runs.
    pub update: Vec<DataRef>,
    /// The inter codel run when the service is interrupted at this codel
    /// (null: the service then ends with `INTERRUPTED`).
    pub on_inter: Option<String>,
    /// Worst-case execution time in nanoseconds (null: unknown).
    pub wcet_ns: Option<u64>,
    /// The possible outcomes (an absent or empty `next` is `end`); empty
    /// for control codels, which accept or reject with a report.
    pub next: Vec<OutcomeInfo>,
}

/// A codel argument.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct ArgInfo {
    /// Passed read-only.
    #[serde(rename = "const")]
    pub is_const: bool,
    /// The type of the data passed, as IDL writes it (null when it did not
    /// resolve).
    #[serde(rename = "type")]
    pub ty: Option<String>,
    /// The data passed (null when it did not resolve).
    pub data: Option<DataRef>,
}

/// A codel outcome.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(tag = "outcome", rename_all = "lowercase")]
pub enum OutcomeInfo {
    /// Go to this codel of the same service.
    Codel {
        /// The codel's name.
        codel: String,
    },
    /// End with this report.
    Report {
        /// The report's name.
        report: String,
    },
    /// End successfully.
    End,
}

/// The mutual exclusion the engine must enforce.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct LockGroups {
    /// Every lockable structure, in declaration order, with the codels that
    /// use it.
    pub structures: Vec<LockGroup>,
    /// Every pair of codels of different threads that must not run at the
    /// same time, in codel order (`a` before `b`).
    pub conflicts: Vec<Conflict>,
}

/// One lockable structure and its users.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct LockGroup {
    /// The structure (`demoIds`, `demoExport.state`).
    pub structure: String,
    /// Which kind of block it belongs to.
    pub kind: DataKindInfo,
    /// Its type, as IDL writes it (the block name for an IDS block).
    #[serde(rename = "type")]
    pub ty: String,
    /// The codels passing it (or data in it) as an argument, in codel
    /// order.
    pub users: Vec<LockUser>,
}

/// A codel using a structure.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct LockUser {
    /// The codel's id (`service::name`).
    pub codel: String,
    /// The thread running it.
    pub thread: Option<String>,
    /// Whether it may write the structure (a non-`const` argument).
    pub writes: bool,
}

/// Two codels of different threads that conflict.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct Conflict {
    /// The first codel's id.
    pub a: String,
    /// The second codel's id.
    pub b: String,
    /// The structures both use and at least one may write.
    pub structures: Vec<String>,
}

/// What genom-check established.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct VerificationInfo {
    /// Always `genom-check`.
    pub tool: String,
    /// genom-check's version.
    pub tool_version: String,
    /// The checked file.
    pub source: SourceHash,
    /// The files it includes, in load order.
    pub includes: Vec<SourceHash>,
    /// Diagnostics by severity.
    pub counts: CountsInfo,
    /// States explored.
    pub states: u64,
    /// Transitions fired.
    pub transitions: u64,
    /// Whether exploration covered the whole state space.
    pub complete: bool,
    /// The distinct codes of the error diagnostics, sorted; empty when
    /// verified.
    pub error_codes: Vec<String>,
    /// The properties proven, in a fixed order (empty when not verified).
    pub properties: Vec<PropertyInfo>,
}

/// A property established by the check.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, JsonSchema)]
pub struct PropertyInfo {
    /// Its kind: `static-semantics`, `deadlock-free`, `no-starvation`,
    /// `every-service-can-start`, `interrupts-terminate`,
    /// `every-codel-reachable`, `every-service-can-end`,
    /// `auto-services-run-forever`, `no-privilege-escalation`,
    /// `thread-never-overruns` or `meets-max-time`.
    pub property: String,
    /// The thread or service it is about, null for the whole component.
    pub subject: Option<String>,
    /// What it means for this component, as a sentence.
    pub statement: String,
}

/// A file and the SHA-256 of its text.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, JsonSchema)]
pub struct SourceHash {
    /// The path as given (on the command line, or resolved from the
    /// including file), with `/` separators.
    pub path: String,
    /// SHA-256 of the file's bytes, lowercase hexadecimal.
    #[schemars(regex(pattern = r"^[0-9a-f]{64}$"))]
    pub sha256: String,
}

/// Diagnostics by severity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
pub struct CountsInfo {
    /// Errors.
    pub errors: u64,
    /// Warnings.
    pub warnings: u64,
    /// Advice.
    pub advice: u64,
}
