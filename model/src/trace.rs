//! Counterexample and witness traces attached to behavioural and timing
//! verdicts: the sequence of events from component start (LANGUAGE.md
//! section 3) that leads to the problem.

use crate::span::Span;

/// The kind of one trace event.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Event {
    /// The component starts (time 0).
    ComponentStart,
    /// A client sends a request for a service.
    Request,
    /// The control thread rejects a request (reason in `outcome`).
    Reject,
    /// The control codel accepts a request.
    Accept,
    /// The request is acknowledged: the service instance becomes pending.
    Acknowledge,
    /// A service instance becomes active at its start codel.
    Start,
    /// A thread starts running a codel.
    CodelStart,
    /// A codel finishes with an outcome.
    CodelEnd,
    /// A thread takes a ticket in GenoM3's resource queue for its next
    /// codel, which cannot begin yet (a lock it needs is held, or older
    /// tickets wait).
    LockWait,
    /// A service instance is interrupted.
    Interrupt,
    /// The max-time watchdog fires.
    Watchdog,
    /// A periodic thread wakes up.
    WakeUp,
    /// The final reply of an instance (result in `outcome`).
    Reply,
    /// Time passes with nothing else happening.
    Delay,
    /// The violation itself (last step of a counterexample).
    Violation,
}

impl Event {
    /// Stable kebab-case name used in JSON output.
    pub fn as_str(self) -> &'static str {
        match self {
            Event::ComponentStart => "component-start",
            Event::Request => "request",
            Event::Reject => "reject",
            Event::Accept => "accept",
            Event::Acknowledge => "acknowledge",
            Event::Start => "start",
            Event::CodelStart => "codel-start",
            Event::CodelEnd => "codel-end",
            Event::LockWait => "lock-wait",
            Event::Interrupt => "interrupt",
            Event::Watchdog => "watchdog",
            Event::WakeUp => "wake-up",
            Event::Reply => "reply",
            Event::Delay => "delay",
            Event::Violation => "violation",
        }
    }
}

/// One step of a trace.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TraceStep {
    /// What happens.
    pub event: Event,
    /// When, in nanoseconds since component start (timed traces only).
    pub time_ns: Option<u64>,
    /// The thread involved (`control` for the control thread).
    pub thread: Option<String>,
    /// The service involved.
    pub service: Option<String>,
    /// The codel involved.
    pub codel: Option<String>,
    /// The outcome, reject reason or reply.
    pub outcome: Option<String>,
    /// Where in the source (codel or service), for display.
    pub span: Option<Span>,
    /// A sentence describing the step.
    pub text: String,
    /// A step of a thread that plays no part in the finding (no thread
    /// involved in it waited for that thread's codels nor behind its
    /// tickets): kept, since a replay needs it, and left out of human
    /// output.
    pub aside: bool,
}

impl TraceStep {
    /// A step with only an event and a sentence.
    pub fn new(event: Event, text: impl Into<String>) -> Self {
        Self {
            event,
            time_ns: None,
            thread: None,
            service: None,
            codel: None,
            outcome: None,
            span: None,
            text: text.into(),
            aside: false,
        }
    }
}

/// A sequence of events from component start. For infinite behaviours
/// (starvation, unbounded loops) `loop_start` is the index of the first step
/// of the cycle that repeats forever after the last step.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Trace {
    /// The steps, in order.
    pub steps: Vec<TraceStep>,
    /// Where the repeating cycle starts, for lasso-shaped traces.
    pub loop_start: Option<usize>,
}

impl Trace {
    /// The threads whose steps are set aside ([`TraceStep::aside`]), in
    /// the order they first appear.
    pub fn aside_threads(&self) -> Vec<&str> {
        let mut out: Vec<&str> = Vec::new();
        for s in self.steps.iter().filter(|s| s.aside) {
            if let Some(t) = s.thread.as_deref().filter(|t| !out.contains(t)) {
                out.push(t);
            }
        }
        out
    }
}
