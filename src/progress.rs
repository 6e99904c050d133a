//! Progress of a long check on a terminal: after a second, a line on
//! stderr that says which file is explored, how many states the running
//! exploration has stored (`genom_model::limits::explored`, reported by the
//! explorers at their periodic limit test), how long it has run and the
//! limits it will stop at, rewritten in place a few times a second and
//! erased when the check ends. Only for the human format on a terminal
//! (stderr), never when piped, quiet or in a machine format: the caller
//! decides with [`Progress::wanted`].

use std::io::{IsTerminal, Write as _};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How long a check runs before its progress is shown.
const QUIET_FOR: Duration = Duration::from_secs(1);
/// How often the line is rewritten.
const EVERY: Duration = Duration::from_millis(250);

/// A progress line being shown for one check.
pub struct Progress {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl Progress {
    /// Whether progress is shown: the human format, not quiet, stderr a
    /// terminal.
    pub fn wanted(human: bool, quiet: bool) -> bool {
        human && !quiet && std::io::stderr().is_terminal()
    }

    /// Starts showing the progress of the check of `file`, whose limits
    /// are said by `limits` (`10,000,000 states, 30s`).
    pub fn start(file: String, limits: String) -> Progress {
        genom_model::limits::report_explored(0);
        let stop = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&stop);
        let thread = std::thread::spawn(move || show(&file, &limits, &flag));
        Progress {
            stop,
            thread: Some(thread),
        }
    }

    /// Stops and erases the line.
    pub fn finish(mut self) {
        self.end();
    }

    fn end(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.end();
    }
}

/// The thread: waits [`QUIET_FOR`], then rewrites the line every
/// [`EVERY`] until `stop`, and erases it.
fn show(file: &str, limits: &str, stop: &AtomicBool) {
    let started = Instant::now();
    let mut next = started + QUIET_FOR;
    let mut shown = false;
    while !stop.load(Ordering::Relaxed) {
        std::thread::sleep(Duration::from_millis(50));
        let now = Instant::now();
        if now < next {
            continue;
        }
        next = now + EVERY;
        let line = format!(
            "genom-check: checking {}: {} states, {:.0} s (stops at {limits})",
            genom_render::escaped(file),
            genom_model::limits::grouped(genom_model::limits::explored()),
            (now - started).as_secs_f64()
        );
        let mut err = std::io::stderr().lock();
        let _ = write!(err, "\r\x1b[2K{line}");
        let _ = err.flush();
        shown = true;
    }
    if shown {
        let mut err = std::io::stderr().lock();
        let _ = write!(err, "\r\x1b[2K");
        let _ = err.flush();
    }
}
