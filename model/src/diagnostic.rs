//! The one diagnostic type of genom-check: a stable [`Code`] (the public
//! interface CI scripts match on, LANGUAGE.md section 4), its [`Severity`],
//! a message, labelled spans, an optional help and an optional trace.
//!
//! Every stage (parser, resolver, checks, engines) builds these through small
//! named constructors in its own `diagnostics.rs`; they are rendered in one
//! place (the `genom-render` crate).

use std::fmt;
use std::str::FromStr;

use serde::Serialize;

use crate::span::Span;
use crate::trace::Trace;

/// How serious a diagnostic is. Ordered from least to most severe.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// A suggestion; never affects the exit status.
    Advice,
    /// Probably a mistake; exit 1 only with `--deny warnings`.
    Warning,
    /// The component is wrong or unverified; exit status 1.
    Error,
}

impl Severity {
    /// The lowercase name used in JSON output.
    pub fn as_str(self) -> &'static str {
        match self {
            Severity::Advice => "advice",
            Severity::Warning => "warning",
            Severity::Error => "error",
        }
    }
}

macro_rules! codes {
    ($($(#[$doc:meta])* $variant:ident = $text:literal, $sev:ident, $meaning:literal;)*) => {
        /// Every diagnostic code of LANGUAGE.md section 4. The string form is
        /// stable: CI scripts match on it.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub enum Code {
            $($(#[$doc])* $variant,)*
        }

        impl Code {
            /// Every code, in the order of the spec's table.
            pub const ALL: &'static [Code] = &[$(Code::$variant,)*];

            /// The stable kebab-case code.
            pub fn as_str(self) -> &'static str {
                match self { $(Code::$variant => $text,)* }
            }

            /// The severity the spec assigns to this code.
            pub fn severity(self) -> Severity {
                match self { $(Code::$variant => Severity::$sev,)* }
            }

            /// One-line meaning, as in the spec's table.
            pub fn meaning(self) -> &'static str {
                match self { $(Code::$variant => $meaning,)* }
            }
        }
    };
}

codes! {
    /// The text does not parse.
    Syntax = "syntax", Error, "the text does not parse; says what was expected where";
    /// An included file does not exist or cannot be read.
    IncludeNotFound = "include-not-found", Error, "an included IDL file cannot be found or read";
    /// A file includes itself, directly or not.
    IncludeCycle = "include-cycle", Error, "IDL files include each other in a cycle";
    /// No `component` item.
    MissingComponent = "missing-component", Error, "the file has no `component` item";
    /// Two things of one kind share a name in one scope.
    DuplicateDefinition = "duplicate-definition", Error, "two things of one kind share a name in one scope";
    /// A type name that resolves to nothing.
    UnknownType = "unknown-type", Error, "a type name that resolves to nothing";
    /// A data reference that resolves to nothing.
    UnknownData = "unknown-data", Error, "a data reference that resolves to nothing";
    /// A thread name that resolves to nothing.
    UnknownThread = "unknown-thread", Error, "a thread name that resolves to nothing";
    /// A service name that resolves to nothing.
    UnknownService = "unknown-service", Error, "a service name that resolves to nothing";
    /// A codel name that resolves to nothing.
    UnknownCodel = "unknown-codel", Error, "a codel name that resolves to nothing";
    /// A report name that resolves to nothing.
    UnknownReport = "unknown-report", Error, "a report name that resolves to nothing";
    /// A credential class that resolves to nothing.
    UnknownCredential = "unknown-credential", Error, "a credential class that resolves to nothing";
    /// Unknown attribute, attribute not allowed there, or bad value.
    InvalidAttribute = "invalid-attribute", Error, "unknown attribute, attribute not allowed there, or bad value";
    /// A service with a thread has no start codel.
    MissingStart = "missing-start", Error, "a service that runs on a thread has no start codel";
    /// A service with a start codel names no thread.
    MissingThread = "missing-thread", Error, "a service with a start codel names no thread";
    /// More than one `init` service.
    MultipleInit = "multiple-init", Error, "more than one `init` service";
    /// Two start or two control codels in one service.
    DuplicateCodelKind = "duplicate-codel-kind", Error, "two start codels or two control codels in one service";
    /// A `next` entry that is not allowed.
    BadNext = "bad-next", Error, "a `next` outcome that is not allowed";
    /// An `on-inter` that is not allowed.
    BadOnInter = "bad-on-inter", Error, "an `on-inter` that is not allowed";
    /// A name that is both a codel and a report, or a codel named `end`.
    AmbiguousName = "ambiguous-name", Error, "a name that is both a codel and a report, or a codel named `end`";
    /// A value or argument does not fit its declared type.
    TypeMismatch = "type-mismatch", Error, "a value or argument does not fit its declared type";
    /// One codel function used with different prototypes.
    PrototypeMismatch = "prototype-mismatch", Error, "one codel function used with different prototypes";
    /// An `update` entry that is not an argument of `exec`.
    UpdateNotArgument = "update-not-argument", Error, "an `update` entry that is not an argument of `exec`";
    /// An `update` entry passed as `const`.
    ConstUpdate = "const-update", Error, "an `update` entry that `exec` passes as `const`";
    /// A codel that no execution reaches.
    UnreachableCodel = "unreachable-codel", Warning, "a codel that no execution reaches";
    /// A non-auto service that can never end by itself from some reachable codel.
    NoTermination = "no-termination", Warning, "a non-auto service that can never end by itself from some reachable codel";
    /// An auto service that can end by itself.
    AutoTerminates = "auto-terminates", Warning, "an `auto` service that can end by itself";
    /// A report no codel can produce.
    UnusedReport = "unused-report", Warning, "a report no codel or control codel can produce";
    /// An interruptible codel with no cleanup codel.
    MissingOnInter = "missing-on-inter", Advice, "an interruptible codel with no cleanup codel";
    /// Pending instances that wait on each other.
    Deadlock = "deadlock", Error, "a reachable state with pending instances that wait on each other";
    /// A pending instance that can wait forever.
    Starvation = "starvation", Error, "a pending instance that can wait forever on a running instance that may never end";
    /// A service that no execution can ever start.
    DeadService = "dead-service", Error, "a service that no execution can ever start";
    /// An interrupted service that may never end.
    UnboundedInterrupt = "unbounded-interrupt", Error, "an interrupted service that may never end";
    /// A codel WCET longer than its thread's period.
    CodelOverrun = "codel-overrun", Error, "a codel WCET longer than its thread's period";
    /// A period's codels cannot finish before the next wake-up.
    ThreadOverrun = "thread-overrun", Error, "some reachable period's codels cannot finish before the next wake-up";
    /// Even the fastest execution misses the max-time.
    MaxTimeInfeasible = "max-time-infeasible", Error, "even the fastest execution of the service ends after its max-time";
    /// Some execution misses the max-time.
    MaxTimeExceeded = "max-time-exceeded", Error, "some execution misses the max-time";
    /// Max-time is only enforced by the watchdog.
    MaxTimeWatchdog = "max-time-watchdog", Advice, "an unbounded loop: max-time is only enforced by the watchdog";
    /// A worst-case response time later than a `--deadline`.
    DeadlineMiss = "deadline-miss", Error, "some execution replies to the service later than its `--deadline` (or never)";
    /// Timing checks incomplete because codels lack WCETs.
    MissingWcet = "missing-wcet", Advice, "timing checks incomplete because codels lack `max-time`";
    /// A limit stopped verification.
    Incomplete = "incomplete", Error, "verification did not finish: a limit stopped it, or the engines do not model the component's semantics";
    /// A type that contains itself by value.
    RecursiveType = "recursive-type", Error, "a type that contains itself by value, so that no value of it is finite";
    /// A weaker credential controls a stronger one.
    PrivilegeEscalation = "privilege-escalation", Warning, "a service requestable with a weaker credential controls one that needs a stronger credential";
    /// A preprocessor directive the GenoM3 front end does not interpret.
    IgnoredDirective = "ignored-directive", Advice, "a GenoM3 preprocessor directive that is ignored";
    /// A GenoM3 `yield` or state naming no state of its owner.
    UnknownState = "unknown-state", Error, "a GenoM3 codel yields to, or runs in, a state that no codel of its owner declares";
    /// A GenoM3 codel state that no yield from `start` or `stop` reaches.
    UnreachableState = "unreachable-state", Error, "a GenoM3 codel state that no path of yields from `start` or `stop` reaches";
    /// A GenoM3 `stop` codel from which `ether` cannot be reached.
    StopNoEther = "stop-no-ether", Error, "a GenoM3 `codel<stop>` from which no path of yields reaches `ether`";
    /// A GenoM3 `async` codel sharing data with a codel of another task.
    AsyncSharedData = "async-shared-data", Error, "a GenoM3 `async` codel uses ids data that a codel of another task also uses";
    /// A GenoM3 codel parameter that could be several things.
    MissingSource = "missing-source", Error, "a GenoM3 codel parameter name that matches several sources (ids, local, port, remote) and has no qualifier";
    /// A GenoM3 `provides`/`uses` naming no interface.
    UnknownInterface = "unknown-interface", Error, "a GenoM3 `provides` or `uses` names no known interface";
    /// A GenoM3 cycle of unpaused transitions that nothing leaves.
    Livelock = "livelock", Error, "a reachable cycle of GenoM3 codel transitions without `pause::` or `async` that no yield leaves: the task sweeps it forever";
    /// A GenoM3 cycle of unpaused transitions with a way out.
    UnpausedLoop = "unpaused-loop", Warning, "a reachable cycle of GenoM3 codel transitions without `pause::` or `async`: the task may sweep it many times in one period, or busy-spin between events without a period";
    /// A malformed or unresolved line of a WCET side file.
    BadWcet = "bad-wcet", Error, "a WCET side-file line that is malformed or names an unknown owner or state";
    /// A system file that does not parse or has a bad value.
    BadSystem = "bad-system", Error, "a system file (`--system`) that does not parse, or a key or value it does not accept";
    /// A system file names a component, port or source that does not exist.
    UnknownSystemName = "unknown-system-name", Error, "a system file names a component, port or external source that does not exist";
    /// Two connected ports of different types.
    PortTypeMismatch = "port-type-mismatch", Error, "a system file connects two ports whose IDL types differ";
    /// An input connected more than once.
    DuplicateConnection = "duplicate-connection", Error, "a system file connects one input port more than once";
    /// A bad connection direction.
    BadConnection = "bad-connection", Error, "a system file connects a port the wrong way (an input as a source, an output as a target)";
    /// An input port that nothing feeds.
    UnconnectedInput = "unconnected-input", Warning, "an input port of a system's component that no connection or external source feeds";
    /// A cause-effect chain whose data age or reaction time exceeds its deadline.
    ChainDeadlineMiss = "chain-deadline-miss", Error, "a cause-effect chain's worst-case data age or reaction time exceeds its deadline, or cannot be bounded";
    /// A cause-effect chain that gets no bound.
    ChainUnbounded = "chain-unbounded", Warning, "a cause-effect chain gets no data age bound: a task on it is aperiodic, may overrun, or lacks WCETs";
}

impl fmt::Display for Code {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The error of parsing an unknown code name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown diagnostic code `{0}`")]
pub struct UnknownCode(pub String);

impl FromStr for Code {
    type Err = UnknownCode;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Code::ALL
            .iter()
            .copied()
            .find(|c| c.as_str() == s)
            .ok_or_else(|| UnknownCode(s.to_owned()))
    }
}

/// A span with a message. The first label of a diagnostic is its primary
/// location.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Label {
    /// Where.
    pub span: Span,
    /// What about it (may be empty).
    pub message: String,
}

