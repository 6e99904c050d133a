//! What the engine benches share: the line each prints on stderr for one
//! run of a case before criterion measures it.

use std::time::Duration;

/// Prints one run's figures: states, transitions, time, states per second,
/// bytes per stored state, and whether it finished.
#[allow(clippy::cast_precision_loss, clippy::print_stderr)]
pub fn print(name: &str, states: u64, transitions: u64, elapsed: Duration, bytes: f64, done: bool) {
    let secs = elapsed.as_secs_f64().max(1e-9);
    eprintln!(
        "{name}: {states} states, {transitions} transitions, {:.1} ms, {:.0} states/s, {bytes:.1} B/state{}",
        secs * 1000.0,
        states as f64 / secs,
        if done { "" } else { ", incomplete" }
    );
}
