//! Stop requests: Ctrl-C (SIGINT), SIGTERM (sent by `timeout`, systemd, `docker stop` and
//! batch schedulers at a job's time limit) and SIGHUP (a closed terminal) are all handled
//! alike. The first one stops the render: the iteration in progress is abandoned (its passes
//! poll the flag) and the image of all finished iterations is written, unless none has
//! finished, in which case nothing is written and existing files are left alone. A second
//! one, [`REPEAT_WINDOW`] or more after the first, exits at once without writing. Either way
//! the exit status is [`EXIT_INTERRUPTED`].
//!
//! One stop often arrives twice: coreutils `timeout` signals the child and then its whole
//! process group, which holds the child again, and any supervisor that signals both a
//! process and its group does the same. Signals within [`REPEAT_WINDOW`] of the first are
//! therefore the same request, not an order to quit without writing.

use anyhow::{Context, Result};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

/// Exit status after an interrupted render, whichever of SIGINT, SIGTERM or SIGHUP stopped it:
/// 130 (128 + SIGINT, the shell convention for Ctrl-C). One status for all three, because the
/// handler cannot tell them apart and because scripts test for one "stopped early" status.
pub const EXIT_INTERRUPTED: u8 = 130;

/// Stop signals within this time of the first one repeat it: they do not quit at once.
/// Long enough for a signal delivered twice by a process-group kill, short enough that a
/// second Ctrl-C pressed on purpose still quits.
pub const REPEAT_WINDOW: Duration = Duration::from_secs(1);

/// What one stop signal asks for, given the ones before it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopRequest {
    /// The first: stop after abandoning the iteration in progress, writing what finished.
    Stop,
    /// Within [`REPEAT_WINDOW`] of the first: the same stop, delivered again.
    Repeat,
    /// Later than that: quit at once without writing.
    Quit,
}

/// A shared "please stop" flag, set by a stop signal (or by a test).
#[derive(Clone, Debug, Default)]
pub struct Interrupt {
    count: Arc<AtomicU32>,
    /// When the first stop signal arrived.
    first: Arc<OnceLock<Instant>>,
}

impl Interrupt {
    /// A flag that nothing has raised yet (and no handler installed).
    pub fn new() -> Self {
        Self::default()
    }

    /// Installs the process's handler for SIGINT, SIGTERM and SIGHUP (once per process).
    pub fn install_handler(&self) -> Result<()> {
        let this = self.clone();
        ctrlc::set_handler(move || match this.signal_at(Instant::now()) {
            StopRequest::Stop => status!(
                "\nppm: interrupted: abandoning the iteration in progress, then writing what \
                 the finished ones give (a render's image, converge's CSV and plot; stop again \
                 to quit at once)"
            ),
            StopRequest::Repeat => status!(
                "ppm: the stop signal came again within {} s: still stopping and writing",
                REPEAT_WINDOW.as_secs()
            ),
            StopRequest::Quit => {
                status!("\nppm: interrupted twice, exiting now without writing");
                std::process::exit(EXIT_INTERRUPTED.into());
            }
        })
        .context("cannot install the stop-signal handler")
    }

    /// A stop signal that arrived at `now`: raises the flag and says what it asks for.
    pub fn signal_at(&self, now: Instant) -> StopRequest {
        let first = *self.first.get_or_init(|| now);
        if self.request() == 1 {
            StopRequest::Stop
        } else if now.saturating_duration_since(first) < REPEAT_WINDOW {
            StopRequest::Repeat
        } else {
            StopRequest::Quit
        }
    }

    /// Raises the flag; returns how many times it has been raised.
    pub fn request(&self) -> u32 {
        self.count.fetch_add(1, Ordering::SeqCst) + 1
    }

    /// True once an interrupt arrived.
    pub fn requested(&self) -> bool {
        self.count.load(Ordering::SeqCst) > 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flag_is_shared_between_clones() {
        let a = Interrupt::new();
        let b = a.clone();
        assert!(!a.requested());
        assert_eq!(b.request(), 1);
        assert!(a.requested());
        assert_eq!(a.request(), 2);
    }

    /// A signal delivered twice (a process-group kill) is one stop; a second signal later
    /// than the window quits, as does every one after it.
    #[test]
    fn signals_within_the_window_repeat_the_first() {
        let t0 = Instant::now();
        let stop = Interrupt::new();
        assert_eq!(stop.signal_at(t0), StopRequest::Stop);
        assert!(stop.requested());
        assert_eq!(stop.signal_at(t0), StopRequest::Repeat);
        let just_inside = t0 + REPEAT_WINDOW - Duration::from_millis(1);
        assert_eq!(stop.signal_at(just_inside), StopRequest::Repeat);
        assert_eq!(stop.signal_at(t0 + REPEAT_WINDOW), StopRequest::Quit);
        assert_eq!(stop.signal_at(t0 + 10 * REPEAT_WINDOW), StopRequest::Quit);
    }
}
