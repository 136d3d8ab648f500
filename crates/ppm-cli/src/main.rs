//! `ppm`: renders scene files with progressive photon mapping or path tracing, compares images
//! and measures convergence. See `ppm --help`.

#[macro_use]
mod console;
#[macro_use]
mod usage;
mod args;
mod bare_obj;
mod black_image;
mod camera_matrices;
mod compare;
mod converge;
mod convert;
mod crop;
mod display;
mod error_log;
mod guard;
mod info;
mod memory;
mod merge;
mod oom;
mod output;
mod plot;
mod process_limits;
mod progress;
mod provenance;
mod render;
mod render_loop;
mod report;
mod rescue;
mod resume;
mod resume_flags;
mod scene_search;
mod setup;
mod signal;
mod state_attributes;
mod state_check;
mod state_file;

use anyhow::Result;
use args::{Cli, Command};
use clap::Parser;
use render::Outcome;
use signal::{Interrupt, EXIT_INTERRUPTED};
use std::process::ExitCode;

/// A failed allocation is an error with exit status 1, never an abort (see [`oom`]).
#[global_allocator]
static ALLOCATOR: oom::ReportingAllocator = oom::ReportingAllocator;

fn main() -> ExitCode {
    // Usage errors exit with status 2 (clap's convention, and ours for the usage errors
    // found after parsing), --help and --version with 0, other errors with 1.
    let cli = Cli::parse();
    match run(cli) {
        Ok(Outcome::Finished) => ExitCode::SUCCESS,
        Ok(Outcome::Interrupted) => ExitCode::from(EXIT_INTERRUPTED),
        Err(e) => {
            status!("error: {}", error_message(&e));
            if usage::is_usage(&e) {
                ExitCode::from(2)
            } else {
                ExitCode::FAILURE
            }
        }
    }
}

/// The error and its causes joined by ": ", as `{e:#}` prints them, but without a cause
/// whose text the message before it already ends with: a library error that shows its
/// cause in its own message and also returns it as its `source` (`cannot read x.obj: No
/// such file or directory`) would otherwise print the cause twice.
fn error_message(e: &anyhow::Error) -> String {
    let mut message = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if message.is_empty() {
            message = text;
        } else if !message.ends_with(&text) {
            message = format!("{message}: {text}");
        }
    }
    message
}

fn run(cli: Cli) -> Result<Outcome> {
    let interrupt = Interrupt::writing(match cli.command {
        Some(Command::Converge(_)) => signal::CONVERGE_WRITES,
        _ => signal::RENDER_WRITES,
    });
    match cli.command {
        Some(Command::Compare(args)) => compare::run(&args).map(|()| Outcome::Finished),
        Some(Command::Info(args)) => info::run(&args.image).map(|()| Outcome::Finished),
        Some(Command::Merge(args)) => merge::run(&args).map(|()| Outcome::Finished),
        Some(Command::Convert(args)) => convert::run(&args).map(|()| Outcome::Finished),
        Some(Command::Converge(args)) => {
            interrupt.install_handler()?;
            converge::run(&args, &interrupt)
        }
        Some(Command::Render(args)) => {
            interrupt.install_handler()?;
            render::run(&args, &interrupt)
        }
        None => {
            interrupt.install_handler()?;
            render::run(&cli.render, &interrupt)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::error_message;
    use anyhow::Context;

    /// A cause already at the end of the message is not repeated; other causes are joined.
    #[test]
    fn a_cause_shown_by_its_error_is_not_repeated() {
        #[derive(Debug)]
        struct ShowsItsSource {
            source: std::io::Error,
        }
        impl std::fmt::Display for ShowsItsSource {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, "x.obj: cannot read mesh: {}", self.source)
            }
        }
        impl std::error::Error for ShowsItsSource {
            fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
                Some(&self.source)
            }
        }
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "No such file");
        let e = Err::<(), _>(ShowsItsSource { source: io })
            .context("cannot load scene a.yml")
            .unwrap_err();
        assert_eq!(
            error_message(&e),
            "cannot load scene a.yml: x.obj: cannot read mesh: No such file"
        );
        let plain = Err::<(), _>(std::io::Error::other("disk full"))
            .context("writing out.exr")
            .unwrap_err();
        assert_eq!(error_message(&plain), "writing out.exr: disk full");
    }
}
