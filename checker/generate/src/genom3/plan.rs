//! The plan of a generated GenoM3 component before it is printed: data,
//! tasks, services, their state machines and codel parameters.

/// A parameter direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Dir {
    In,
    Out,
    InOut,
}

impl Dir {
    pub(crate) fn text(self) -> &'static str {
        match self {
            Dir::In => "in",
            Dir::Out => "out",
            Dir::InOut => "inout",
        }
    }
}

/// Where a codel parameter comes from, when the text says it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Source {
    /// Unqualified: the name is unique among the sources.
    Implicit,
    Ids,
    Local,
    Port,
}

/// One codel parameter: `[source] dir path`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Param {
    pub(crate) source: Source,
    pub(crate) dir: Dir,
    pub(crate) path: String,
}

impl Param {
    pub(crate) fn text(&self) -> String {
        let source = match self.source {
            Source::Implicit => "",
            Source::Ids => "ids ",
            Source::Local => "local ",
            Source::Port => "port ",
        };
        format!("{source}{} {}", self.dir.text(), self.path)
    }
}

/// A yield: a state (`None`: `ether`), paused or not.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Yield {
    pub(crate) to: Option<usize>,
    pub(crate) pause: bool,
}

/// One codel of a state machine: the states it runs in, its function,
/// parameters and yields.
#[derive(Debug, Clone)]
pub(crate) struct FsmCodel {
    pub(crate) states: Vec<usize>,
    pub(crate) function: String,
    pub(crate) params: Vec<Param>,
    pub(crate) yields: Vec<Yield>,
    pub(crate) is_async: bool,
}

/// A state machine (an activity's or a task's permanent one): its state
/// names (index 0 is `start`; `stop`, when present, is last) and codels.
#[derive(Debug, Clone)]
pub(crate) struct Fsm {
    pub(crate) states: Vec<String>,
    pub(crate) codels: Vec<FsmCodel>,
}

/// A control codel (`validate` or a function's `codel`).
#[derive(Debug, Clone)]
pub(crate) struct ControlCodel {
    pub(crate) function: String,
    pub(crate) params: Vec<Param>,
}

/// A task.
#[derive(Debug, Clone)]
pub(crate) struct TaskPlan {
    pub(crate) name: String,
    pub(crate) period_ms: Option<u64>,
    pub(crate) delay_ms: Option<u64>,
    pub(crate) fsm: Option<Fsm>,
}

/// A service parameter: `dir type name [= default : "doc"]`, or for an
/// attribute `dir path [= default]` (then `ty` is empty).
#[derive(Debug, Clone)]
pub(crate) struct ServiceParam {
    pub(crate) dir: Dir,
    pub(crate) ty: &'static str,
    pub(crate) name: String,
    pub(crate) default: Option<String>,
}

/// Kinds of service.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    Activity,
    Function,
    Attribute,
}

/// One service (activity, function or attribute).
#[derive(Debug, Clone)]
pub(crate) struct ServicePlan {
    pub(crate) name: String,
    pub(crate) kind: Kind,
    pub(crate) task: Option<usize>,
    pub(crate) params: Vec<ServiceParam>,
    pub(crate) interrupts: Vec<usize>,
    pub(crate) interrupts_all: bool,
    pub(crate) after: Vec<usize>,
    pub(crate) before: Vec<usize>,
    pub(crate) throws: Vec<usize>,
    pub(crate) validate: Option<ControlCodel>,
    /// A function's codels, run in sequence.
    pub(crate) codels: Vec<ControlCodel>,
    /// An activity's state machine.
    pub(crate) fsm: Option<Fsm>,
}

/// An ids member, port or struct field type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum DataTy {
    Long,
    Double,
    Pose,
    Cmd,
}

impl DataTy {
    pub(crate) fn name(self) -> &'static str {
        match self {
            DataTy::Long => "long",
            DataTy::Double => "double",
            DataTy::Pose => "g_pose",
            DataTy::Cmd => "g_cmd",
        }
    }

    /// The paths below a datum of this type, with their types (the datum
    /// itself not included).
    pub(crate) fn members(self) -> Vec<(String, DataTy)> {
        match self {
            DataTy::Long | DataTy::Double => Vec::new(),
            DataTy::Pose => vec![("x".into(), DataTy::Double), ("y".into(), DataTy::Double)],
            DataTy::Cmd => {
                let mut v = vec![
                    ("speed".into(), DataTy::Long),
                    ("target".into(), DataTy::Pose),
                ];
                v.extend(
                    DataTy::Pose
                        .members()
                        .into_iter()
                        .map(|(m, t)| (format!("target.{m}"), t)),
                );
                v
            }
        }
    }

    /// A default value for a scalar (`None` for a struct).
    pub(crate) fn default_value(self, k: usize) -> Option<String> {
        match self {
            DataTy::Long => Some(k.to_string()),
            DataTy::Double => Some(format!("{k}.5")),
            DataTy::Pose | DataTy::Cmd => None,
        }
    }
}

/// A path a codel or attribute may name: an ids member or one of its
/// members, or a port.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct DataPath {
    pub(crate) path: String,
    pub(crate) ty: DataTy,
}

impl DataPath {
    /// The parameter name GenoM3 gives it: its last component.
    pub(crate) fn last(&self) -> &str {
        self.path.rsplit('.').next().unwrap_or(&self.path)
    }

    /// Whether one of the two paths is the other or contains it.
    pub(crate) fn overlaps(&self, other: &str) -> bool {
        let (a, b) = (self.path.as_str(), other);
        a == b || a.starts_with(&format!("{b}.")) || b.starts_with(&format!("{a}."))
    }
}

/// A port.
#[derive(Debug, Clone)]
pub(crate) struct PortPlan {
    pub(crate) name: String,
    pub(crate) out: bool,
}

/// The whole component.
#[derive(Debug, Clone)]
pub(crate) struct Plan {
    pub(crate) name: String,
    pub(crate) exceptions: Vec<String>,
    pub(crate) members: Vec<(String, DataTy)>,
    pub(crate) paths: Vec<DataPath>,
    pub(crate) ports: Vec<PortPlan>,
    pub(crate) tasks: Vec<TaskPlan>,
    pub(crate) services: Vec<ServicePlan>,
}
