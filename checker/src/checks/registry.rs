//! What the registry ([`super::STATIC_CHECKS`], [`super::VERDICTS`]) knows
//! of a check: each check file describes itself with these, and the
//! registry lists the descriptions. The codes, their explanations, and
//! which components a static check applies to are read from here only.

use genom_model::component::Component;
use genom_model::{Code, Diagnostic, Dialect};

/// A code a check reports and its long explanation (Markdown, as
/// `genom-check explain CODE` prints it after the code's one-line meaning).
pub type Explained = (Code, &'static str);

/// Which components a static check applies to: the one place that says it
/// (a check never tests the component's language itself to skip it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Applies {
    /// Every component.
    Always,
    /// Components of this language only (the reason is in the check's
    /// docs).
    Only(Dialect),
}

impl Applies {
    /// Whether the check applies to a component written in `dialect`.
    pub fn to(self, dialect: Dialect) -> bool {
        match self {
            Applies::Always => true,
            Applies::Only(d) => d == dialect,
        }
    }
}

/// A static check as the registry runs it: the model in, its findings out.
#[derive(Debug, Clone, Copy)]
pub struct StaticCheck {
    /// The words naming it when a limit stops the static phase before it.
    pub name: &'static str,
    /// The components it applies to.
    pub applies: Applies,
    /// The check.
    pub run: fn(&Component) -> Vec<Diagnostic>,
    /// The codes it reports, with their explanations.
    pub codes: &'static [Explained],
}
