//! Images read back as linear RGB, for `compare`, `converge` and `--reference`: ppm's own
//! EXRs, the Radiance HDR files other renderers write, and PNGs (decoded from sRGB).

use super::srgb::srgb_eotf;
use anyhow::{bail, Context, Result};
use glam::Vec3;
use ppm_core::film::Image;
use std::fs::File;
use std::io::BufReader;
use std::path::Path;

/// Errors if `image` holds a NaN or infinite value: every metric would be NaN or infinite,
/// which says nothing (and a NaN compares false against any threshold a script tests).
pub fn check_finite(image: &Image, path: &Path, what: &str) -> Result<()> {
    let bad = image.pixels.iter().filter(|p| !p.is_finite()).count();
    if let Some(i) = image.pixels.iter().position(|p| !p.is_finite()) {
        let (x, y) = (i as u32 % image.width, i as u32 / image.width);
        bail!(
            "{what} {} has {bad} pixel(s) with NaN or infinite values (the first at ({x}, {y}): \
             {}); the error metrics would be meaningless",
            path.display(),
            image.pixels[i]
        );
    }
    Ok(())
}

/// Reads a reference image (`--reference`, `converge --reference`): as [`read_image`], and
/// refused if a pixel is NaN or infinite, as `compare` refuses it: the error against it would
/// be NaN, printed and logged as if it were a measurement.
pub fn read_reference(path: &Path) -> Result<Image> {
    let image = read_image(path)?;
    check_finite(&image, path, "the reference")?;
    Ok(image)
}

/// Reads an image as linear RGB: an OpenEXR file (its R, G, B channels), a Radiance .hdr file
/// (what other renderers, SmallVCM among them, write) or, as a convenience, a PNG (decoded
/// from sRGB).
pub fn read_image(path: &Path) -> Result<Image> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("exr") => read_exr(path),
        Some("hdr") => read_hdr(path),
        Some("png") => read_png(path),
        _ => bail!(
            "cannot read {}: expected an .exr, .hdr or .png file",
            path.display()
        ),
    }
    .with_context(|| format!("cannot read image {}", path.display()))
}

fn read_exr(path: &Path) -> Result<Image> {
    let exr_image = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |size, _| Image::new(size.width() as u32, size.height() as u32),
        |image: &mut Image, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            let i = pos.y() * image.width as usize + pos.x();
            image.pixels[i] = Vec3::new(r, g, b);
        },
    )
    // exr's errors repeat their io::Error as their source: keep the message only.
    .map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok(exr_image.layer_data.channel_data.pixels)
}

fn read_hdr(path: &Path) -> Result<Image> {
    // Radiance RGBE decodes to linear floats; no transfer curve to undo.
    read_rgb(path, image::ImageFormat::Hdr, |c| c)
}

fn read_png(path: &Path) -> Result<Image> {
    // to_rgb32f maps the codes to [0, 1] (of 255 or 65535) without touching the transfer curve.
    read_rgb(path, image::ImageFormat::Png, srgb_eotf)
}

/// Decodes `path` as `format` to RGB floats and maps each channel by `to_linear`.
fn read_rgb(path: &Path, format: image::ImageFormat, to_linear: fn(f32) -> f32) -> Result<Image> {
    let reader = BufReader::new(File::open(path)?);
    let rgb = image::ImageReader::with_format(reader, format)
        .decode()?
        .to_rgb32f();
    Ok(Image {
        width: rgb.width(),
        height: rgb.height(),
        pixels: rgb
            .pixels()
            .map(|p| Vec3::from(p.0.map(to_linear)))
            .collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;
    use std::io::BufWriter;

    /// A Radiance file (written by the image crate's encoder) reads back top row first, in
    /// R, G, B order, within RGBE's precision (8 mantissa bits under the largest channel).
    #[test]
    fn hdr_reads_in_order_within_rgbe_precision() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("other_renderer.hdr");
        let (width, height) = (3, 2);
        let pixels: Vec<Vec3> = (0..width * height)
            .map(|i| Vec3::new(1.0 + i as f32, 0.5 * i as f32, 0.03 * (5 - i) as f32))
            .collect();
        let rgb: Vec<image::Rgb<f32>> = pixels.iter().map(|p| image::Rgb(p.to_array())).collect();
        let file = BufWriter::new(File::create(&path).unwrap());
        image::codecs::hdr::HdrEncoder::new(file)
            .encode(&rgb, width, height)
            .unwrap();
        let back = read_image(&path).unwrap();
        assert_eq!((back.width, back.height), (width as u32, height as u32));
        for (i, (a, b)) in back.pixels.iter().zip(&pixels).enumerate() {
            let tolerance = b.max_element() / 128.0;
            assert!(
                (*a - *b).abs().max_element() <= tolerance,
                "pixel {i}: {a} vs {b}"
            );
        }
    }

    #[test]
    fn unreadable_images_are_named() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("missing.exr");
        assert!(format!("{:#}", read_image(&missing).unwrap_err()).contains("missing.exr"));
        let garbage = dir.path().join("garbage.exr");
        fs::write(&garbage, b"not an exr").unwrap();
        assert!(format!("{:#}", read_image(&garbage).unwrap_err()).contains("garbage.exr"));
        let err = format!("{:#}", read_image(Path::new("x.tiff")).unwrap_err());
        assert!(err.contains("x.tiff") && err.contains(".exr"), "{err}");
        let garbage = dir.path().join("garbage.hdr");
        fs::write(&garbage, b"#?RADIANCE\nnot a header").unwrap();
        assert!(format!("{:#}", read_image(&garbage).unwrap_err()).contains("garbage.hdr"));
    }
}
