//! The plan of a generated component before it is printed: data types,
//! data, functions, services and their codels.

use crate::rng::SplitMix;

/// A data type of the generated data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Ty {
    Double,
    Long,
    Boolean,
}

impl Ty {
    pub(crate) const ALL: [Ty; 3] = [Ty::Double, Ty::Long, Ty::Boolean];

    pub(crate) fn name(self) -> &'static str {
        match self {
            Ty::Double => "double",
            Ty::Long => "long",
            Ty::Boolean => "boolean",
        }
    }

    pub(crate) fn default_value(self, r: &mut SplitMix) -> String {
        match self {
            Ty::Double => format!("{}.{}", r.below(10), r.below(10)),
            Ty::Long => r.below(100).to_string(),
            Ty::Boolean => if r.chance(0.5) { "TRUE" } else { "FALSE" }.to_owned(),
        }
    }
}

/// A piece of data a codel can name: its text, type, and whether it is a
/// lockable structure that `update` may list (`ids` member, export item)
/// rather than a service parameter.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Data {
    pub(crate) text: String,
    pub(crate) ty: Ty,
    pub(crate) structure: bool,
}

/// A codel function: its name and fixed prototype.
#[derive(Debug, Clone)]
pub(crate) struct Function {
    pub(crate) name: String,
    pub(crate) args: Vec<(bool, Ty)>,
}

/// Kinds of service.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    Init,
    Auto,
    Plain,
    Setter,
}

/// A `next` outcome.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Out {
    Codel(usize),
    End,
    Report(usize),
}

/// One generated codel (index 0 is `start`).
#[derive(Debug, Clone, Default)]
pub(crate) struct CodelPlan {
    pub(crate) name: String,
    pub(crate) inter: bool,
    pub(crate) next: Vec<Out>,
    pub(crate) on_inter: Option<usize>,
}

/// One generated service.
#[derive(Debug, Clone)]
pub(crate) struct ServicePlan {
    pub(crate) name: String,
    pub(crate) kind: Kind,
    pub(crate) thread: Option<usize>,
    pub(crate) stops: Vec<usize>,
    pub(crate) delays: Vec<usize>,
    pub(crate) forbids: Vec<usize>,
    pub(crate) max_time: bool,
}
