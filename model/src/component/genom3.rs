//! GenoM3 concepts the LANGUAGE.md model has no place for: ports, task
//! state machines (permanent task codels), `pause::` and `async`, service
//! ordering (`before`/`after`), locals, exceptions, remotes, and the
//! component's GenoM3 properties. Filled by the GenoM3 front end
//! (`genom3-frontend`) in [`super::Component::genom3`]; `None` for a
//! LANGUAGE.md component, so nothing else changes for those.
//!
//! Mapping used by the front end (so that the engines read GenoM3 through
//! the existing model): tasks are threads; activities are services on
//! their task, one [`super::Codel`] per FSM state (`start` is the start
//! codel, `stop` the inter codel every other codel is interrupted to, the
//! rest exec codels, `ether` is `end`); functions and attributes are
//! control-only services (`validate` and the function's codels are control
//! codels named `validate`, `codel`, `codel2`...); `ids` is one IDS structure named
//! `ids`; an `out` port is an export structure, an `in` port an import
//! structure, both in block `port`; `throws` are the service's reports.

use super::{CodelId, Duration, Field, Named, Ref, ServiceId, StructureId, ThreadId, Ty};
use crate::span::Span;

/// Everything GenoM3-specific about a component.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Genom3Info {
    /// True when it was read from an `interface` (no component).
    pub is_interface: bool,
    /// `email`.
    pub email: Option<String>,
    /// `require` packages.
    pub require: Vec<String>,
    /// `codels-require` packages.
    pub codels_require: Vec<String>,
    /// `clock-rate`.
    pub clock_rate: Option<Duration>,
    /// `provides` interfaces (the built-in `genom` first).
    pub provides: Vec<Named>,
    /// `uses` interfaces.
    pub uses: Vec<Named>,
    /// Ports, in declaration order (provided and used interfaces' included).
    pub ports: Vec<Port>,
    /// One entry per task (by thread).
    pub tasks: Vec<Task>,
    /// One entry per service (by service).
    pub services: Vec<ServiceInfo>,
    /// One entry per FSM or control codel of a service.
    pub codels: Vec<CodelInfo>,
    /// Exceptions (IDL `exception`), by qualified name.
    pub exceptions: Vec<Exception>,
    /// Services of used interfaces, callable through `remote` parameters.
    pub remotes: Vec<Remote>,
}

/// A port.
#[derive(Debug, Clone, PartialEq)]
pub struct Port {
    /// Its name.
    pub name: Named,
    /// `out` (else `in`).
    pub is_out: bool,
    /// `multiple`.
    pub multiple: bool,
    /// Its data type.
    pub ty: Ty,
    /// The import or export structure standing for it.
    pub structure: Option<StructureId>,
    /// The interface it comes from (`uses` flips its direction).
    pub interface: Option<String>,
}

/// A task: the thread's GenoM3 properties and its permanent codels.
#[derive(Debug, Clone, PartialEq)]
pub struct Task {
    /// The thread standing for it.
    pub thread: ThreadId,
    /// `delay`.
    pub delay: Option<Duration>,
    /// `scheduling real-time`.
    pub real_time: bool,
    /// Exceptions it may throw.
    pub throws: Vec<Named>,
    /// Its permanent codels (the task's own state machine).
    pub codels: Vec<FsmCodel>,
}

/// One FSM codel of a task or a service.
#[derive(Debug, Clone, PartialEq)]
pub struct FsmCodel {
    /// The states it runs in (`start`, `stop`, user states).
    pub states: Vec<Named>,
    /// The codel function.
    pub function: Named,
    /// What it may yield.
    pub yields: Vec<Yield>,
    /// `async`.
    pub is_async: bool,
    /// Its parameters.
    pub params: Vec<CodelParam>,
    /// Worst-case execution time (from a WCET side file).
    pub wcet: Option<Duration>,
    /// The whole codel.
    pub span: Span,
}

/// One `yield` target.
#[derive(Debug, Clone, PartialEq)]
pub struct Yield {
    /// The state (`ether` ends).
    pub state: Named,
    /// `pause::` (wait for the next period before running it).
    pub pause: bool,
}

/// Where a codel parameter's data comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum ParamSource {
    /// An ids member.
    Ids,
    /// A service parameter or local variable.
    Local,
    /// A port.
    Port,
    /// A remote service.
    Remote,
}

/// A resolved codel parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct CodelParam {
    /// Where its data comes from.
    pub source: ParamSource,
    /// `in`, `out`, `inout`, as written.
    pub dir: String,
    /// The member path as written (`a.b[2]`), or the name.
    pub path: String,
    /// The name the codel function sees (`::name` rename, else the last
    /// member).
    pub name: String,
    /// Where it is written.
    pub span: Span,
}

/// GenoM3 facts about one service.
#[derive(Debug, Clone, PartialEq)]
pub struct ServiceInfo {
    /// The service.
    pub service: ServiceId,
    /// `attribute`, `function` or `activity`.
    pub kind: String,
    /// `before` services.
    pub before: Vec<Ref<ServiceId>>,
    /// `after` services.
    pub after: Vec<Ref<ServiceId>>,
    /// `interrupts all`.
    pub interrupts_all: bool,
    /// `local` variables.
    pub locals: Vec<Field>,
    /// The interface it comes from (`provides`).
    pub interface: Option<String>,
}

/// GenoM3 facts about one model codel (a state of an activity, or a control
/// codel of a function or attribute).
#[derive(Debug, Clone, PartialEq)]
pub struct CodelInfo {
    /// The model codel.
    pub codel: CodelId,
    /// The FSM codel it comes from (shared by the states it runs in).
    pub fsm: FsmCodel,
}

/// An IDL exception.
#[derive(Debug, Clone, PartialEq)]
pub struct Exception {
    /// Qualified name.
    pub name: Named,
    /// Its members.
    pub fields: Vec<Field>,
}

/// A service of a used interface.
#[derive(Debug, Clone, PartialEq)]
pub struct Remote {
    /// Its name.
    pub name: Named,
    /// The interface.
    pub interface: String,
}
