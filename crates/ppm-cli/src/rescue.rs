//! The last resort of a render whose image cannot be written where it was asked for (a full
//! disk, a quota, a folder removed or made read-only during the render): the same PNG and EXR,
//! render state included, written to a folder on another file system, so that hours of
//! rendering are not lost to a write error at the end.
//!
//! The rescue folders are tried in order: `$PPM_RESCUE_DIR` if set, the system's temporary
//! folder (`$TMPDIR`, else `/tmp`), then `$HOME`; a folder that is the output's own is skipped
//! (it has just failed). The files are named `<stem>.rescued-<pid>.png` and `.exr`, with `-2`,
//! `-3`... added when such a file exists already (a container reuses its process ids), so no
//! rescue ever replaces another. The render still ends
//! with an error (the files asked for were not written); the message says where the image
//! went, and the rescued EXR continues with `--resume` like any other.

use crate::output::OutputPaths;
use crate::provenance::Provenance;
use crate::state_file;
use anyhow::Result;
use ppm_core::film::Image;
use ppm_core::integrator::Snapshot;
use std::path::{Path, PathBuf};

/// Writes the render's PNG and EXR to `paths`; if that fails, to the first rescue folder that
/// takes them. The error of a failed write names the rescued files, or says that no rescue
/// folder could take them and why.
pub fn write_or_rescue(
    paths: &OutputPaths,
    image: &Image,
    snapshot: &Snapshot,
    provenance: &Provenance,
) -> Result<()> {
    let Err(error) = state_file::write_image_and_state(paths, image, snapshot, provenance) else {
        return Ok(());
    };
    let mut failures = Vec::new();
    for folder in rescue_folders(paths) {
        let rescued = rescue_paths(paths, &folder, |p| p.exists());
        match state_file::write_image_and_state(&rescued, image, snapshot, provenance) {
            Ok(()) => {
                return Err(error.context(format!(
                    "the render is safe in {} and {} (continue it with --resume {})",
                    rescued.png.display(),
                    rescued.exr.display(),
                    rescued.exr.display()
                )))
            }
            Err(e) => failures.push(format!("{}: {e:#}", folder.display())),
        }
    }
    let tried = if failures.is_empty() {
        "every rescue folder ($PPM_RESCUE_DIR, $TMPDIR or /tmp, $HOME) is unset or the \
         output's own"
            .to_string()
    } else {
        format!("no rescue folder took it either ({})", failures.join("; "))
    };
    Err(error.context(format!("the render is lost: {tried}")))
}

/// The folders a failed write tries, in order, without repeats and without the output's own.
fn rescue_folders(paths: &OutputPaths) -> Vec<PathBuf> {
    let own = folder_of(&paths.exr);
    let set = |name| std::env::var_os(name).filter(|v| !v.is_empty());
    let candidates = [
        set("PPM_RESCUE_DIR").map(PathBuf::from),
        Some(set("TMPDIR").map_or_else(|| PathBuf::from("/tmp"), PathBuf::from)),
        set("HOME").map(PathBuf::from),
    ];
    // (folder as given, its canonical form for the comparisons)
    let mut folders: Vec<(PathBuf, PathBuf)> = Vec::new();
    for folder in candidates.into_iter().flatten() {
        let canonical = folder.canonicalize().unwrap_or_else(|_| folder.clone());
        let seen = folders.iter().any(|(_, c)| *c == canonical);
        if !seen && own.as_ref() != Some(&canonical) {
            folders.push((folder, canonical));
        }
    }
    folders.into_iter().map(|(folder, _)| folder).collect()
}

/// The output's folder, canonical (`None` if it cannot be resolved).
fn folder_of(path: &Path) -> Option<PathBuf> {
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty());
    parent.unwrap_or(Path::new(".")).canonicalize().ok()
}

/// `<folder>/<stem>.rescued-<pid>.png` and `.exr`, `<stem>` the output's file name without
/// `.exr`; `.rescued-<pid>-2`, `-3`... while either file `exists`.
fn rescue_paths(paths: &OutputPaths, folder: &Path, exists: impl Fn(&Path) -> bool) -> OutputPaths {
    let stem = paths
        .exr
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "render".to_string());
    let base = format!("{stem}.rescued-{}", std::process::id());
    (1u32..)
        .map(|n| {
            let name = if n == 1 {
                base.clone()
            } else {
                format!("{base}-{n}")
            };
            OutputPaths {
                png: folder.join(format!("{name}.png")),
                exr: folder.join(format!("{name}.exr")),
            }
        })
        .find(|p| !exists(&p.png) && !exists(&p.exr))
        .expect("some name is free")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rescue_files_keep_the_stem_and_add_the_process() {
        let paths = OutputPaths {
            png: PathBuf::from("out/shot.0001.png"),
            exr: PathBuf::from("out/shot.0001.exr"),
        };
        let pid = std::process::id();
        let rescued = rescue_paths(&paths, Path::new("/safe"), |_| false);
        assert_eq!(
            rescued.exr,
            PathBuf::from(format!("/safe/shot.0001.rescued-{pid}.exr"))
        );
        assert_eq!(
            rescued.png,
            PathBuf::from(format!("/safe/shot.0001.rescued-{pid}.png"))
        );
        // An earlier rescue of the same name (a reused process id) is never replaced.
        let taken = [
            PathBuf::from(format!("/safe/shot.0001.rescued-{pid}.png")),
            PathBuf::from(format!("/safe/shot.0001.rescued-{pid}-2.exr")),
        ];
        let rescued = rescue_paths(&paths, Path::new("/safe"), |p| taken.iter().any(|t| t == p));
        assert_eq!(
            rescued.exr,
            PathBuf::from(format!("/safe/shot.0001.rescued-{pid}-3.exr"))
        );
    }

    #[test]
    fn the_outputs_own_folder_is_never_a_rescue_folder() {
        let dir = tempfile::tempdir().unwrap();
        let paths = OutputPaths {
            png: std::env::temp_dir().join("a.png"),
            exr: std::env::temp_dir().join("a.exr"),
        };
        let folders = rescue_folders(&paths);
        let tmp = std::env::temp_dir().canonicalize().unwrap();
        assert!(
            folders
                .iter()
                .all(|f| f.canonicalize().ok().as_ref() != Some(&tmp)),
            "{folders:?}"
        );
        let elsewhere = OutputPaths {
            png: dir.path().join("sub/a.png"),
            exr: dir.path().join("sub/a.exr"),
        };
        let folders = rescue_folders(&elsewhere);
        let unique: std::collections::HashSet<_> = folders.iter().collect();
        assert_eq!(unique.len(), folders.len(), "{folders:?}");
    }
}
