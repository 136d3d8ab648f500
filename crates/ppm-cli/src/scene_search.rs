//! Where a scene named on the command line is looked for, so that `ppm cornell_box.yml` works
//! from any folder. A path that exists as given is used as given; otherwise a relative path is
//! looked up, in this order, in
//! 1. `./scenes` (the repository root's scenes, as before),
//! 2. each folder of the `PPM_SCENES` environment variable (separated like `PATH`),
//! 3. the scenes installed beside the binary: `<bin>/scenes`, `<bin>/../share/ppm/scenes`,
//! 4. the scenes/ folder of the source tree the binary was built from (a last resort that
//!    only helps on the machine that built it).

use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// The folders searched for a scene not found as given, in order (see the module docs).
pub fn search_folders(
    ppm_scenes: Option<OsString>,
    executable: Option<PathBuf>,
    source_scenes: &Path,
) -> Vec<PathBuf> {
    let mut folders = vec![PathBuf::from("scenes")];
    if let Some(list) = ppm_scenes {
        folders.extend(std::env::split_paths(&list).filter(|p| !p.as_os_str().is_empty()));
    }
    if let Some(bin) = executable.as_deref().and_then(Path::parent) {
        folders.push(bin.join("scenes"));
        folders.push(bin.join("../share/ppm/scenes"));
    }
    folders.push(source_scenes.to_path_buf());
    folders
}

/// The folders searched by this process: `PPM_SCENES`, this executable's location and the
/// source tree (`CARGO_MANIFEST_DIR` at compile time).
pub fn default_search_folders() -> Vec<PathBuf> {
    search_folders(
        std::env::var_os("PPM_SCENES"),
        std::env::current_exe().ok(),
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes"),
    )
}

/// Every path tried for `arg`, in order: `arg` itself, then (for a relative path) `arg` in
/// each search folder.
pub fn candidates(arg: &Path, folders: &[PathBuf]) -> Vec<PathBuf> {
    let mut paths = vec![arg.to_path_buf()];
    if arg.is_relative() {
        paths.extend(folders.iter().map(|f| f.join(arg)));
    }
    paths
}

/// The first candidate that is a file, if any.
pub fn find(arg: &Path, folders: &[PathBuf]) -> Option<PathBuf> {
    candidates(arg, folders).into_iter().find(|p| p.is_file())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folders_come_in_the_documented_order() {
        let list = std::env::join_paths(["/a", "/b"]).unwrap();
        let folders = search_folders(
            Some(list),
            Some(PathBuf::from("/opt/ppm/bin/ppm")),
            Path::new("/src/scenes"),
        );
        assert_eq!(
            folders,
            [
                PathBuf::from("scenes"),
                PathBuf::from("/a"),
                PathBuf::from("/b"),
                PathBuf::from("/opt/ppm/bin/scenes"),
                PathBuf::from("/opt/ppm/bin/../share/ppm/scenes"),
                PathBuf::from("/src/scenes"),
            ]
        );
        assert_eq!(
            search_folders(None, None, Path::new("/src/scenes")),
            [PathBuf::from("scenes"), PathBuf::from("/src/scenes")]
        );
    }

    #[test]
    fn first_existing_file_wins() {
        let one = tempfile::tempdir().unwrap();
        let two = tempfile::tempdir().unwrap();
        std::fs::write(two.path().join("s.yml"), "").unwrap();
        std::fs::create_dir(one.path().join("s.yml")).unwrap(); // a folder is not a scene
        let folders = [one.path().to_path_buf(), two.path().to_path_buf()];
        assert_eq!(
            find(Path::new("s.yml"), &folders),
            Some(two.path().join("s.yml"))
        );
        std::fs::write(one.path().join("t.yml"), "").unwrap();
        std::fs::write(two.path().join("t.yml"), "").unwrap();
        assert_eq!(
            find(Path::new("t.yml"), &folders),
            Some(one.path().join("t.yml"))
        );
        // An absolute path is only tried as given.
        let absolute = one.path().join("missing.yml");
        assert_eq!(
            candidates(&absolute, &folders),
            std::slice::from_ref(&absolute)
        );
    }
}
