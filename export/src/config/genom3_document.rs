//! The document of the `config` export of a GenoM3 component: the Rust
//! types that serialise to its runtime configuration, in GenoM3's terms
//! (tasks, activities, functions, attributes, codels with their states,
//! the ids members and ports each codel locks), and give its JSON Schema,
//! committed as `export/schema/genom3-runtime-config.schema.json`.

use schemars::JsonSchema;
use serde::Serialize;

use super::{ParamInfo, SourceHash, VerificationInfo};

/// The verified runtime configuration of one GenoM3 component.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[schemars(title = "genom-check GenoM3 runtime configuration")]
pub struct Genom3Config {
    /// Always `genom-check/genom3-runtime-config`.
    #[schemars(extend("const" = "genom-check/genom3-runtime-config"))]
    pub format: String,
    /// The layout version; fields may be added without a bump, never
    /// removed or renamed.
    pub format_version: u32,
    /// True only when the check found no error and explored the whole
    /// state space; false for an `--allow-unverified` export that was not
    /// (`verification.error_codes` and `verification.complete` say why).
    pub verified: bool,
    /// The `component` item.
    pub component: G3ComponentInfo,
    /// The ports, in source order.
    pub ports: Vec<G3Port>,
    /// The tasks (execution threads), in source order; the control task,
    /// which runs every `validate` and every function's and attribute's
    /// codels, is implicit.
    pub tasks: Vec<G3Task>,
    /// The services, in source order.
    pub services: Vec<G3Service>,
    /// What the verdicts rest on besides the text.
    pub assumptions: G3Assumptions,
    /// What genom-check established, and about which files (the WCET file
    /// among them).
    pub verification: VerificationInfo,
}

/// The `component` item.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct G3ComponentInfo {
    /// Its name.
    pub name: String,
    /// `version` (null when absent).
    pub version: Option<String>,
    /// `lang`, the language of the codels (null when absent).
    pub lang: Option<String>,
    /// `email` (null when absent).
    pub email: Option<String>,
    /// `doc` (null when absent).
    pub doc: Option<String>,
    /// `require`: the packages the component needs.
    pub require: Vec<String>,
    /// `codels-require`: the packages its codels need.
    pub codels_require: Vec<String>,
    /// `clock-rate` in nanoseconds: the period of the component's clock
    /// (null: the middleware's default).
    pub clock_rate_ns: Option<u64>,
    /// The interfaces it provides.
    pub provides: Vec<String>,
    /// The interfaces it uses.
    pub uses: Vec<String>,
}

/// The direction of a port.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum PortDirection {
    /// The component reads it.
    In,
    /// The component writes it.
    Out,
}

/// A port.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct G3Port {
    /// Its name.
    pub name: String,
    /// `in` or `out`.
    pub direction: PortDirection,
    /// `multiple`: a set of ports created at run time.
    pub multiple: bool,
    /// Its data type, as IDL writes it.
    #[serde(rename = "type")]
    pub ty: String,
}

/// How a task is scheduled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Scheduling {
    /// `scheduling real-time`.
    RealTime,
    /// The system's default.
    Default,
}

/// A task.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct G3Task {
    /// Its name.
    pub name: String,
    /// `period` in nanoseconds; null for an aperiodic task (it runs when
    /// an activity is ready).
    pub period_ns: Option<u64>,
    /// `delay` in nanoseconds: the offset of its first tick (0 when
    /// absent).
    pub delay_ns: u64,
    /// `priority` (0 when absent).
    pub priority: i64,
    /// `stack` in bytes (null: the system's default).
    pub stack_bytes: Option<u64>,
    /// `scheduling`.
    pub scheduling: Scheduling,
    /// The exceptions its permanent codels may throw.
    pub throws: Vec<String>,
    /// The codels of its permanent activity, in source order (empty when
    /// it has none).
    pub codels: Vec<G3Codel>,
    /// The activities it runs, in source order.
    pub activities: Vec<String>,
}

/// The kind of a GenoM3 service.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum G3ServiceKind {
    /// Runs its codels in a task, until it ends.
    Activity,
    /// Runs its codels in the control task, then replies.
    Function,
    /// Copies its parameters to or from the ids in the control task.
    Attribute,
}

