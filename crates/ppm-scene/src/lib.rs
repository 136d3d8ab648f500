//! # ppm-scene
//!
//! Scene format v1 (one YAML file, see `docs/scene-format.md`) and OBJ/MTL meshes, loaded into
//! a [`ppm_core::scene::Scene`]. TODO(scene helper): implement.

use ppm_core::scene::Scene;
use std::path::{Path, PathBuf};

/// A loaded scene and the warnings met on the way (unknown MTL files, degenerate triangles...).
pub struct LoadedScene {
    pub scene: Scene,
    pub warnings: Vec<String>,
}

/// Why a scene could not be loaded. The message names the file and the line, field or path.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error("{0}")]
    Todo(String),
}

/// Loads a scene file (scene format v1).
pub fn load_scene(path: &Path) -> Result<LoadedScene, LoadError> {
    Err(LoadError::Todo(format!(
        "{}: loader not written yet",
        path.display()
    )))
}

/// The scene file a command-line argument names: the path as given if it exists, otherwise
/// the same path inside `scenes/` (so `ppm cornell_box.yml` works from the repository root).
pub fn resolve_scene_path(arg: &Path) -> PathBuf {
    if arg.exists() {
        return arg.to_path_buf();
    }
    let in_scenes = Path::new("scenes").join(arg);
    if in_scenes.exists() {
        in_scenes
    } else {
        arg.to_path_buf()
    }
}
