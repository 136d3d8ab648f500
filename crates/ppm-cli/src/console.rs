//! Text for the user on stdout and stderr that survives a closed pipe. Rust ignores SIGPIPE,
//! so `println!` and `eprintln!` panic when the reader has gone (`ppm scene 2>&1 | head -1`).

use anyhow::{Context, Result};
use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};

/// Set by `-q/--quiet`: [`info!`] lines are dropped (warnings and errors still print).
static QUIET: AtomicBool = AtomicBool::new(false);

/// Silences [`info!`] lines and the progress bar for the rest of the process.
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// True under `-q/--quiet`.
pub fn quiet() -> bool {
    QUIET.load(Ordering::Relaxed)
}

/// `eprintln!` that never panics: with stderr closed a status line has nowhere to go, and the
/// render must go on and be written regardless.
macro_rules! status {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

/// A [`status!`] line that `-q/--quiet` silences: summaries and progress reports, not
/// warnings or errors.
macro_rules! info {
    ($($arg:tt)*) => {{
        if !$crate::console::quiet() {
            status!($($arg)*);
        }
    }};
}

/// Prints `text` to stdout. A closed pipe (`ppm compare A B | head -1`) is the reader's choice,
/// not an error: the rest is dropped quietly.
pub fn print_stdout(text: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        result => result.context("cannot write to stdout"),
    }
}