/// One problem found in a component.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct Diagnostic {
    /// The stable code.
    pub code: Code,
    /// The severity (the code's, from the spec).
    pub severity: Severity,
    /// One-line description, lowercase, no final period.
    pub message: String,
    /// Labelled spans; the first is the primary location.
    pub labels: Vec<Label>,
    /// A suggestion for fixing it.
    pub help: Option<String>,
    /// The counterexample or witness, for behavioural verdicts.
    pub trace: Option<Trace>,
}

impl Diagnostic {
    /// A diagnostic with the code's severity, primary span and label.
    pub fn new(
        code: Code,
        message: impl Into<String>,
        span: Span,
        label: impl Into<String>,
    ) -> Self {
        Self {
            code,
            severity: code.severity(),
            message: message.into(),
            labels: vec![Label {
                span,
                message: label.into(),
            }],
            help: None,
            trace: None,
        }
    }

    /// Adds a secondary label.
    #[must_use]
    pub fn with_label(mut self, span: Span, message: impl Into<String>) -> Self {
        self.labels.push(Label {
            span,
            message: message.into(),
        });
        self
    }

    /// Sets the help text.
    #[must_use]
    pub fn with_help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    /// Sets the help text when there is one.
    #[must_use]
    pub fn with_optional_help(mut self, help: Option<String>) -> Self {
        self.help = help;
        self
    }

