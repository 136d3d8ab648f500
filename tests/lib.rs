//! Shared helpers of the end-to-end tests: the shipped scenes, loaded small.

use ppm_core::scene::SceneBuilder;
use std::path::PathBuf;

/// The four scenes shipped in `scenes/`.
pub const SCENES: [&str; 4] = [
    "cornell_box.yml",
    "cornell_box_specular.yml",
    "cornell_box_water.yml",
    "cornell_box_glossy.yml",
];

/// Path of a shipped scene.
pub fn scene_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(name)
}

/// Loads a shipped scene's parts (unbuilt) at the given resolution.
pub fn load_small(name: &str, width: u32, height: u32) -> SceneBuilder {
    let (mut builder, warnings) =
        ppm_scene::load_scene_builder(&scene_path(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(warnings.is_empty(), "{name}: {warnings:?}");
    builder.camera.set_resolution(width, height).unwrap();
    builder
}
