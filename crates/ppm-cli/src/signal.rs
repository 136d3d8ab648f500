//! Ctrl-C handling: the first interrupt asks the render to stop after the current iteration
//! (the image of all finished iterations is still written); the second exits at once.

use anyhow::{Context, Result};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;

/// Exit status after an interrupted render (128 + SIGINT, the shell convention).
pub const EXIT_INTERRUPTED: u8 = 130;

/// A shared "please stop" flag, set by Ctrl-C (or by a test).
#[derive(Clone, Debug, Default)]
pub struct Interrupt {
    count: Arc<AtomicU32>,
}

impl Interrupt {
    /// A flag that nothing has raised yet (and no handler installed).
    pub fn new() -> Self {
        Self::default()
    }

    /// Installs the process's Ctrl-C handler (once per process).
    pub fn install_handler(&self) -> Result<()> {
        let this = self.clone();
        ctrlc::set_handler(move || {
            if this.request() >= 2 {
                status!("\nppm: interrupted twice, exiting now");
                std::process::exit(EXIT_INTERRUPTED.into());
            }
            status!(
                "\nppm: interrupted: finishing the current iteration, then writing the image \
                 (Ctrl-C again to quit at once)"
            );
        })
        .context("cannot install the Ctrl-C handler")
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
