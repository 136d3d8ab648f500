//! # ppm-scene
//!
//! Scene format v1 (one YAML file, specified in `docs/scene-format.md`) and Wavefront OBJ/MTL
//! meshes, loaded into a [`ppm_core::scene::Scene`]; and Mitsuba XML scenes with their OBJ,
//! PLY and serialized meshes ([`mitsuba`], `docs/mitsuba.md`), chosen by the `.xml` extension;
//! and pbrt-v4 scenes ([`pbrt`], `docs/pbrt.md`), chosen by `.pbrt`.
//!
//! Loading never panics on bad input: every problem becomes a [`LoadError`] whose message
//! starts with the file and the line (and column) or field path, e.g.
//! `scenes/box.yml:7:22: materials.white.color: component 1 is -0.5, expected a reflectance in [0, 1]`.
//! Problems the loader can work around (a missing MTL file, degenerate triangles, unusable
//! vertex normals, an MTL material that would create energy) become warnings naming the file.
//!
//! ```no_run
//! let loaded = ppm_scene::load_scene(std::path::Path::new("scenes/cornell_box.yml"))?;
//! for w in &loaded.warnings {
//!     eprintln!("warning: {w}");
//! }
//! # Ok::<(), ppm_scene::LoadError>(())
//! ```

mod angle;
mod build;
mod closed_glass;
mod content_hash;
pub mod convert;
pub mod crop;
mod environment;
mod error;
mod file_cache;
pub mod fov;
pub mod image_file;
pub mod ior;
mod light_area;
mod light_placement;
mod materials;
pub mod mitsuba;
pub mod mtl;
pub mod mtl_texture;
mod nesting;
pub mod obj;
mod object_transform;
pub mod pbrt;
pub mod placement;
pub mod ply;
mod ply_object;
pub mod radiance_map;
pub mod serialized;
mod texture_desc;
mod values;
mod yaml;
mod yaml_light;

pub use build::DEFAULT_RESOLUTION;
pub use content_hash::content_hash;
pub use error::LoadError;
pub use file_cache::LoadStats;
pub use nesting::MAX_NESTING;

use ppm_core::scene::{Scene, SceneBuilder};
use std::path::{Path, PathBuf};

/// A loaded scene and the warnings met on the way (unknown MTL files, degenerate triangles...).
pub struct LoadedScene {
    pub scene: Scene,
    pub warnings: Vec<String>,
    /// [`content_hash`] of the scene as loaded (meshes included).
    pub content_hash: u64,
    /// What the load read: each file named by many objects is read once.
    pub stats: LoadStats,
}

/// Loads a scene file (scene format v1, or a Mitsuba XML scene) and builds the scene (BVH,
/// lights).
pub fn load_scene(path: &Path) -> Result<LoadedScene, LoadError> {
    load_scene_with_defines(path, &[])
}

