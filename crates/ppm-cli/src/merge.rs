//! `ppm merge PARTS... -o OUT`: joins the EXRs of slices of one render (shards, or a render
//! and its resumed continuations) into the image of the whole render, bit for bit.
//!
//! The film sums are exact integers (see `ppm_core::film`), so adding the parts' sums in any
//! order gives the sums of one uninterrupted render; the parts must be renders of the same
//! scene content and settings (every value of [`Provenance::identity`]), and their iteration
//! ranges must tile 0..N: no overlap, no gap, starting at 0, and ending at N when the parts
//! are shards of an N-iteration render.

use crate::args::MergeArgs;
use crate::output;
use crate::provenance::Provenance;
use crate::state_file::{self, SavedRender};
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// Runs `ppm merge`.
pub fn run(args: &MergeArgs) -> Result<()> {
    let paths = output::output_paths(Some(&args.output), Path::new("merged"))?;
    let inputs: Vec<(&str, &Path)> = args.parts.iter().map(|p| ("part", p.as_path())).collect();
    crate::guard::refuse_overwriting_inputs(&paths, &inputs)?;
    output::create_folder_and_check(&paths.png)?;
    output::create_folder_and_check(&paths.exr)?;
    let mut parts = Vec::with_capacity(args.parts.len());
    for path in &args.parts {
        let part = state_file::read(path)?;
        part.provenance.refuse_crop(path, "merge")?;
        parts.push((path.clone(), part));
    }
    let (snapshot, provenance) = merge(parts)?;
    state_file::write_image_and_state(&paths, &snapshot.film.image(), &snapshot, &provenance)?;
    status!(
        "merged {} parts: iterations {}..{} of {}, wrote {} and {}",
        args.parts.len(),
        snapshot.film.first_iteration(),
        snapshot.film.next_iteration(),
        provenance.scene,
        paths.png.display(),
        paths.exr.display()
    );
    Ok(())
}

/// Checks the parts are slices of one render and joins them, in iteration order.
pub fn merge(
    mut parts: Vec<(PathBuf, SavedRender)>,
) -> Result<(ppm_core::integrator::Snapshot, Provenance)> {
    let Some((first_path, first)) = parts.first() else {
        bail!("no parts to merge");
    };
    for (path, part) in &parts[1..] {
        if let Some(difference) = first.provenance.difference(&part.provenance) {
            bail!(
                "{} and {} are not parts of one render: they differ in {difference}",
                first_path.display(),
                path.display()
            );
        }
    }
    parts.sort_by_key(|(_, p)| {
        (
            p.snapshot.film.first_iteration(),
            p.snapshot.film.next_iteration(),
        )
    });
    let range = |p: &SavedRender| {
        (
            p.snapshot.film.first_iteration(),
            p.snapshot.film.next_iteration(),
        )
    };
    let (path0, part0) = &parts[0];
    let (first0, _) = range(part0);
    if first0 != 0 {
        bail!(
            "iterations 0..{first0} are missing: the earliest part, {}, starts at iteration {first0}",
            path0.display()
        );
    }
    for pair in parts.windows(2) {
        let ((a_path, a), (b_path, b)) = (&pair[0], &pair[1]);
        let ((a_first, a_end), (b_first, b_end)) = (range(a), range(b));
        if b_first < a_end {
            bail!(
                "{} (iterations {a_first}..{a_end}) and {} (iterations {b_first}..{b_end}) overlap",
                a_path.display(),
                b_path.display()
            );
        }
        if b_first > a_end {
            bail!(
                "iterations {a_end}..{b_first} are missing: {} ends at {a_end} and {} starts at {b_first}",
                a_path.display(),
                b_path.display()
            );
        }
    }
    // Shards know how many iterations the whole render has: the last one must be there.
    let total = parts
        .iter()
        .filter_map(|(_, p)| p.provenance.shard)
        .map(|s| s.total)
        .max();
    let (last_path, last) = &parts[parts.len() - 1];
    let (_, end) = range(last);
    if let Some(total) = total {
        if end < total {
            bail!(
                "iterations {end}..{total} of the {total}-iteration render are missing \
                 (the latest part, {}, ends at {end})",
                last_path.display()
            );
        }
    }

    let mut parts = parts.into_iter();
    let (_, first) = parts.next().expect("at least one part");
    let mut snapshot = first.snapshot;
    let mut provenance = first.provenance;
    provenance.shard = None;
    for (path, part) in parts {
        snapshot
            .append(&part.snapshot)
            .with_context(|| format!("cannot merge {}", path.display()))?;
        provenance.render_seconds += part.provenance.render_seconds;
        provenance.threads = format!("{},{}", provenance.threads, part.provenance.threads);
    }
    Ok((snapshot, provenance))
}