    /// Attaches a trace.
    #[must_use]
    pub fn with_trace(mut self, trace: Trace) -> Self {
        self.trace = Some(trace);
        self
    }

    /// The primary span (first label).
    pub fn span(&self) -> Span {
        self.labels.first().map_or(Span::default(), |l| l.span)
    }

    /// The ordering key: file (load order), position, then code and message.
    fn sort_key(&self) -> (u32, u32, Code, &str) {
        let span = self.span();
        (span.start, span.end, self.code, &self.message)
    }
}

/// Sorts diagnostics by file (load order: the checked file first, then its
/// includes), position, code and message, and drops exact duplicates.
pub fn sort_diagnostics(diagnostics: &mut Vec<Diagnostic>) {
    diagnostics.sort_by(|a, b| a.sort_key().cmp(&b.sort_key()));
    diagnostics.dedup();
}

/// The closest of `candidates` to `name`, if any is close enough to be a
/// plausible typo (Jaro-Winkler similarity of at least 0.8). Ties go to the
/// first candidate in alphabetical order, so suggestions are deterministic.
pub fn closest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    candidates
        .into_iter()
        .map(|c| (strsim::jaro_winkler(name, c), c))
        .filter(|&(score, c)| score >= 0.8 && c != name)
        .max_by(|a, b| a.0.total_cmp(&b.0).then_with(|| b.1.cmp(a.1)))
        .map(|(_, c)| c)
}

