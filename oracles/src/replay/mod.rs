//! An independent replay of the execution semantics (LANGUAGE.md section 3)
//! against a verdict's trace.
//!
//! The explorer (`genom_engine::dialect`) and this module are two readings
//! of the same text; this one is written from the specification alone and
//! shares no code with the explorer nor with `genom_model::behaviour`: it reads
//! only the resolved [`Component`] (services, codels and their `next`,
//! `on-inter`, `stops`/`delays`/`forbids`, `max-time`, kinds, threads and
//! [`Component::conflicts`]). It trusts nothing in the trace: every step is
//! checked to be allowed in the current state, and the state after the last
//! step is checked to show the claimed violation ([`ReplayEnd::exhibits`]).
//!
//! # State
//!
//! For each service, a list of *instances* ([`Instance`]): `pending`
//! (acknowledged, not started, with the interrupted instances it still
//! waits for), `active` at a codel (ready, or running, possibly with the
//! interrupt noted), or `stopping` at a codel (ready or running). Plus
//! whether initialisation is done.
//!
//! # How steps are read
//!
//! - `component-start` is the first step, and only the first. Without an
//!   `init` service, initialisation is done at once.
//! - `request` S (thread `control`) opens a request, closed by `reject` or
//!   `acknowledge`; one request at a time. The rules of section 3 are
//!   applied in order: a `reject`
//!   must give (in `outcome`) the reason of the first rule that applies
//!   (`NOT_INITIALIZED`, `FORBIDDEN`, `BUSY`); when none applies, only the
//!   control codel can reject (with one of S's reports) or `accept`, and it
//!   must be able to take its locks (no conflicting codel is running) from
//!   the `request` step on. The control codel runs on the control thread
//!   from `request` to its `accept` or `reject`, which may be later (a
//!   timed trace): meanwhile the other threads go on (`wake-up`,
//!   `codel-start` of a codel that does not conflict with it, `codel-end`,
//!   `start`, `reply`, `watchdog`), but no other request is handled. Then
//!   every instance of the services of `S.stops` must be interrupted
//!   (`interrupt` steps; `codel` is `null` for a pending instance, else the
//!   instance's current codel) before `acknowledge` creates the pending
//!   instance, which waits for the stopped instances still running.
//! - `start` S: S's pending instance starts; it must not be delayed (no
//!   other service with an instance lists S in `delays`) nor wait for a
//!   stopped instance. Starting is urgent: no other step than `start`,
//!   `reply`, `acknowledge` or the steps of an open request may happen
//!   while some pending instance can start.
//! - `codel-start` S `codel`: S's instance is ready at that codel; its
//!   thread runs no other codel, and no codel running on another thread
//!   conflicts with it.
//! - `codel-end` S `codel` `outcome`: the running codel ends; the outcome
//!   must be in its `next` (`end` for an empty `next`). An interrupted
//!   active instance goes to the codel's `on-inter` instead (the outcome may
//!   then be `null`), or ends with `INTERRUPTED`.
//! - `interrupt` only inside a request, for a service of the requester's
//!   `stops`; `watchdog` only for a service with `max-time`. A stopping
//!   instance (or one whose running codel was already interrupted) is not
//!   interrupted again.
//! - Every ending is followed at once by the `reply` step of that instance
//!   with its value: `end`, a report, `INTERRUPTED`, or `TIMEOUT` when the
//!   watchdog interrupted it (an inter codel's report outcome replies that
//!   report). A reply must carry its value, and there is exactly one per
//!   instance.
//! - When initialisation completes (at `component-start` without an `init`
//!   service, else when the `init` service replies `end`), every `auto`
//!   service starts (`start` with no request: it becomes active at its start
//!   codel, or completes at once without one) before anything else happens,
//!   whatever `delays` or `forbids` the autos list about each other: autos
//!   are never pending.
//! - `wake-up` and `delay` change nothing in this untimed reading; `time_ns`
//!   must not decrease.
//! - `violation` is the last step, and there is one.
//!
//! With `loop_start`, the steps from there to the violation must lead back
//! to the state they start from (instances compared by service, phase and
//! codel), so that they can repeat forever.

mod claims;
pub mod genom3;
pub mod genom3_timed;
mod requests;
mod state;
mod steps;

use genom_model::component::Component;
use genom_model::trace::Trace;

pub use claims::{Claim, Fate, ReplayEnd, ReplayError};
pub use state::{Instance, InstanceId, Phase, State};
use steps::Replayer;

/// Replays `trace` in `c` from component start; fails at the first step the
/// semantics does not allow (or if the trace is not shaped as a verdict's
/// trace: `component-start` first, `violation` last, a well-formed loop).
pub fn replay(c: &Component, trace: &Trace) -> Result<ReplayEnd, ReplayError> {
    Replayer::new(c).run(trace)
}

/// [`replay`], then [`ReplayEnd::exhibits`].
pub fn replay_claim(
    c: &Component,
    trace: &Trace,
    claim: Claim<'_>,
) -> Result<ReplayEnd, ReplayError> {
    let end = replay(c, trace)?;
    end.exhibits(c, claim)?;
    Ok(end)
}
