//! Terminal facts: whether to colour output and how wide to draw it.

use std::io::IsTerminal as _;

use crate::cli::Color;

/// Width used when stdout is not a terminal (stable for snapshots and CI).
pub const DEFAULT_WIDTH: usize = 100;

/// Whether to use ANSI colours.
pub fn use_color(choice: Color) -> bool {
    match choice {
        Color::Always => true,
        Color::Never => false,
        Color::Auto => {
            std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty())
                && std::env::var("TERM").map_or(true, |t| t != "dumb")
                && std::io::stdout().is_terminal()
        }
    }
}

/// Width for wrapping reports: `COLUMNS` on a terminal, else the default.
pub fn width() -> usize {
    if !std::io::stdout().is_terminal() {
        return DEFAULT_WIDTH;
    }
    std::env::var("COLUMNS")
        .ok()
        .and_then(|c| c.parse::<usize>().ok())
        .filter(|&w| w >= 40)
        .unwrap_or(DEFAULT_WIDTH)
}

/// Writes to stdout. A closed pipe (`genom-check ... | head`) is not an
/// error worth a panic: the rest of the output is dropped silently.
pub fn emit(text: &str) {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    let _ = out.write_all(text.as_bytes()).and_then(|()| out.flush());
}
