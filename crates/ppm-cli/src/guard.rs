//! What a render may touch in its output folder: never one of its own input files, and, of
//! the files it did not write in this run, only its own stale temporary files.

use crate::output::OutputPaths;
use anyhow::{bail, Result};
use std::fs;
use std::io::Read as _;
use std::path::Path;
use std::time::{Duration, SystemTime};

/// A temporary file is stale when its writer is gone: untouched this long (a write renames
/// its temporary file within seconds) and, where the process table can be read, its process
/// no longer runs.
pub const STALE_AGE: Duration = Duration::from_secs(10 * 60);

/// Refuses a render whose PNG or EXR would replace one of its inputs: `ppm scene.png`, where
/// `scene.png` is in fact the YAML scene, would otherwise overwrite the scene with its render.
pub fn refuse_overwriting_inputs(paths: &OutputPaths, inputs: &[(&str, &Path)]) -> Result<()> {
    refuse_replacing(
        &[("output", &paths.png), ("output", &paths.exr)],
        inputs,
        "ppm would overwrite its own input; choose another output name with -o",
    )
}

/// Refuses a render whose other outputs (`--error-log`, the `--aov` images) would replace an
/// input (the scene, `--reference`, `--resume`'s file), one of the render's images or each
/// other. Only the image may replace the file it resumes from (atomically, once the render
/// is done); a log or an extra image written there would destroy it.
pub fn refuse_replacing_by_extras(
    extras: &[(&str, &Path)],
    inputs: &[(&str, &Path)],
    paths: &OutputPaths,
) -> Result<()> {
    let mut taken: Vec<(&str, &Path)> = inputs.to_vec();
    taken.push(("output", &paths.png));
    taken.push(("output", &paths.exr));
    for (i, extra) in extras.iter().enumerate() {
        let remedy = "ppm would overwrite it; choose another name";
        refuse_replacing(std::slice::from_ref(extra), &taken, remedy)?;
        refuse_replacing(std::slice::from_ref(extra), &extras[..i], remedy)?;
    }
    Ok(())
}

/// Refuses an `--error-log` path that holds a file other than an error log (whose first line
/// is `header`): the log is rewritten from its first line, so a mesh, a scene or an image
/// given there by mistake would be lost. An empty file or an earlier log may be replaced.
pub fn refuse_replacing_non_log(path: &Path, header: &str) -> Result<()> {
    use std::io::{BufRead, BufReader};
    let Ok(file) = fs::File::open(path) else {
        return Ok(());
    };
    let mut first = String::new();
    // Only the first line is read (a binary file gives up at once or at its first bytes).
    let _ = BufReader::new(file.take(4096)).read_line(&mut first);
    if first.is_empty() || first.trim_end() == header {
        return Ok(());
    }
    bail!(
        "--error-log {} already exists and is not an error log (its first line is not `{header}`): \
         ppm would overwrite it; give another file name or remove the file",
        path.display()
    )
}

/// Refuses when an output of `outputs` names the file (or the path) of one of `taken`, with
/// `remedy` in the message.
fn refuse_replacing(
    outputs: &[(&str, &Path)],
    taken: &[(&str, &Path)],
    remedy: &str,
) -> Result<()> {
    for (role, output) in outputs {
        for (what, input) in taken {
            if same_file(output, input) || same_path(output, input) {
                bail!(
                    "the {role} {} is the {what} {}: {remedy}",
                    output.display(),
                    input.display()
                );
            }
        }
    }
    Ok(())
}

/// True if the two paths name the same place: the same file name in the same folder (after
/// links), whether the file exists or not.
fn same_path(a: &Path, b: &Path) -> bool {
    let place = |p: &Path| {
        let folder = match p.parent() {
            Some(f) if !f.as_os_str().is_empty() => f,
            _ => Path::new("."),
        };
        Some((fs::canonicalize(folder).ok()?, p.file_name()?.to_owned()))
    };
    matches!((place(a), place(b)), (Some(x), Some(y)) if x == y)
}

/// True if both paths exist and name the same file (after links).
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (fs::metadata(a), fs::metadata(b)) {
            (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        match (fs::canonicalize(a), fs::canonicalize(b)) {
            (Ok(x), Ok(y)) => x == y,
            _ => false,
        }
    }
}

/// Removes the stale temporary files of `paths` left by a killed run (`kill -9`, a power
/// cut): only names of the exact pattern `output::durable::temp_sibling` gives these two files,
/// `.<name>.tmp-<pid>-<n>` or `.<name>.write-test-<pid>-<n>`, and only stale ones (see
/// [`STALE_AGE`]). Returns the files removed; a file that cannot be removed is left alone.
pub fn clean_stale_temporaries(paths: &OutputPaths) -> Vec<std::path::PathBuf> {
    let mut removed = Vec::new();
    for target in [&paths.png, &paths.exr] {
        let Some(name) = target.file_name().map(|n| n.to_string_lossy().into_owned()) else {
            continue;
        };
        let dir = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        let Ok(entries) = fs::read_dir(dir) else {
            continue;
        };
        for entry in entries.flatten() {
            let file_name = entry.file_name().to_string_lossy().into_owned();
            let Some(pid) = temporary_of(&file_name, &name) else {
                continue;
            };
            let path = entry.path();
            if is_stale(&path, pid) && fs::remove_file(&path).is_ok() {
                removed.push(path);
            }
        }
    }
    removed
}

/// The writer's process id if `file_name` is a temporary file of `target`.
fn temporary_of(file_name: &str, target: &str) -> Option<u32> {
    let rest = file_name.strip_prefix('.')?.strip_prefix(target)?;
    let rest = rest
        .strip_prefix(".tmp-")
        .or_else(|| rest.strip_prefix(".write-test-"))?;
    let (pid, n) = rest.split_once('-')?;
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    (digits(pid) && digits(n)).then(|| pid.parse().ok())?
}

fn is_stale(path: &Path, pid: u32) -> bool {
    let Ok(meta) = fs::symlink_metadata(path) else {
        return false;
    };
    if !meta.is_file() {
        return false;
    }
    let old = meta
        .modified()
        .ok()
        .and_then(|m| SystemTime::now().duration_since(m).ok())
        .is_some_and(|age| age >= STALE_AGE);
    old && !process_running(pid)
}

/// Whether process `pid` runs on this machine (always assumed where /proc does not exist).
fn process_running(pid: u32) -> bool {
    let proc_root = Path::new("/proc");
    !proc_root.join("self").exists() || proc_root.join(pid.to_string()).exists()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_our_own_pattern_is_a_temporary() {
        assert_eq!(temporary_of(".out.png.tmp-123-4", "out.png"), Some(123));
        assert_eq!(temporary_of(".out.exr.write-test-9-0", "out.exr"), Some(9));
        for other in [
            ".out.png.tmp-123",
            ".out.png.tmp-12a-4",
            ".out.png.tmp--4",
            "out.png.tmp-1-2",
            ".other.png.tmp-1-2",
            ".out.png.bak-1-2",
            ".out.png",
        ] {
            assert_eq!(temporary_of(other, "out.png"), None, "{other}");
        }
    }
}
