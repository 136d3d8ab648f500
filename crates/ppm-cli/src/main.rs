//! `ppm`: renders scene files with progressive photon mapping or path tracing, compares images
//! and measures convergence. See `ppm --help`.

#[macro_use]
mod console;
mod args;
mod bare_obj;
mod black_image;
mod compare;
mod converge;
mod crop;
mod display;
mod error_log;
mod guard;
mod info;
mod memory;
mod merge;
mod output;
mod plot;
mod progress;
mod provenance;
mod render;
mod report;
mod resume;
mod scene_search;
mod setup;
mod signal;
mod state_file;

use anyhow::Result;
use args::{Cli, Command};
use clap::Parser;
use render::Outcome;
use signal::{Interrupt, EXIT_INTERRUPTED};
use std::process::ExitCode;

fn main() -> ExitCode {
    // Usage errors exit with status 2 (clap's convention), --help and --version with 0.
    let cli = Cli::parse();
    match run(cli) {
        Ok(Outcome::Finished) => ExitCode::SUCCESS,
        Ok(Outcome::Interrupted) => ExitCode::from(EXIT_INTERRUPTED),
        Err(e) => {
            status!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<Outcome> {
    let interrupt = Interrupt::new();
    match cli.command {
        Some(Command::Compare(args)) => compare::run(&args).map(|()| Outcome::Finished),
        Some(Command::Info(args)) => info::run(&args.image).map(|()| Outcome::Finished),
        Some(Command::Merge(args)) => merge::run(&args).map(|()| Outcome::Finished),
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
