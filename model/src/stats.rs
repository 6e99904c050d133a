//! Verification statistics reported next to the diagnostics: how much of the
//! state space was explored, how long it took, and which engine decided
//! each part of the component.

use serde::Serialize;

/// Figures of one check run. Absent figures mean the stage did not run.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Statistics {
    /// Discrete (or symbolic, when timed) states stored.
    pub states: u64,
    /// Transitions fired.
    pub transitions: u64,
    /// Wall-clock time of the whole check, in milliseconds.
    pub time_ms: f64,
    /// Whether exploration covered the whole state space.
    pub complete: bool,
    /// Bytes per stored state (encoding plus hash-table overhead).
    pub bytes_per_state: Option<f64>,
    /// What explored each part of the component, in exploration order.
    pub decided_by: Vec<Decision>,
    /// What the verdicts rest on besides the component (rendered at the
    /// file's level, JSON `assumptions`, not inside `statistics`).
    #[serde(skip)]
    pub assumptions: Vec<Assumption>,
}

/// Something a verdict rests on that the component itself does not say:
/// the WCETs of a side file, or a bound on the executions explored. A
/// clean verdict holds only under its assumptions.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Serialize)]
pub struct Assumption {
    /// `wcet` (durations from a WCET file) or `instances` (a bound on the
    /// concurrent instances of each activity).
    pub kind: &'static str,
    /// The WCET file, for `wcet` (none: the component's own `max-time`s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// The bound, for `instances`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bound: Option<usize>,
    /// What it says, in a sentence that follows "assuming".
    pub text: String,
}

impl Assumption {
    /// Codels take at most the WCETs of `file`.
    pub fn wcet(file: &str) -> Self {
        Assumption {
            kind: "wcet",
            file: Some(file.to_owned()),
            bound: None,
            text: format!("every codel takes at most its WCET from `{file}`"),
        }
    }

    /// LANGUAGE.md: codels take at most their `max-time` (the WCETs are
    /// the component's own; one without `max-time` is taken as running in
    /// no time: `missing-wcet`).
    pub fn max_times() -> Self {
        Assumption {
            kind: "wcet",
            file: None,
            bound: None,
            text: "every codel takes at most its `max-time` (one without, no time)".to_owned(),
        }
    }

    /// At most `n` concurrent instances of each activity; `restarts`: some
    /// activity interrupts itself, and one more request for it, which
    /// interrupts the running ones, is explored.
    pub fn instances(n: usize, restarts: bool) -> Self {
        let each = if n == 1 {
            "at most 1 concurrent request of each activity (from its `validate` to its reply)"
                .to_owned()
        } else {
            format!(
                "at most {n} concurrent requests of each activity (from its `validate` to its reply)"
            )
        };
        let text = if restarts {
            format!(
                "{each}, plus one new request for an activity that interrupts itself (a client restarting it) while they run"
            )
        } else {
            each
        };
        Assumption {
            kind: "instances",
            file: None,
            bound: Some(n),
            text,
        }
    }
}

impl Statistics {
    /// The texts of the assumptions joined by `; `, as they follow
    /// "assuming" (`None` when the verdicts rest on nothing else).
    pub fn assumed(&self) -> Option<String> {
        let texts: Vec<&str> = self.assumptions.iter().map(|a| a.text.as_str()).collect();
        (!texts.is_empty()).then(|| texts.join("; "))
    }

    /// The engines that decided, in a fixed order, joined by `+`:
    /// `explicit`, `symbolic`, `explicit+symbolic`, `zones`.
    pub fn engines(&self) -> String {
        let mut names: Vec<&str> = self.decided_by.iter().map(|d| d.method.engine()).collect();
        names.sort_unstable();
        names.dedup();
        names.join("+")
    }
}

/// How one part of the component (a cluster of services that interact, or
/// the initialisation phase) was explored.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Decision {
    /// The services explored, by name.
    pub services: Vec<String>,
    /// How.
    pub method: Method,
    /// The engine: `explicit`, `symbolic` or `zones`.
    pub engine: &'static str,
    /// States stored (symbolic: configurations in the reachable set).
    pub states: u64,
    /// Whether that exploration finished.
    pub complete: bool,
}

impl Decision {
    /// A record of `method` over `services`.
    pub fn new(services: Vec<String>, method: Method, states: u64, complete: bool) -> Self {
        Decision {
            services,
            method,
            engine: method.engine(),
            states,
            complete,
        }
    }
}

/// An exploration method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Explicit, every interleaving.
    Exhaustive,
    /// Explicit, with the partial-order reduction.
    Reduced,
    /// Explicit, part by part (compositional).
    Compositional,
    /// Symbolic: the reachable set as a BDD.
    Symbolic,
    /// Timed: explicit discrete states with clock zones.
    Zones,
    /// Timed, without exploring: a static bound on each task's wake-up
    /// shorter than its period (GenoM3, docs/genom3-semantics.md 15.12).
    Bound,
    /// Timed: zones, until every cause of overrun the static bound leaves
    /// possible was found, each with its trace (GenoM3,
    /// docs/genom3-semantics.md 15.14).
    Witnesses,
}

impl Method {
    /// The engine the method belongs to.
    pub fn engine(self) -> &'static str {
        match self {
            Method::Exhaustive | Method::Reduced | Method::Compositional => "explicit",
            Method::Symbolic => "symbolic",
            Method::Zones | Method::Witnesses => "zones",
            Method::Bound => "bound",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn engines_are_listed_once_in_a_fixed_order() {
        let d = |m| Decision::new(vec!["a".to_owned()], m, 1, true);
        let s = Statistics {
            decided_by: vec![
                d(Method::Symbolic),
                d(Method::Reduced),
                d(Method::Compositional),
            ],
            ..Statistics::default()
        };
        assert_eq!(s.engines(), "explicit+symbolic");
        assert_eq!(Statistics::default().engines(), "");
        let json = serde_json::to_string(&d(Method::Compositional)).ok();
        assert_eq!(
            json.as_deref(),
            Some(
                r#"{"services":["a"],"method":"compositional","engine":"explicit","states":1,"complete":true}"#
            )
        );
    }
}