/// A service.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct G3Service {
    /// Its name.
    pub name: String,
    /// `activity`, `function` or `attribute`.
    pub kind: G3ServiceKind,
    /// `doc` (null when absent).
    pub doc: Option<String>,
    /// The task running its codels (an activity's); null for the control
    /// task.
    pub task: Option<String>,
    /// The services a request of it interrupts, in source order (every
    /// service for `interrupts all`).
    pub interrupts: Vec<String>,
    /// `interrupts all`.
    pub interrupts_all: bool,
    /// `after`: it is rejected until one of these has completed.
    pub after: Vec<String>,
    /// `before`: it is rejected once one of these has completed.
    pub before: Vec<String>,
    /// The exceptions it may throw (its own and the component's).
    pub throws: Vec<String>,
    /// Input parameters, in order.
    pub inputs: Vec<ParamInfo>,
    /// Output parameters, in order.
    pub outputs: Vec<ParamInfo>,
    /// Its `validate` codel (run by the control task before the request
    /// is accepted), null when it has none.
    pub validate: Option<G3Codel>,
    /// Its other codels: an activity's state machine, or the codels a
    /// function runs in the control task one after the other.
    pub codels: Vec<G3Codel>,
    /// Its worst-case response time, from the request's acknowledgment
    /// to its final reply, over every execution under the assumptions
    /// (set a client's request timeout from it); null when it was not
    /// computed: without a WCET file, and for the services of the
    /// built-in `genom` interface (`kill`, `abort_activity`,
    /// `connect_port`, `connect_service`), which the timed model does not
    /// request.
    pub response_time: Option<G3ResponseTime>,
}

/// A codel function and the states it runs in.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct G3Codel {
    /// The C function.
    pub function: String,
    /// The states it runs in with the WCET assumed in each (`validate`,
    /// `codel`, `codel2`... for the control task's codels).
    pub states: Vec<G3State>,
    /// The states it may yield to, with `pause::` (wait for the task's
    /// next tick) or not; `ether` ends.
    pub yields: Vec<G3Yield>,
    /// `async`: it runs in a thread of its own and locks nothing.
    #[serde(rename = "async")]
    pub is_async: bool,
    /// The ids members, ports and remote services it locks while it runs
    /// (none for an `async` codel), in parameter order.
    pub locks: Vec<G3Lock>,
}

/// A state a codel runs in.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, JsonSchema)]
pub struct G3State {
    /// The state's name.
    pub name: String,
    /// The worst-case execution time assumed, in nanoseconds (from the
    /// WCET file); null when none is given: the verdicts take it as 0.
    pub wcet_ns: Option<u64>,
}

/// A `yield` target.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, JsonSchema)]
pub struct G3Yield {
    /// The state (`ether` ends the activity).
    pub state: String,
    /// `pause::`: run it at the task's next tick.
    pub pause: bool,
}

/// What a codel locks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum LockKind {
    /// An ids member: codels conflict when one path is a prefix of the
    /// other and one of them writes.
    Ids,
    /// A port: codels conflict whatever their directions.
    Port,
    /// A remote service: codels conflict whatever their directions.
    Remote,
}

/// One resource a codel locks.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, JsonSchema)]
pub struct G3Lock {
    /// `ids`, `port` or `remote`.
    pub kind: LockKind,
    /// The member path as written (`servo.gain`), or the port's or remote
    /// service's name.
    pub name: String,
    /// Whether the codel may write it (`out` or `inout`).
    pub writes: bool,
}

/// What is known of a worst-case response time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ResponseStatus {
    /// Exactly `worst_ns`: a supremum some execution comes arbitrarily
    /// close to, none goes beyond.
    Exact,
    /// At most `worst_ns`, not proven reached.
    AtMost,
    /// More than `worst_ns` (the horizon of the computation).
    Above,
    /// Some execution keeps an instance alive forever without replying.
    Unbounded,
    /// Not decided: a limit stopped the computation.
    Unknown,
}

/// A worst-case response time.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, JsonSchema)]
pub struct G3ResponseTime {
    /// What is known of it.
    pub status: ResponseStatus,
    /// The figure of `exact`, `at-most` and `above` in nanoseconds, else
    /// null.
    pub worst_ns: Option<u64>,
    /// Why the bound is not exact, or null.
    pub note: Option<String>,
}

/// What the verdicts rest on.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
pub struct G3Assumptions {
    /// The WCET file and the SHA-256 of its text; null without one (then
    /// no timing verdict was made).
    pub wcet_file: Option<SourceHash>,
    /// The bound on the concurrent instances of each activity the timed
    /// verdicts explored (null without timing verdicts).
    pub max_instances: Option<u64>,
    /// Every assumption as a sentence, in the order the check states them.
    pub statements: Vec<String>,
}
