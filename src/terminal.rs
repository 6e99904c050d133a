//! Terminal facts: whether to colour output and how wide to draw it, and
//! the one way the commands write to standard output ([`emit`]), which
//! remembers a failed write so that the run ends with exit status 2.

use std::io::IsTerminal as _;
use std::sync::OnceLock;

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

/// Why writing to stdout failed, once it has (a closed pipe aside).
static FAILED: OnceLock<String> = OnceLock::new();

/// Writes to stdout. A closed pipe (`genom-check ... | head`) ends the
/// output quietly, as Unix tools do: the rest is dropped and the exit
/// status is the command's. Any other failure (a full disk, `> /dev/full`,
/// the file size limit) is remembered for [`failure`], and nothing more is
/// written.
pub fn emit(text: &str) {
    use std::io::Write as _;
    if FAILED.get().is_some() {
        return;
    }
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        if e.kind() != std::io::ErrorKind::BrokenPipe {
            let _ = FAILED.set(e.to_string());
        }
    }
}

/// Why writing to stdout failed, if it did (other than a closed pipe).
pub fn failure() -> Option<&'static str> {
    FAILED.get().map(String::as_str)
}

/// A path from outside (an output, an input read) as it may be shown on
/// stderr: `/`-separated, its control characters escaped. (`-` stays `-`:
/// for `-o` it is a file name, not standard input.)
pub fn shown(path: &std::path::Path) -> String {
    let path = genom_model::span::display_path(path);
    genom_render::escaped(&path).into_owned()
}
