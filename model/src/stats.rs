//! Verification statistics reported next to the diagnostics: how much of the
//! state space was explored and how long it took.

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
}
