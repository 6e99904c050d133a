//! Resource limits shared by every phase: a deadline (`--timeout`) and a
//! memory bound (`--max-memory`), looked at by the parsers, the static
//! phase and the engines through one [`Watch`].
//!
//! The memory measured is the process's heap in use, counted by the
//! binary's global allocator into [`heap`]; a library used without that
//! allocator (tests, fuzzing) sees 0 there, and the engines then fall back
//! to the size of their own state storage. The allocator refuses to grow
//! the heap past [`heap_bound`] (the process then stops with a one-line
//! message), and the phases stop cleanly, with `incomplete`, once the heap
//! reaches [`soft_bound`], a little below it: the resident size stays
//! under `--max-memory` (the binary's code and stacks are the margin).

use std::time::Instant;

/// The longest duration genom-check reads (a period, delay, WCET,
/// `max-time` or deadline): one day, in nanoseconds. Sums of thousands of
/// such durations stay far below the range of the timed engines'
/// arithmetic (zone bounds hold constants below 2^61), so no sum wraps or
/// saturates into a verdict; a longer duration is an error where it is
/// read.
pub const MAX_DURATION_NS: u64 = 86_400_000_000_000;

/// The error text for a duration above [`MAX_DURATION_NS`].
pub fn duration_too_long(text: &str) -> String {
    format!("`{text}` is longer than genom-check's limit of one day (86400s) for a duration")
}

use crate::{Code, Diagnostic, Span};

/// The live heap of the process, as counted by a global allocator that
/// reports to it (the `genom-check` binary's).
pub mod heap {
    use std::sync::atomic::{AtomicUsize, Ordering};

    static IN_USE: AtomicUsize = AtomicUsize::new(0);

    /// Records `bytes` allocated; returns the heap in use after it.
    pub fn allocated(bytes: usize) -> usize {
        IN_USE
            .fetch_add(bytes, Ordering::Relaxed)
            .saturating_add(bytes)
    }

    /// Records `bytes` freed.
    pub fn freed(bytes: usize) {
        IN_USE.fetch_sub(bytes, Ordering::Relaxed);
    }

    /// Bytes of heap in use (0 when no counting allocator is installed).
    pub fn in_use() -> usize {
        IN_USE.load(Ordering::Relaxed)
    }
}

/// The room left for the binary's code, stacks and the allocator's own
/// overhead (freed memory it keeps): a quarter of the limit, at most
/// 64 MiB.
fn margin(max_memory: usize) -> usize {
    (max_memory / 4).min(64 << 20)
}

/// The heap size past which the allocator refuses to grow (and the
/// process stops): `max_memory` less a margin for what is not heap.
pub fn heap_bound(max_memory: usize) -> usize {
    max_memory - margin(max_memory)
}

/// The heap size at which the phases stop cleanly with `incomplete`: seven
/// eighths of [`heap_bound`], so that the step in progress (a vector that
/// doubles, a zone) still fits under it.
pub fn soft_bound(max_memory: usize) -> usize {
    let hard = heap_bound(max_memory);
    hard - hard / 8
}

/// Which limit stopped a phase.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Limit {
    /// `--timeout` passed.
    Time,
    /// The heap reached [`soft_bound`] of `--max-memory`.
    Memory,
}

impl Limit {
    /// The option that sets it: `--timeout`.
    pub fn option(self) -> &'static str {
        match self {
            Limit::Time => "--timeout",
            Limit::Memory => "--max-memory",
        }
    }

    /// How a message names it: `time limit (--timeout)`.
    pub fn describe(self) -> &'static str {
        match self {
            Limit::Time => "time limit (--timeout)",
            Limit::Memory => "memory limit (--max-memory)",
        }
    }
}

/// A deadline and a memory bound, looked at between two steps of a phase.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Watch {
    /// When to stop.
    pub deadline: Option<Instant>,
    /// `--max-memory`, in bytes.
    pub max_memory: usize,
}

impl Default for Watch {
    fn default() -> Self {
        Watch::unlimited()
    }
}

impl Watch {
    /// No deadline and no memory bound.
    pub fn unlimited() -> Self {
        Watch {
            deadline: None,
            max_memory: usize::MAX,
        }
    }

