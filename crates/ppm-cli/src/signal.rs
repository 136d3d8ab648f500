//! Stop requests: Ctrl-C (SIGINT), SIGTERM (sent by `timeout`, systemd, `docker stop` and
//! batch schedulers at a job's time limit), SIGHUP (a closed terminal), SIGUSR1 and SIGUSR2
//! (what Slurm's `--signal` sends ahead of a time limit) and SIGXCPU (a soft CPU-time limit,
//! `ulimit -t`) are all handled alike. The first one stops the render: the iteration in progress is abandoned (its passes
//! poll the flag) and the image of all finished iterations is written, unless none has
//! finished, in which case nothing is written and existing files are left alone. A second
//! one, [`REPEAT_WINDOW`] or more after the first, exits at once without writing. Either way
//! the exit status is [`EXIT_INTERRUPTED`].
//!
//! One stop often arrives twice: coreutils `timeout` signals the child and then its whole
//! process group, which holds the child again, and any supervisor that signals both a
//! process and its group does the same. Signals within [`REPEAT_WINDOW`] of the first are
//! therefore the same request, not an order to quit without writing.
//!
//! A signal the process inherits as ignored stays ignored: `nohup ppm ...` keeps rendering
//! after a hang-up, and so does a render a script starts in the background (`ppm ... &`),
//! which the shell starts with SIGINT ignored. SIGXFSZ (a file larger than `ulimit -f`) is
//! ignored, so that such a write fails as a full disk does, leaving the files before it,
//! instead of killing the process.

use anyhow::{Context, Result};
use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM, SIGUSR1, SIGUSR2, SIGXCPU, SIGXFSZ};
use signal_hook::iterator::Signals;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

/// The signals that stop a render.
pub const STOP_SIGNALS: [i32; 6] = [SIGINT, SIGTERM, SIGHUP, SIGUSR1, SIGUSR2, SIGXCPU];

/// Exit status after an interrupted render, whichever stop signal stopped it:
/// 130 (128 + SIGINT, the shell convention for Ctrl-C). One status for all of them, because
/// scripts test for one "stopped early" status.
pub const EXIT_INTERRUPTED: u8 = 130;

/// What a stopped render writes, as its stop message says.
pub const RENDER_WRITES: &str = "the image of the finished iterations";

/// What a stopped `ppm converge` writes.
pub const CONVERGE_WRITES: &str = "the CSV and plot of the finished runs";

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
    /// What the command writes when stopped, for the message the first signal prints.
    writes: &'static str,
    count: Arc<AtomicU32>,
    /// When the first stop signal arrived.
    first: Arc<OnceLock<Instant>>,
}

impl Interrupt {
    /// A flag that nothing has raised yet (and no handler installed).
    #[cfg(test)]
    pub fn new() -> Self {
        Self::default()
    }

    /// A flag for a command that, stopped, writes `writes` (`the image of the finished
    /// iterations`): the first signal's message says so.
    pub fn writing(writes: &'static str) -> Self {
        Interrupt {
            writes,
            ..Self::default()
        }
    }

    /// What the first stop signal prints.
    pub fn stop_message(&self) -> String {
        let writes = if self.writes.is_empty() {
            "what is finished"
        } else {
            self.writes
        };
        format!(
            "\nppm: interrupted: abandoning the iteration in progress, then writing {writes} \
             (stop again to quit at once)"
        )
    }

    /// Installs the process's handler for the [`STOP_SIGNALS`] it does not inherit as
    /// ignored (once per process), and ignores SIGXFSZ. signal-hook's async-signal-safe
    /// handler only wakes the thread started here (`ppm-signals`), which reacts in ordinary
    /// code, so it may print and exit.
    pub fn install_handler(&self) -> Result<()> {
        let watched: Vec<i32> = STOP_SIGNALS
            .into_iter()
            .filter(|&signal| !inherited_as_ignored(signal))
            .collect();
        ignore_if_default(SIGXFSZ);
        let mut signals =
            Signals::new(&watched).context("cannot install the stop-signal handler")?;
        let this = self.clone();
        std::thread::Builder::new()
            .name("ppm-signals".into())
            .spawn(move || {
                for _ in signals.forever() {
                    this.on_signal();
                }
            })
            .context("cannot start the stop-signal thread")?;
        Ok(())
    }

    /// What a stop signal does: raise the flag and say so, or quit on a late second one.
    fn on_signal(&self) {
        match self.signal_at(Instant::now()) {
            StopRequest::Stop => status!("{}", self.stop_message()),
            StopRequest::Repeat => status!(
                "ppm: the stop signal came again within {} s: still stopping and writing",
                REPEAT_WINDOW.as_secs()
            ),
            StopRequest::Quit => {
                status!("\nppm: interrupted twice, exiting now without writing");
                std::process::exit(EXIT_INTERRUPTED.into());
            }
        }
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

/// The current disposition of `signal`, read without changing it.
fn disposition(signal: i32) -> Option<libc::sighandler_t> {
    // SAFETY: sigaction with a null new action only reads the current one into `old`, a
    // zeroed (valid) struct of the right type.
    unsafe {
        let mut old: libc::sigaction = std::mem::zeroed();
        (libc::sigaction(signal, std::ptr::null(), &mut old) == 0).then_some(old.sa_sigaction)
    }
}

/// True if the process was started with `signal` ignored (`nohup`, a background job).
fn inherited_as_ignored(signal: i32) -> bool {
    disposition(signal) == Some(libc::SIG_IGN)
}

/// Ignores `signal` unless something has set a handler for it.
fn ignore_if_default(signal: i32) {
    if disposition(signal) == Some(libc::SIG_DFL) {
        // SAFETY: setting a signal to SIG_IGN installs no code; it cannot break invariants.
        unsafe { libc::signal(signal, libc::SIG_IGN) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A render's stop message speaks of its image, converge's of its CSV and plot.
    #[test]
    fn the_stop_message_names_what_the_command_writes() {
        let render = Interrupt::writing(RENDER_WRITES).stop_message();
        assert!(
            render.contains("the image of the finished iterations") && !render.contains("converge"),
            "{render}"
        );
        let converge = Interrupt::writing(CONVERGE_WRITES).stop_message();
        assert!(converge.contains("CSV and plot"), "{converge}");
    }

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
