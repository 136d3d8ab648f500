//! Where a render starts: from nothing, at the first iteration of its shard (`--shard I/K`
//! with `-n N`), or from a saved image or checkpoint (`--resume FILE.exr`), refusing a file
//! of another scene or settings with a message naming the difference.

use crate::provenance::{Provenance, Shard};
use crate::state_file;
use anyhow::{bail, Result};
use ppm_core::integrator::Snapshot;
use std::path::Path;

/// The starting state of a render and how many iterations it still has to do.
pub struct Start {
    pub snapshot: Snapshot,
    /// Iterations to render in this run (None: until the time limit, or the default count).
    pub iterations: Option<u64>,
    /// The provenance to record: this render's, with the shard and the earlier runs' time
    /// and threads.
    pub provenance: Provenance,
}

/// What the command line asked: `-n`, `--shard`, `--resume`.
pub struct StartArgs<'a> {
    pub iterations: Option<u64>,
    pub shard: Option<(u64, u64)>,
    pub resume: Option<&'a Path>,
}

/// Decides where the render of `provenance` (this command's scene and settings) starts.
///
/// - neither flag: at iteration 0, for `-n` iterations;
/// - `--shard I/K -n N`: at the first iteration of slice I of K of the N iterations
///   ([`Shard::range`]), for the length of that slice;
/// - `--resume FILE`: where FILE stopped, for `-n` more iterations; with `--shard` too, FILE
///   must be a (partial) render of that shard, which is then finished.
pub fn plan(args: &StartArgs, provenance: &Provenance) -> Result<Start> {
    let (width, height) = (provenance.width, provenance.height);
    let shard = match args.shard {
        None => None,
        Some((index, count)) => {
            let Some(total) = args.iterations else {
                usage_bail!("--shard {index}/{count} needs -n, the iterations of the whole render");
            };
            if count > total {
                usage_bail!("--shard {index}/{count}: {count} shards of {total} iterations (-n) would leave some empty");
            }
            Some(Shard {
                index,
                count,
                total,
            })
        }
    };
    let mut provenance = provenance.clone();
    provenance.shard = shard;
    let Some(path) = args.resume else {
        let (first, end) = shard.map_or((0, 0), |s| s.range());
        return Ok(Start {
            snapshot: Snapshot::starting_at(width, height, first),
            iterations: if shard.is_some() {
                Some(end - first)
            } else {
                args.iterations
            },
            provenance,
        });
    };

    let saved = state_file::read(path)?;
    saved.provenance.refuse_crop(path, "resume")?;
    if let Some(difference) = provenance.difference(&saved.provenance) {
        bail!(
            "cannot resume {}: it is not a render of this scene and settings; they differ in \
             {difference} (this render vs the file; leave the flag out to take the file's)",
            path.display()
        );
    }
    let film = &saved.snapshot.film;
    let iterations = match shard {
        None => args.iterations,
        Some(s) => {
            let (first, end) = s.range();
            if film.first_iteration() != first || film.next_iteration() > end {
                bail!(
                    "cannot resume {} as shard {s}: it holds iterations {}..{}, the shard is \
                     iterations {first}..{end}",
                    path.display(),
                    film.first_iteration(),
                    film.next_iteration()
                );
            }
            Some(end - film.next_iteration())
        }
    };
    provenance.render_seconds = saved.provenance.render_seconds;
    // The runs that contributed iterations: this one only if it has any left to render.
    provenance.threads = if iterations == Some(0) {
        saved.provenance.threads.clone()
    } else {
        format!("{},{}", saved.provenance.threads, provenance.threads)
    };
    Ok(Start {
        snapshot: saved.snapshot,
        iterations,
        provenance,
    })
}
