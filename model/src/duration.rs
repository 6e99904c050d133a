//! How a duration in nanoseconds is written for people (reports,
//! messages, response times).

/// Formats nanoseconds with the largest unit that divides them exactly.
pub fn format_ns(ns: u64) -> String {
    const UNITS: [(u64, &str); 4] = [
        (60_000_000_000, "min"),
        (1_000_000_000, "s"),
        (1_000_000, "ms"),
        (1_000, "us"),
    ];
    if ns == 0 {
        return "0".to_owned();
    }
    for (factor, unit) in UNITS {
        if ns % factor == 0 {
            return format!("{}{unit}", ns / factor);
        }
    }
    format!("{ns}ns")
}