    /// The limit passed, if any: time first (or a [`cancel`]), then the
    /// process's heap.
    pub fn exceeded(&self) -> Option<Limit> {
        if cancelled() || self.deadline.is_some_and(|d| Instant::now() >= d) {
            return Some(Limit::Time);
        }
        self.heap_exceeded().then_some(Limit::Memory)
    }

    /// Whether the process's heap reached [`soft_bound`].
    pub fn heap_exceeded(&self) -> bool {
        heap::in_use() >= soft_bound(self.max_memory)
    }
}

/// Whether a check of this process is asked to stop ([`cancel`]).
static CANCELLED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Asks the check running in this process to stop at its next limit test,
/// as if its deadline had passed (`on`), or lets the next one run
/// (`!on`). The language server cancels a check whose text changed; the
/// command line never does.
pub fn cancel(on: bool) {
    CANCELLED.store(on, std::sync::atomic::Ordering::Relaxed);
}

/// Whether [`cancel`] asked the running check to stop.
pub fn cancelled() -> bool {
    CANCELLED.load(std::sync::atomic::Ordering::Relaxed)
}

/// Whether `limits`-style deadline `d` passed, or the check was cancelled.
pub fn out_of_time(deadline: Option<Instant>) -> bool {
    cancelled() || deadline.is_some_and(|d| Instant::now() >= d)
}

/// `incomplete`: `limit` passed while a front-end was parsing, at `at`;
/// the rest of the text was not read and nothing was checked.
pub fn parsing_stopped(at: Span, limit: Limit) -> Diagnostic {
    let raise = limit.option();
    Diagnostic::new(
        Code::Incomplete,
        format!(
            "verification is incomplete: the {} was reached while parsing",
            limit.describe()
        ),
        at,
        "parsing stopped here",
    )
    .with_help(format!(
        "nothing was checked: the rest of the file was not read; raise {raise}"
    ))
}

/// A limit passed during the static checks, at the component's name:
/// `left` names the checks that did not run; nothing behavioural ran
/// either.
pub fn static_stopped(at: Span, limit: Limit, left: &[&str]) -> Diagnostic {
    let raise = limit.option();
    Diagnostic::new(
        Code::Incomplete,
        format!(
            "verification is incomplete: the {} was reached during the static checks",
            limit.describe()
        ),
        at,
        "not fully verified",
    )
    .with_help(format!(
        "not checked: {}, and every behavioural property; raise {raise}",
        left.join(", ")
    ))
}

/// The states stored by the exploration running in this process, as its
/// last periodic limit test saw them: what a progress display shows.
static EXPLORED: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// Records that the running exploration has stored `states` states (the
/// explorers call it at their periodic time and memory test; nothing reads
/// it but a progress display).
pub fn report_explored(states: usize) {
    let states = u64::try_from(states).unwrap_or(u64::MAX);
    EXPLORED.store(states, std::sync::atomic::Ordering::Relaxed);
}

/// The states the running exploration last reported ([`report_explored`]).
pub fn explored() -> u64 {
    EXPLORED.load(std::sync::atomic::Ordering::Relaxed)
}

/// A count as people read it: `1234567` as `1,234,567`.
pub fn grouped(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn counts_are_grouped_by_thousands() {
        assert_eq!(grouped(0), "0");
        assert_eq!(grouped(999), "999");
        assert_eq!(grouped(1000), "1,000");
        assert_eq!(grouped(10_000_000), "10,000,000");
    }

    use super::*;

    #[test]
    fn bounds_leave_a_margin_and_stop_softly_first() {
        let m = 200 << 20;
        assert_eq!(heap_bound(m), 150 << 20);
        assert!(soft_bound(m) < heap_bound(m));
        assert_eq!(heap_bound(8 << 30), (8 << 30) - (64 << 20));
        assert_eq!(heap_bound(0), 0);
    }

    #[test]
    fn an_unlimited_watch_never_stops_and_a_past_deadline_does() {
        assert_eq!(Watch::unlimited().exceeded(), None);
        let past = Watch {
            deadline: Some(Instant::now()),
            max_memory: usize::MAX,
        };
        assert_eq!(past.exceeded(), Some(Limit::Time));
    }
}
