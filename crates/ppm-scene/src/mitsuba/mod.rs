//! Mitsuba scenes (XML, versions 0.5/0.6 and 2/3) with their OBJ, PLY and serialized meshes.
//!
//! Two layers, as Mitsuba's own loader and pbrt-v4's are built:
//! - the parse layer (`parse.rs`, `names.rs`, `transform.rs`) reads the XML into a tree of
//!   plugin objects with typed properties ([`tree::SceneTree`]), each with its file and line,
//!   and knows nothing of rendering;
//! - the build layer (`build/`) maps each plugin to ppm's [`SceneBuilder`], one function per
//!   plugin, reading properties through typed getters ([`props::Props`]) that report any
//!   property left unread.
//!
//! What is supported and how each plugin maps: `docs/mitsuba.md`.

mod build;
pub mod ior;
pub mod names;
pub mod parse;
pub mod props;
pub mod spectrum;
pub mod transform;
pub mod tree;
mod values;

pub use build::shape::SEGMENTS;

use crate::LoadError;
use ppm_core::scene::SceneBuilder;
use std::path::Path;

/// Loads the Mitsuba scene at `path`; `defines` (name, value) set `$name` parameters,
/// overriding the file's `<default>`s. Returns the scene's parts and the warnings.
pub fn load_mitsuba(
    path: &Path,
    defines: &[(String, String)],
) -> Result<(SceneBuilder, Vec<String>), LoadError> {
    let tree = parse::parse_file(path, defines)?;
    let mut warnings = Vec::new();
    let builder = build::build(&tree, &mut warnings)?;
    Ok((builder, warnings))
}

/// Like [`load_mitsuba`] for XML text in memory; `path` names it in messages and locates its
/// relative files.
pub fn parse_mitsuba(
    text: &str,
    path: &Path,
    defines: &[(String, String)],
) -> Result<(SceneBuilder, Vec<String>), LoadError> {
    let tree = parse::parse_str(text, path, defines)?;
    let mut warnings = Vec::new();
    let builder = build::build(&tree, &mut warnings)?;
    Ok((builder, warnings))
}