/// Counts by severity.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct Counts {
    /// Number of errors.
    pub errors: usize,
    /// Number of warnings.
    pub warnings: usize,
    /// Number of advice.
    pub advice: usize,
}

impl Counts {
    /// Counts a list of diagnostics.
    pub fn of(diagnostics: &[Diagnostic]) -> Self {
        let mut c = Counts::default();
        for d in diagnostics {
            c.add(d.severity);
        }
        c
    }

    /// Adds one diagnostic of this severity.
    pub fn add(&mut self, severity: Severity) {
        match severity {
            Severity::Error => self.errors += 1,
            Severity::Warning => self.warnings += 1,
            Severity::Advice => self.advice += 1,
        }
    }

    /// Adds another count.
    pub fn merge(&mut self, other: Counts) {
        self.errors += other.errors;
        self.warnings += other.warnings;
        self.advice += other.advice;
    }
}

/// Source text quoted for a message: in backticks, with control characters
/// escaped (`\0`, `\u{1b}`) so that a message never writes them raw.
pub fn quote(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('`');
    for c in text.chars() {
        if c.is_control() {
            out.extend(c.escape_debug());
        } else {
            out.push(c);
        }
    }
    out.push('`');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_trip_and_are_unique() {
        for &code in Code::ALL {
            assert_eq!(code.as_str().parse::<Code>(), Ok(code));
        }
        let mut names: Vec<_> = Code::ALL.iter().map(|c| c.as_str()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), Code::ALL.len());
        assert!("nope".parse::<Code>().is_err());
    }

    #[test]
    fn severities_follow_the_spec_table() {
        assert_eq!(Code::Syntax.severity(), Severity::Error);
        assert_eq!(Code::UnreachableCodel.severity(), Severity::Warning);
        assert_eq!(Code::MissingOnInter.severity(), Severity::Advice);
        assert_eq!(Code::MissingWcet.severity(), Severity::Advice);
        assert_eq!(Code::PrivilegeEscalation.severity(), Severity::Warning);
        assert_eq!(Code::Incomplete.severity(), Severity::Error);
    }

    #[test]
    fn sorting_is_by_position_and_removes_duplicates() {
        let a = Diagnostic::new(Code::Syntax, "b", Span::new(10, 11), "");
        let b = Diagnostic::new(Code::Syntax, "a", Span::new(2, 3), "");
        let mut v = vec![a.clone(), b.clone(), a.clone()];
        sort_diagnostics(&mut v);
        assert_eq!(v, vec![b, a]);
    }
}
