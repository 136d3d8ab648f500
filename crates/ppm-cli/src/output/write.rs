//! The image encoders: an 8-bit sRGB PNG for looking at, a linear f32 EXR for measuring, each
//! written to a temporary file ([`PendingFile`]); and the PNG and EXR of a render committed as
//! a pair ([`commit_pair`]), so that a failed write never leaves a new PNG beside an old EXR.

use super::durable::PendingFile;
use super::srgb::to_srgb8;
use super::OutputPaths;
use anyhow::{Context, Result};
use ppm_core::film::Image;
use std::path::Path;

/// Writes interleaved 8-bit RGB as a PNG, atomically.
pub fn write_png_rgb8(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<()> {
    pending_png_rgb8(path, width, height, rgb)?.commit()
}

fn pending_png_rgb8(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<PendingFile> {
    use image::ImageEncoder;
    PendingFile::write(path, |w| {
        image::codecs::png::PngEncoder::new(w).write_image(
            rgb,
            width,
            height,
            image::ExtendedColorType::Rgb8,
        )?;
        Ok(())
    })
}

/// Writes an image as an sRGB 8-bit PNG, atomically (renders write PNG and EXR as a pair with
/// [`crate::state_file::write_image_and_state`]).
#[cfg(test)]
pub fn write_png(path: &Path, image: &Image) -> Result<()> {
    pending_png(path, image)?.commit()
}

/// A PNG of `image` written to a temporary file, to be committed (see [`commit_pair`]).
pub fn pending_png(path: &Path, image: &Image) -> Result<PendingFile> {
    pending_png_rgb8(path, image.width, image.height, &to_srgb8(image))
}

/// Writes an image as a linear RGB f32 OpenEXR file, ZIP-compressed (lossless), atomically,
/// without a render state (an AOV; renders write theirs with `state_file`).
pub fn write_exr(path: &Path, image: &Image) -> Result<()> {
    pending_exr(path, image)?.commit()
}

fn pending_exr(path: &Path, image: &Image) -> Result<PendingFile> {
    use exr::prelude::{Image as ExrImage, SpecificChannels, WritableImage};
    let channels = SpecificChannels::rgb(|exr::math::Vec2(x, y)| {
        let p = image.get(x as u32, y as u32);
        (p.x, p.y, p.z)
    });
    let exr_image = ExrImage::from_encoded_channels(
        (image.width as usize, image.height as usize),
        exr::prelude::Encoding::SMALL_LOSSLESS,
        channels,
    );
    PendingFile::write(path, |w| {
        exr_image
            .write()
            .to_buffered(w)
            .map_err(|e| anyhow::anyhow!("{e}"))
    })
}

/// Commits a PNG and an EXR written in full to temporary files ([`PendingFile`]) as a pair:
/// both were written before either is renamed over its target, so a full disk or any other
/// write error leaves the previous PNG and EXR both as they were (never a new PNG beside an
/// old EXR). The error says which files were replaced. The two files are encoded and written
/// at the same time, on two threads (the EXR's render state makes it the longer of the two).
pub fn commit_pair(
    paths: &OutputPaths,
    png: impl FnOnce() -> Result<PendingFile> + Send,
    exr: impl FnOnce() -> Result<PendingFile> + Send,
) -> Result<()> {
    let kept = || {
        format!(
            "neither {} nor {} was replaced",
            paths.png.display(),
            paths.exr.display()
        )
    };
    let (png, exr) = std::thread::scope(|scope| {
        let exr = scope.spawn(exr);
        let png = png();
        let exr = exr
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        (png, exr)
    });
    let png = png.with_context(kept)?;
    let exr = exr.with_context(kept)?;
    png.commit().with_context(kept)?;
    exr.commit().with_context(|| {
        format!(
            "{} was replaced but {} was not: the two files are from different renders",
            paths.png.display(),
            paths.exr.display()
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::read_image;
    use crate::output::srgb::encode_srgb8;
    use crate::output::test_image;
    use glam::Vec3;

    #[test]
    fn exr_round_trip_is_exact() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.exr");
        let image = test_image();
        write_exr(&path, &image).unwrap();
        let back = read_image(&path).unwrap();
        assert_eq!(back, image);
    }

    #[test]
    fn png_round_trip_is_within_one_code() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.png");
        let mut image = Image::new(4, 2);
        let values = [0.0, 0.001, 0.02, 0.18, 0.5, 0.9, 1.0, 3.0];
        for (px, v) in image.pixels.iter_mut().zip(values) {
            *px = Vec3::new(v, v * 0.5, 1.0 - v.min(1.0));
        }
        write_png(&path, &image).unwrap();
        let back = read_image(&path).unwrap();
        assert_eq!((back.width, back.height), (4, 2));
        for (a, b) in back.pixels.iter().zip(&image.pixels) {
            for (x, y) in a.to_array().into_iter().zip(b.to_array()) {
                assert_eq!(encode_srgb8(x), encode_srgb8(y));
            }
        }
    }
}
