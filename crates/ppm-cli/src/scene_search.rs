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

/// A folder searched for scenes and the rule (of the module docs) that searches it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SearchFolder {
    pub path: PathBuf,
    /// The rule in words, as `-v` prints it: `in ./scenes`, `in $PPM_SCENES`.
    pub rule: &'static str,
}

/// What `-v` says of a scene found as given.
pub const AS_GIVEN: &str = "as given";

/// The folders searched for a scene not found as given, in order (see the module docs).
pub fn search_folders(
    ppm_scenes: Option<OsString>,
    executable: Option<PathBuf>,
    source_scenes: &Path,
) -> Vec<SearchFolder> {
    let folder = |path: PathBuf, rule| SearchFolder { path, rule };
    let mut folders = vec![folder(PathBuf::from("scenes"), "in ./scenes")];
    if let Some(list) = ppm_scenes {
        folders.extend(
            std::env::split_paths(&list)
                .filter(|p| !p.as_os_str().is_empty())
                .map(|p| folder(p, "in $PPM_SCENES")),
        );
    }
    if let Some(bin) = executable.as_deref().and_then(Path::parent) {
        folders.push(folder(bin.join("scenes"), "beside the binary"));
        folders.push(folder(
            normalized(&bin.join("../share/ppm/scenes")),
            "in the binary's ../share/ppm/scenes",
        ));
    }
    folders.push(folder(
        normalized(source_scenes),
        "in the scenes/ of the source tree ppm was built from",
    ));
    folders
}

/// `path` without `.` and `dir/..` components (lexically: `/src/crates/cli/../../scenes` is
/// `/src/scenes`), so that messages print the path a user would type.
fn normalized(path: &Path) -> PathBuf {
    use std::path::Component;
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir
                if matches!(out.components().next_back(), Some(Component::Normal(_))) =>
            {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// The folders searched by this process: `PPM_SCENES`, this executable's location and the
/// source tree (`CARGO_MANIFEST_DIR` at compile time).
pub fn default_search_folders() -> Vec<SearchFolder> {
    search_folders(
        std::env::var_os("PPM_SCENES"),
        std::env::current_exe().ok(),
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes"),
    )
}

/// Every path tried for `arg`, in order, with the rule that tries it: `arg` itself, then
/// (for a relative path) `arg` in each search folder.
pub fn candidates(arg: &Path, folders: &[SearchFolder]) -> Vec<(PathBuf, &'static str)> {
    let mut paths = vec![(arg.to_path_buf(), AS_GIVEN)];
    if arg.is_relative() {
        paths.extend(folders.iter().map(|f| (f.path.join(arg), f.rule)));
    }
    paths
}

/// The first candidate that is a file, if any, with the rule that found it.
pub fn find(arg: &Path, folders: &[SearchFolder]) -> Option<(PathBuf, &'static str)> {
    candidates(arg, folders)
        .into_iter()
        .find(|(p, _)| p.is_file())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paths(folders: &[SearchFolder]) -> Vec<PathBuf> {
        folders.iter().map(|f| f.path.clone()).collect()
    }

    #[test]
    fn folders_come_in_the_documented_order() {
        let list = std::env::join_paths(["/a", "/b"]).unwrap();
        let folders = search_folders(
            Some(list),
            Some(PathBuf::from("/opt/ppm/bin/ppm")),
            Path::new("/src/crates/ppm-cli/../../scenes"),
        );
        assert_eq!(
            paths(&folders),
            [
                PathBuf::from("scenes"),
                PathBuf::from("/a"),
                PathBuf::from("/b"),
                PathBuf::from("/opt/ppm/bin/scenes"),
                PathBuf::from("/opt/ppm/share/ppm/scenes"),
                PathBuf::from("/src/scenes"),
            ]
        );
        let rules: Vec<&str> = folders.iter().map(|f| f.rule).collect();
        assert_eq!(rules[0], "in ./scenes");
        assert_eq!(rules[1..3], ["in $PPM_SCENES"; 2]);
        assert_eq!(rules[3], "beside the binary");
        assert!(rules[5].contains("source tree"), "{}", rules[5]);
        assert_eq!(
            paths(&search_folders(None, None, Path::new("/src/scenes"))),
            [PathBuf::from("scenes"), PathBuf::from("/src/scenes")]
        );
    }

    #[test]
    fn first_existing_file_wins() {
        let one = tempfile::tempdir().unwrap();
        let two = tempfile::tempdir().unwrap();
        std::fs::write(two.path().join("s.yml"), "").unwrap();
        std::fs::create_dir(one.path().join("s.yml")).unwrap(); // a folder is not a scene
        let folders = [
            SearchFolder {
                path: one.path().to_path_buf(),
                rule: "one",
            },
            SearchFolder {
                path: two.path().to_path_buf(),
                rule: "two",
            },
        ];
        assert_eq!(
            find(Path::new("s.yml"), &folders),
            Some((two.path().join("s.yml"), "two"))
        );
        std::fs::write(one.path().join("t.yml"), "").unwrap();
        std::fs::write(two.path().join("t.yml"), "").unwrap();
        assert_eq!(
            find(Path::new("t.yml"), &folders),
            Some((one.path().join("t.yml"), "one"))
        );
        // An absolute path is only tried as given.
        let absolute = one.path().join("missing.yml");
        assert_eq!(
            candidates(&absolute, &folders),
            [(absolute.clone(), AS_GIVEN)]
        );
    }
}
