//! Radiance maps for environment lights, read from image files: OpenEXR (linear, the `exr`
//! crate), Radiance HDR (RGBE, linear) and PNG (sRGB-encoded: decoded to linear with the
//! sRGB transfer curve, as Mitsuba 3 does for 8-bit images). The core takes the decoded RGB
//! buffer ([`ppm_core::light::LatLongMap`]); decoding lives here, with the other file formats.

use glam::Vec3;
use ppm_core::light::{EqualAreaMap, LatLongMap};
use std::fs::File;
use std::io::BufReader;
use std::path::Path;

/// A decoded image: width, height and linear RGB texels, row-major from the top row.
pub struct RgbImage {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<Vec3>,
}

/// Reads `path` by its extension (`.exr`, `.hdr`, `.png`). The error says what went wrong,
/// without the path (the caller names the file and the field).
pub fn read_rgb(path: &Path) -> Result<RgbImage, String> {
    crate::file_cache::note_read();
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("exr") => read_exr(path),
        Some("hdr") => read_with(path, image::ImageFormat::Hdr, |c| c),
        Some("png") => read_with(path, image::ImageFormat::Png, srgb_to_linear),
        _ => Err("expected an .exr, .hdr or .png file".into()),
    }
}

/// Reads `path` ([`read_rgb`]) as a lat-long radiance map (`envmap.rs` in ppm-core has its
/// frame): every texel finite and non-negative.
pub fn read_map(path: &Path) -> Result<LatLongMap, String> {
    let image = read_rgb(path)?;
    LatLongMap::new(image.width, image.height, image.texels).map_err(|e| e.to_string())
}

/// Reads `path` ([`read_rgb`]) as an equal-area octahedral radiance map (pbrt-v4's format,
/// `equal_area.rs` in ppm-core): square, every texel finite and non-negative.
pub fn read_equal_area_map(path: &Path) -> Result<EqualAreaMap, String> {
    let image = read_rgb(path)?;
    if image.width != image.height {
        return Err(format!(
            "an equal-area map is square; this image is {}x{}",
            image.width, image.height
        ));
    }
    EqualAreaMap::new(image.width, image.texels).map_err(|e| e.to_string())
}

fn read_exr(path: &Path) -> Result<RgbImage, String> {
    crate::file_cache::note_read();
    crate::file_cache::note_read();
    let image = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |size, _| RgbImage {
            width: size.width(),
            height: size.height(),
            texels: vec![Vec3::ZERO; size.width() * size.height()],
        },
        |image: &mut RgbImage, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            image.texels[pos.y() * image.width + pos.x()] = Vec3::new(r, g, b);
        },
    )
    .map_err(|e| e.to_string())?;
    Ok(image.layer_data.channel_data.pixels)
}

fn read_with(
    path: &Path,
    format: image::ImageFormat,
    to_linear: fn(f32) -> f32,
) -> Result<RgbImage, String> {
    crate::file_cache::note_read();
    let reader = BufReader::new(File::open(path).map_err(|e| e.to_string())?);
    let rgb = image::ImageReader::with_format(reader, format)
        .decode()
        .map_err(|e| e.to_string())?
        .to_rgb32f();
    Ok(RgbImage {
        width: rgb.width() as usize,
        height: rgb.height() as usize,
        texels: rgb
            .pixels()
            .map(|p| Vec3::from(p.0.map(to_linear)))
            .collect(),
    })
}

/// The sRGB electro-optical transfer function (IEC 61966-2-1): code value in [0, 1] to
/// linear.
fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}
