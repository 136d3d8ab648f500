//! Helpers shared by the loader tests: scratch folders, a minimal valid scene, and an OBJ
//! loader call for the OBJ and MTL tests.
#![allow(dead_code)]

use ppm_scene::obj::{load_obj, ObjData, ObjMaterials};
use std::path::{Path, PathBuf};

/// A fresh, empty scratch folder for one test (under Cargo's per-target temp folder).
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("ppm-scene-tests")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes `files` (name, content) into a fresh scratch folder and returns it.
pub fn write_files(test: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = scratch(test);
    for (name, text) in files {
        let path = dir.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }
    dir
}

/// The repository's `scenes/` folder.
pub fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// A camera block every test scene can start with.
pub const CAMERA: &str =
    "camera: { position: [0, 1, 3.9], look_at: [0, 1, 0], up: [0, 1, 0], fov: 38 }\n";

/// A small valid scene: a camera, a light and a floor.
pub const VALID: &str = "\
camera: { position: [0, 1, 3.9], look_at: [0, 1, 0], up: [0, 1, 0], fov: 38 }
resolution: [64, 48]
materials:
  white: { type: diffuse, color: [0.7, 0.7, 0.7] }
  lamp: { type: diffuse, color: [0.5, 0.5, 0.5], emission: [10, 10, 10] }
objects:
  - { type: quad, corner: [-1, 0, -1], edge_u: [0, 0, 2], edge_v: [2, 0, 0], material: white }
  - { type: sphere, center: [0, 1.5, 0], radius: 0.1, material: lamp }
";

/// Four vertices of the unit square in z = 0, counter-clockwise seen from +z (OBJ text).
pub const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

/// Loads `dir/name` with its MTL materials; panics with the loader's message on an error.
pub fn load(dir: &Path, name: &str) -> (ObjData, Vec<String>) {
    let mut warnings = Vec::new();
    let data = load_obj(&dir.join(name), ObjMaterials::FromMtl, &mut warnings)
        .unwrap_or_else(|e| panic!("{e}"));
    (data, warnings)
}
