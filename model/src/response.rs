//! Worst-case response times: for each service, the largest time from the
//! acknowledgment of an instance to its final reply over all executions.
//! Dialect-independent: an engine computes them, the renderers print them
//! (a table after the diagnostics, `response_times` in JSON). How the zone
//! engine computes them and what each [`Bound`] means is in
//! `docs/timing.md` ("Worst-case response times").

use serde::Serialize;

use crate::span::Span;

/// What is known of a service's worst-case response time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bound {
    /// Exactly this many nanoseconds (a supremum: some execution comes
    /// arbitrarily close to it, none goes beyond).
    Exact(u64),
    /// At most this many nanoseconds: an upper bound, not proven reached
    /// (the model over-approximates, e.g. a watchdog timed approximately).
    AtMost(u64),
    /// More than this many nanoseconds (the horizon of the computation),
    /// and not proven unbounded.
    Above(u64),
    /// Some execution keeps an instance alive forever without replying.
    Unbounded,
    /// Not decided (the exploration stopped on a limit, or the model
    /// cannot decide it).
    Unknown,
}

impl Bound {
    /// The stable name of the bound's kind, as in JSON `status`.
    pub fn status(self) -> &'static str {
        match self {
            Bound::Exact(_) => "exact",
            Bound::AtMost(_) => "at-most",
            Bound::Above(_) => "above",
            Bound::Unbounded => "unbounded",
            Bound::Unknown => "unknown",
        }
    }

    /// The figure in nanoseconds, when the bound has one.
    pub fn ns(self) -> Option<u64> {
        match self {
            Bound::Exact(n) | Bound::AtMost(n) | Bound::Above(n) => Some(n),
            Bound::Unbounded | Bound::Unknown => None,
        }
    }

    /// Whether the worst case is known to be later than `deadline_ns`.
    pub fn exceeds(self, deadline_ns: u64) -> bool {
        match self {
            Bound::Exact(n) => n > deadline_ns,
            Bound::Above(n) => n >= deadline_ns,
            Bound::Unbounded => true,
            Bound::AtMost(_) | Bound::Unknown => false,
        }
    }

    /// The bound as people read it: `12ms`, `≤ 30.02s`, `> 1s`,
    /// `unbounded`, `unknown`.
    pub fn human(self) -> String {
        use crate::duration::format_ns;
        match self {
            Bound::Exact(n) => format_ns(n),
            Bound::AtMost(n) => format!("≤ {}", format_ns(n)),
            Bound::Above(n) => format!("> {}", format_ns(n)),
            Bound::Unbounded => "unbounded".to_owned(),
            Bound::Unknown => "unknown".to_owned(),
        }
    }
}

/// The worst-case response time of one service.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ResponseTime {
    /// The service's name.
    pub service: String,
    /// Its name in the source.
    pub span: Span,
    /// What is known of its worst case.
    pub worst: Bound,
    /// The service's own time: its codels' WCETs along its longest chain
    /// (`None` when a loop leaves no longest chain). The rest of `worst` is
    /// waiting: for locks, for other requests, for its task's ticks.
    pub own: Option<u64>,
    /// Why the bound is not exact, when it is not (a short clause).
    pub note: Option<String>,
}

/// A response time as JSON: `{"service", "status", "worst_ns", "note"}`.
#[derive(Debug, Clone, Serialize)]
pub struct JsonResponseTime {
    /// The service.
    pub service: String,
    /// `exact`, `at-most`, `above`, `unbounded` or `unknown`.
    pub status: &'static str,
    /// The figure of `exact`, `at-most` and `above`, else null.
    pub worst_ns: Option<u64>,
    /// The service's own codels' time on their longest chain, or null (a
    /// loop); `worst_ns` beyond it is waiting.
    pub own_ns: Option<u64>,
    /// Why the bound is not exact, or null.
    pub note: Option<String>,
}

impl From<&ResponseTime> for JsonResponseTime {
    fn from(r: &ResponseTime) -> Self {
        JsonResponseTime {
            service: r.service.clone(),
            status: r.worst.status(),
            worst_ns: r.worst.ns(),
            own_ns: r.own,
            note: r.note.clone(),
        }
    }
}

/// Sorts response times by service name (the order of every output).
pub fn sort_response_times(times: &mut [ResponseTime]) {
    times.sort_by(|a, b| a.service.cmp(&b.service));
}

/// The human table of response times (empty text without any): one line
/// per service, after the diagnostics.
pub fn render_table(times: &[ResponseTime]) -> String {
    if times.is_empty() {
        return String::new();
    }
    let head = ["service", "worst response", "own codels", ""];
    let rows: Vec<[String; 4]> = times
        .iter()
        .map(|r| {
            [
                r.service.clone(),
                r.worst.human(),
                r.own
                    .map_or_else(|| "loops".to_owned(), crate::duration::format_ns),
                r.note.clone().unwrap_or_default(),
            ]
        })
        .collect();
    let width = |i: usize| {
        rows.iter()
            .map(|r| r[i].chars().count())
            .chain([head[i].len()])
            .max()
            .unwrap_or(0)
    };
    let widths = [width(0), width(1), width(2)];
    let line = |cells: [&str; 4]| {
        let mut text = String::from("  ");
        for (cell, w) in cells.iter().zip(widths) {
            text.push_str(cell);
            text.push_str(&" ".repeat(w - cell.chars().count() + 2));
        }
        text.push_str(cells[3]);
        format!("{}\n", text.trim_end())
    };
    let mut out = String::from("worst-case response times (acknowledgment to final reply):\n");
    out.push_str(&line(head));
    for r in &rows {
        out.push_str(&line([&r[0], &r[1], &r[2], &r[3]]));
    }
    out.push_str(
        "  (own codels: the service's own codels on their longest chain, at their WCETs; the rest of a worst response is waiting for locks, other requests or its task's ticks)\n",
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rt(service: &str, worst: Bound) -> ResponseTime {
        ResponseTime {
            service: service.to_owned(),
            span: Span::default(),
            worst,
            own: Some(2_000_000),
            note: None,
        }
    }

    #[test]
    fn bounds_compare_with_deadlines() {
        assert!(Bound::Exact(12).exceeds(11));
        assert!(!Bound::Exact(12).exceeds(12));
        assert!(Bound::Above(12).exceeds(12));
        assert!(!Bound::Above(12).exceeds(13));
        assert!(Bound::Unbounded.exceeds(u64::MAX));
        assert!(!Bound::AtMost(12).exceeds(1));
        assert!(!Bound::Unknown.exceeds(1));
    }

    #[test]
    fn the_table_aligns_its_columns() {
        let table = render_table(&[
            rt("Go", Bound::Exact(12_000_000)),
            rt("LongName", Bound::Unbounded),
        ]);
        let lines: Vec<&str> = table.lines().collect();
        assert_eq!(lines.len(), 5, "{table}");
        assert_eq!(lines[1], "  service   worst response  own codels");
        assert_eq!(lines[2], "  Go        12ms            2ms");
        assert_eq!(lines[3], "  LongName  unbounded       2ms");
        assert!(lines[4].starts_with("  (own codels: "), "{table}");
        assert_eq!(render_table(&[]), "");
    }
}