/// Like [`load_scene`], with `defines` (name, value) setting a Mitsuba scene's `$name`
/// parameters over its `<default>`s (a YAML scene has none: they are ignored).
pub fn load_scene_with_defines(
    path: &Path,
    defines: &[(String, String)],
) -> Result<LoadedScene, LoadError> {
    let (builder, mut warnings, stats) = load_scene_builder_with_stats(path, defines)?;
    let content_hash = content_hash(&builder);
    for (material, edges) in closed_glass::open_glass_edges(&builder) {
        warnings.push(format!(
            "{}: the glass of material `{}` is not closed: {edges} open edge{} (used by one triangle only); light that enters it through the hole never meets the far side, so it renders wrong: close the mesh, or use `thindielectric` for a sheet",
            path.display(),
            builder.materials[material as usize].name,
            if edges == 1 { "" } else { "s" }
        ));
    }
    let emissive = light_area::emissive_triangles(&builder);
    let scene = builder.build().map_err(|source| LoadError::Scene {
        path: path.to_path_buf(),
        source,
    })?;
    for material in light_placement::lights_in_other_surfaces(&scene) {
        warnings.push(format!(
            "{}: a light of material `{}` lies in the plane of another surface: rays find one or the other by rounding, so the lamp looks speckled and the algorithms disagree; move it off by a little (the shipped boxes hang their lamp 2 cm under the ceiling)",
            path.display(),
            scene.materials[material as usize].name
        ));
    }
    for (material, gap) in light_placement::lights_facing_near_surfaces(&scene) {
        warnings.push(format!(
            "{}: a light of material `{}` emits into a surface {gap:.3} away (scene units), so only what leaks out of the gap lights the scene: is it turned over? Emission leaves the side of counter-clockwise winding (OBJ faces, quads' edge_u x edge_v); reverse the faces or move the lamp",
            path.display(),
            scene.materials[material as usize].name
        ));
    }
    for (material, triangles) in light_area::lights_without_area(&scene, &emissive) {
        warnings.push(format!(
            "{}: {} of light material `{}` emit{} nothing: no area is left in single precision at {} distance from the camera; make the lamp larger against that distance",
            path.display(),
            if triangles == 1 {
                "the 1 triangle".to_string()
            } else {
                format!("the {triangles} triangles")
            },
            scene.materials[material as usize].name,
            if triangles == 1 { "s" } else { "" },
            if triangles == 1 { "its" } else { "their" },
        ));
    }
    let duplicates = scene.geometry.duplicate_triangles();
    if duplicates > 0 {
        warnings.push(format!(
            "{}: dropped {duplicates} triangles that repeat an earlier triangle exactly (the same three vertices in the same order); they could never be hit",
            path.display()
        ));
    }
    Ok(LoadedScene {
        scene,
        warnings,
        content_hash,
        stats,
    })
}

/// Reads and checks a scene file and the meshes it references, without building the BVH:
/// the scene's parts and the warnings met on the way.
pub fn load_scene_builder(path: &Path) -> Result<(SceneBuilder, Vec<String>), LoadError> {
    load_scene_builder_with_defines(path, &[])
}

/// Like [`load_scene_builder`] with Mitsuba `$name` parameters. The importer is chosen by the
/// extension: `.xml` is a Mitsuba scene (`docs/mitsuba.md`), `.pbrt` a pbrt-v4 scene
/// (`docs/pbrt.md`), anything else scene format v1.
pub fn load_scene_builder_with_defines(
    path: &Path,
    defines: &[(String, String)],
) -> Result<(SceneBuilder, Vec<String>), LoadError> {
    load_scene_builder_with_stats(path, defines).map(|(builder, warnings, _)| (builder, warnings))
}

/// [`load_scene_builder_with_defines`] and what the load read ([`LoadStats`]).
pub fn load_scene_builder_with_stats(
    path: &Path,
    defines: &[(String, String)],
) -> Result<(SceneBuilder, Vec<String>, LoadStats), LoadError> {
    // Every file named by many objects is read and parsed once within this load.
    let scope = file_cache::LoadScope::begin();
    let (builder, warnings) = load_by_extension(path, defines)?;
    Ok((builder, warnings, scope.end()))
}

fn load_by_extension(
    path: &Path,
    defines: &[(String, String)],
) -> Result<(SceneBuilder, Vec<String>), LoadError> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match extension.as_deref() {
        Some("xml") => return mitsuba::load_mitsuba(path, defines),
        Some("pbrt") => return pbrt::load_pbrt(path),
        Some("ply") | Some("serialized") => {
            return Err(LoadError::invalid(
                path,
                "file",
                "a mesh, not a scene: name it from a Mitsuba scene (<shape type=\"ply\"> or \"serialized\") or a YAML scene",
            ))
        }
        _ => {}
    }
    let text = obj::read_text(path, "scene file")?;
    parse_scene(&text, path)
}

/// Like [`load_scene_builder`] for scene text already in memory; `path` names it in messages
/// and relative file names (meshes) are resolved against its folder.
pub fn parse_scene(text: &str, path: &Path) -> Result<(SceneBuilder, Vec<String>), LoadError> {
    // A UTF-8 byte order mark (written by some Windows editors) is not part of the YAML.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    nesting::check_nesting(text, path)?;
    let file: yaml::SceneFile =
        serde_yaml_ng::from_str(text).map_err(|e| LoadError::yaml(path, e))?;
    let mut warnings = Vec::new();
    let _scope = file_cache::LoadScope::begin();
    let builder = build::build(file, path, &mut warnings)?;
    Ok((builder, warnings))
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
