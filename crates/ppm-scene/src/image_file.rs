//! Reading an RGB image file into linear values: PNG and JPEG through `image`, Radiance HDR
//! through `image`, OpenEXR through `exr`.
//!
//! Integer images (8- or 16-bit) are sRGB-encoded by convention and decoded to linear by the
//! sRGB transfer function unless `raw` (then the values are taken as they are, divided by
//! the largest code); float images (HDR, EXR) are linear already.

use crate::LoadError;
use glam::Vec3;
use ppm_core::texture::srgb_to_linear;
use std::path::Path;

/// A decoded image: `width` x `height` linear RGB values, row-major from the top row.
#[derive(Clone, Debug)]
pub struct RgbImage {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<Vec3>,
}

/// Reads the image at `path` (`what` says what it is for, in errors: a missing file is an
/// I/O error naming it, an undecodable one an error naming it and the decoder's reason).
pub fn read_rgb_image(path: &Path, what: &str, raw: bool) -> Result<RgbImage, LoadError> {
    // Read and decoded once per load however many materials use it (`file_cache`).
    crate::file_cache::parsed("image", path, raw.to_string(), || {
        read_uncached(path, what, raw)
    })
}

fn read_uncached(path: &Path, what: &str, raw: bool) -> Result<RgbImage, LoadError> {
    let error = |source: std::io::Error| LoadError::Io {
        path: path.to_path_buf(),
        what: what.to_string(),
        source,
    };
    let broken = |message: String| {
        error(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            message,
        ))
    };
    let is_exr = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    crate::file_cache::note_read();
    if is_exr {
        std::fs::metadata(path).map_err(error)?;
        return read_exr(path).map_err(broken);
    }
    let reader = image::ImageReader::open(path)
        .map_err(error)?
        .with_guessed_format()
        .map_err(error)?;
    let decoded = reader.decode().map_err(|e| broken(e.to_string()))?;
    let float = matches!(
        decoded.color(),
        image::ColorType::Rgb32F | image::ColorType::Rgba32F
    );
    let rgb = decoded.to_rgb32f();
    let (width, height) = rgb.dimensions();
    let decode = |c: f32| if float || raw { c } else { srgb_to_linear(c) };
    let texels = rgb
        .pixels()
        .map(|p| Vec3::new(decode(p[0]), decode(p[1]), decode(p[2])))
        .collect();
    Ok(RgbImage {
        width,
        height,
        texels,
    })
}

/// The first RGB(A) layer of an OpenEXR file (alpha dropped), linear.
fn read_exr(path: &Path) -> Result<RgbImage, String> {
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        path,
        |resolution, _| {
            (
                resolution.width(),
                vec![Vec3::ZERO; resolution.width() * resolution.height()],
            )
        },
        |(width, texels): &mut (usize, Vec<Vec3>),
         position,
         (r, g, b, _a): (f32, f32, f32, f32)| {
            texels[position.y() * *width + position.x()] = Vec3::new(r, g, b);
        },
    )
    .map_err(|e| e.to_string())?;
    let (width, texels) = image.layer_data.channel_data.pixels;
    let height = texels.len() / width.max(1);
    Ok(RgbImage {
        width: width as u32,
        height: height as u32,
        texels,
    })
}
