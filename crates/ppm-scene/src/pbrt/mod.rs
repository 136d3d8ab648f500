//! pbrt-v4 scenes (`.pbrt`): the subset the field's test scenes use.
//!
//! Two layers, as pbrt-v4's own loader and ppm's Mitsuba importer are built:
//! - the parse layer (`lexer.rs`, `params.rs`, `parse.rs`) reads the directives into a
//!   [`scene::Description`]: entities (shapes, lights, materials, textures, the camera) with
//!   the transform and graphics state each was declared under, object instances expanded,
//!   includes read; it knows nothing of rendering;
//! - the build layer (`build/`) maps each entity to ppm's [`SceneBuilder`], one function per
//!   kind, reading parameters through typed getters ([`params::ParamSet`]) that report any
//!   parameter left unread, with its file, line and column.
//!
//! What is supported and how each directive maps: `docs/pbrt.md`.

mod build;
pub mod lexer;
pub mod params;
pub mod parse;
pub mod scene;
pub mod spectrum;

use crate::LoadError;
use ppm_core::scene::SceneBuilder;
use std::fmt;
use std::path::Path;
use std::sync::Arc;

/// Where a token was written: a file, a 1-based line and column (0 = unknown).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Loc {
    pub file: Arc<Path>,
    pub line: u32,
    pub column: u32,
}

impl fmt::Display for Loc {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if self.line > 0 {
            write!(f, ":{}", self.line)?;
            if self.column > 0 {
                write!(f, ":{}", self.column)?;
            }
        }
        Ok(())
    }
}

impl Loc {
    /// A load error at this place.
    pub(crate) fn error(&self, message: impl Into<String>) -> LoadError {
        LoadError::Parse {
            path: self.file.to_path_buf(),
            line: self.line as usize,
            column: self.column as usize,
            message: message.into(),
        }
    }
}

/// Loads the pbrt-v4 scene at `path`: the scene's parts and the warnings.
pub fn load_pbrt(path: &Path) -> Result<(SceneBuilder, Vec<String>), LoadError> {
    let (description, mut warnings) = parse::parse_file(path)?;
    let builder = build::build(&description, &mut warnings)?;
    Ok((builder, warnings))
}

/// Like [`load_pbrt`] for scene text in memory; `path` names it in messages and locates its
/// relative files.
pub fn parse_pbrt(text: &str, path: &Path) -> Result<(SceneBuilder, Vec<String>), LoadError> {
    let (description, mut warnings) = parse::parse_str(text, path)?;
    let builder = build::build(&description, &mut warnings)?;
    Ok((builder, warnings))
}
