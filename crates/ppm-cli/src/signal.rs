//! Stop requests: Ctrl-C (SIGINT), SIGTERM (sent by `timeout`, systemd, `docker stop` and
//! batch schedulers at a job's time limit) and SIGHUP (a closed terminal) are all handled
//! alike. The first one stops the render: the iteration in progress is abandoned (its passes
//! poll the flag) and the image of all finished iterations is written, unless none has
//! finished, in which case nothing is written and existing files are left alone. The second
//! exits at once without writing. Either way the exit status is [`EXIT_INTERRUPTED`].

use anyhow::{Context, Result};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;

/// Exit status after an interrupted render, whichever of SIGINT, SIGTERM or SIGHUP stopped it:
/// 130 (128 + SIGINT, the shell convention for Ctrl-C). One status for all three, because the
/// handler cannot tell them apart and because scripts test for one "stopped early" status.
pub const EXIT_INTERRUPTED: u8 = 130;

/// A shared "please stop" flag, set by a stop signal (or by a test).
#[derive(Clone, Debug, Default)]
pub struct Interrupt {
    count: Arc<AtomicU32>,
}

impl Interrupt {
    /// A flag that nothing has raised yet (and no handler installed).
    pub fn new() -> Self {
        Self::default()
    }

    /// Installs the process's handler for SIGINT, SIGTERM and SIGHUP (once per process).
    pub fn install_handler(&self) -> Result<()> {
        let this = self.clone();
        ctrlc::set_handler(move || {
            if this.request() >= 2 {
                status!("\nppm: interrupted twice, exiting now without writing");
                std::process::exit(EXIT_INTERRUPTED.into());
            }
            status!(
                "\nppm: interrupted: abandoning the iteration in progress, then writing the \
                 image of the finished ones (stop again to quit at once)"
            );
        })
        .context("cannot install the stop-signal handler")
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
}
