//! Writing files so that a failure never leaves a truncated one where a good one was.
//!
//! A result file is written in full to a temporary name in the target folder, synced (fsync)
//! and renamed over its target ([`PendingFile`], [`write_atomic`]): a rename within a file
//! system is atomic, so an interrupted or failed write leaves the old file as it was. Before a
//! long render the target folders are probed ([`check_writable`]), so the render never ends in
//! an unwritable path. Logs that grow during a render are plain files flushed line by line
//! ([`create_log`], [`log_line`]).

use anyhow::{bail, Context, Result};
use std::fs::{self, File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// The folder a file path lives in (`.` for a bare file name).
fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// A fresh name for a temporary file next to `path` (hidden, unique within this process):
/// `.<file name>.<tag>-<pid>-<counter>`. [`crate::guard`] recognises exactly this pattern.
pub(crate) fn temp_sibling(path: &Path, tag: &str) -> PathBuf {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    parent_dir(path).join(format!(".{name}.{tag}-{}-{n}", std::process::id()))
}

/// Fails unless a file can be created at `path`: its folder must exist and accept a new file
/// (tried by creating and deleting a temporary one), and `path` must not be a folder.
/// Called before rendering so that a long render never ends in an unwritable path.
pub fn check_writable(path: &Path) -> Result<()> {
    let dir = parent_dir(path);
    if !dir.is_dir() {
        bail!(
            "cannot write {}: folder {} does not exist",
            path.display(),
            dir.display()
        );
    }
    if path.is_dir() {
        bail!("cannot write {}: it is a folder", path.display());
    }
    let probe = temp_sibling(path, "write-test");
    OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .with_context(|| {
            format!(
                "cannot write {}: folder {} is not writable",
                path.display(),
                dir.display()
            )
        })?;
    let _ = fs::remove_file(&probe);
    Ok(())
}

/// [`check_writable`] after creating `path`'s folder if it does not exist, as `ppm converge
/// --out` does: `-o refs/cornell.exr` needs no `mkdir refs` first.
pub fn create_folder_and_check(path: &Path) -> Result<()> {
    let dir = parent_dir(path);
    if !dir.is_dir() {
        fs::create_dir_all(dir).with_context(|| {
            format!(
                "cannot write {}: cannot create folder {}",
                path.display(),
                dir.display()
            )
        })?;
    }
    check_writable(path)
}

/// A file written in full (and synced) under a temporary name next to its target, waiting to
/// be renamed over it by [`PendingFile::commit`]. Dropped uncommitted, it removes itself.
pub struct PendingFile {
    temp: PathBuf,
    path: PathBuf,
    committed: bool,
}

impl PendingFile {
    /// Writes `path`'s future content to a temporary file: `write` fills it, then it is
    /// synced. On any error the temporary file is removed; `path` is never touched.
    pub fn write(
        path: &Path,
        write: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
    ) -> Result<PendingFile> {
        let pending = PendingFile {
            temp: temp_sibling(path, "tmp"),
            path: path.to_path_buf(),
            committed: false,
        };
        (|| -> Result<()> {
            let file = OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&pending.temp)?;
            let mut writer = BufWriter::new(file);
            write(&mut writer)?;
            let file = writer.into_inner().map_err(|e| e.into_error())?;
            file.sync_all()?;
            Ok(())
        })()
        .with_context(|| format!("cannot write {}", path.display()))?;
        Ok(pending)
    }

    /// Renames the temporary file over the target (atomic within a file system).
    pub fn commit(mut self) -> Result<()> {
        fs::rename(&self.temp, &self.path)
            .with_context(|| format!("cannot write {}", self.path.display()))?;
        self.committed = true;
        Ok(())
    }
}

impl Drop for PendingFile {
    fn drop(&mut self) {
        if !self.committed {
            let _ = fs::remove_file(&self.temp);
        }
    }
}

/// Writes a file atomically: `write` fills a temporary file in the same folder, which is then
/// synced and renamed over `path`. On any error the temporary file is removed and `path` keeps
/// its old content.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<()> {
    PendingFile::write(path, write)?.commit()
}

/// Creates (truncating) a plain file for a log that grows during the render.
pub fn create_log(path: &Path) -> Result<BufWriter<File>> {
    let file = File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    Ok(BufWriter::new(file))
}

/// Writes one line to a log and flushes it, so a log is useful even if the run stops early.
pub fn log_line(log: &mut BufWriter<File>, path: &Path, line: &str) -> Result<()> {
    writeln!(log, "{line}")
        .and_then(|_| log.flush())
        .with_context(|| format!("cannot write {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::{test_image, write_exr, write_png};

    #[test]
    fn atomic_write_replaces_and_leaves_no_temp_files() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.exr");
        write_exr(&path, &test_image()).unwrap();
        write_png(&dir.path().join("out.png"), &test_image()).unwrap();
        // A failing writer must keep the old file and remove its temporary file.
        let before = fs::read(&path).unwrap();
        let err = write_atomic(&path, |w| {
            w.write_all(b"partial")?;
            bail!("disk full")
        })
        .unwrap_err();
        assert!(format!("{err:#}").contains("out.exr"), "{err:#}");
        assert_eq!(fs::read(&path).unwrap(), before);
        let mut names: Vec<String> = fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, ["out.exr", "out.png"]);
    }

    #[test]
    fn writability_check_names_the_folder() {
        let dir = tempfile::tempdir().unwrap();
        check_writable(&dir.path().join("fine.png")).unwrap();
        assert_eq!(
            fs::read_dir(dir.path()).unwrap().count(),
            0,
            "the probe file must be deleted"
        );

        let missing = dir.path().join("no_such_folder").join("x.png");
        let err = check_writable(&missing).unwrap_err().to_string();
        assert!(
            err.contains("no_such_folder") && err.contains("does not exist"),
            "{err}"
        );

        // A regular file used as a folder: not writable even for root.
        let file = dir.path().join("plain_file");
        fs::write(&file, b"x").unwrap();
        let err = check_writable(&file.join("x.png")).unwrap_err().to_string();
        assert!(err.contains("plain_file"), "{err}");

        let err = check_writable(dir.path()).unwrap_err().to_string();
        assert!(err.contains("is a folder"), "{err}");
    }

    #[cfg(unix)]
    #[test]
    fn writability_check_fails_on_a_read_only_folder() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let ro = dir.path().join("read_only");
        fs::create_dir(&ro).unwrap();
        fs::set_permissions(&ro, fs::Permissions::from_mode(0o555)).unwrap();
        // Root ignores permissions; the check can only be asked to fail where writing fails.
        let writing_fails = File::create(ro.join("probe")).is_err();
        let result = check_writable(&ro.join("x.png"));
        fs::set_permissions(&ro, fs::Permissions::from_mode(0o755)).unwrap();
        if writing_fails {
            let err = result.unwrap_err().to_string();
            assert!(
                err.contains("read_only") && err.contains("not writable"),
                "{err}"
            );
        } else {
            result.unwrap();
        }
    }
}
