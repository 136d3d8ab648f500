//! Output files: where a render's files go, how they are written and how images are read.
//!
//! Every render writes two files with one stem: an 8-bit sRGB PNG for looking at and a linear
//! f32 EXR for measuring. This file holds the naming rules ([`output_paths`]); the rest is
//! split by concept:
//! - [`durable`]: writing a file so that a failure never leaves a truncated one (a temporary
//!   name, fsync, rename), the writability check run before a render, line-flushed logs;
//! - [`srgb`]: the sRGB transfer curve and its 8-bit encoding;
//! - [`write`]: the PNG and EXR encoders, and the PNG + EXR pair committed together;
//! - [`read`]: images read back as linear RGB (EXR, Radiance HDR, PNG).
//!
//! The render state an EXR carries beside its image is [`crate::state_file`]'s.

mod durable;
mod read;
mod srgb;
mod write;

pub use durable::{
    check_writable, create_folder_and_check, create_log, log_line, write_atomic, PendingFile,
};
pub use read::{check_finite, read_image, read_reference};
#[cfg(test)]
pub use write::write_png;
pub use write::{commit_pair, pending_png, write_exr, write_png_rgb8};

use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// The two files of one rendered image.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OutputPaths {
    pub png: PathBuf,
    pub exr: PathBuf,
}

/// Image formats ppm does not write: `-o out.jpg` is refused rather than read as a name.
const OTHER_IMAGE_EXTENSIONS: &[&str] = &[
    "jpg", "jpeg", "tif", "tiff", "hdr", "bmp", "gif", "webp", "tga", "pfm", "ppm", "pgm",
];

/// The PNG and EXR paths for `-o output` (or its absence) when rendering `scene`.
///
/// `out.png`, `out.exr` and `out` all give `out.png` + `out.exr`; an existing folder (or a path
/// ending in `/`) receives `<scene stem>.png/.exr`; without `-o` those go to the current folder.
/// Only `.png` and `.exr` (any case) are taken as extensions and replaced; another image
/// format's extension (`.jpg`, `.hdr`...) is refused; any other suffix is part of the name:
/// `shot.0001` gives `shot.0001.png` + `shot.0001.exr`.
pub fn output_paths(output: Option<&Path>, scene: &Path) -> Result<OutputPaths> {
    let stem = scene
        .file_stem()
        .with_context(|| format!("scene path {} has no file name", scene.display()))?;
    let base = match output {
        None => PathBuf::from(stem),
        Some(o) if o.is_dir() || o.as_os_str().to_string_lossy().ends_with(['/', '\\']) => {
            o.join(stem)
        }
        Some(o) => match o
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
        {
            None => o.to_path_buf(),
            Some(e) if e == "png" || e == "exr" => o.with_extension(""),
            Some(e) if OTHER_IMAGE_EXTENSIONS.contains(&e.as_str()) => bail!(
                "output {}: unsupported extension .{e}; use .png, .exr or none \
                 (a PNG and an EXR are always both written)",
                o.display()
            ),
            // `shot.0001`, `render.v2`: a dot in a name is not always an extension.
            Some(_) => o.to_path_buf(),
        },
    };
    Ok(OutputPaths {
        png: with_added_extension(&base, "png"),
        exr: with_added_extension(&base, "exr"),
    })
}

impl OutputPaths {
    /// The EXR of an extra image `name` next to the render: `out.exr` gives `out.<name>.exr`.
    pub fn aov(&self, name: &str) -> PathBuf {
        with_added_extension(&self.exr.with_extension(""), &format!("{name}.exr"))
    }
}

/// `base` + `.ext`, keeping any dots already in the file name.
fn with_added_extension(base: &Path, ext: &str) -> PathBuf {
    let mut s = base.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// An image with values an 8-bit format could not hold (tiny, huge, irrational-looking), for
/// the write tests of [`write`] and [`durable`].
#[cfg(test)]
fn test_image() -> ppm_core::film::Image {
    let mut image = ppm_core::film::Image::new(5, 3);
    for (i, px) in image.pixels.iter_mut().enumerate() {
        *px = glam::Vec3::new(
            i as f32 * 0.173_2,
            1e-6 * i as f32,
            1000.0 / (i as f32 + 1.0),
        );
    }
    image
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(s: &str) -> PathBuf {
        PathBuf::from(s)
    }

    #[test]
    fn output_naming_rules() {
        let scene = Path::new("scenes/cornell_box_water.yml");
        let both = |png: &str, exr: &str| OutputPaths {
            png: p(png),
            exr: p(exr),
        };
        assert_eq!(
            output_paths(None, scene).unwrap(),
            both("cornell_box_water.png", "cornell_box_water.exr")
        );
        for o in ["out.png", "out.exr", "out", "out.PNG"] {
            assert_eq!(
                output_paths(Some(Path::new(o)), scene).unwrap(),
                both("out.png", "out.exr"),
                "{o}"
            );
        }
        assert_eq!(
            output_paths(Some(Path::new("renders/a.b.exr")), scene).unwrap(),
            both("renders/a.b.png", "renders/a.b.exr")
        );
        assert_eq!(
            output_paths(Some(Path::new("renders/")), scene).unwrap(),
            both(
                "renders/cornell_box_water.png",
                "renders/cornell_box_water.exr"
            )
        );
        let dir = tempfile::tempdir().unwrap();
        let got = output_paths(Some(dir.path()), scene).unwrap();
        assert_eq!(got.png, dir.path().join("cornell_box_water.png"));
        let err = output_paths(Some(Path::new("out.jpg")), scene)
            .unwrap_err()
            .to_string();
        assert!(err.contains("out.jpg") && err.contains(".jpg"), "{err}");
    }
}
