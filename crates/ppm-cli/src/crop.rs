//! The crop window: `--cropwindow x0 x1 y0 y1` (fractions of the image, pbrt-v4's convention)
//! or `--pixelbounds x0 x1 y0 y1` (pixels), into the [`PixelBounds`] the renderer computes.
//!
//! Both are half-open ranges from the top-left corner of the image; the output image is the
//! crop's size, and its pixels equal the full render's there at the same seed.

use anyhow::Result;
use ppm_core::pixel_bounds::PixelBounds;
use ppm_scene::crop::{fraction_window, window};

/// The pixels to render for a `width` x `height` image. A crop window [x0, x1) x [y0, y1) in
/// fractions covers pixels ceil(x0 w) .. ceil(x1 w) by ceil(y0 h) .. ceil(y1 h), as in pbrt-v4;
/// the rules are the scene files' (`ppm_scene::crop`), the messages name the flag.
pub fn pixel_bounds(
    width: u32,
    height: u32,
    crop_window: Option<&[f64]>,
    pixel_bounds: Option<&[u32]>,
) -> Result<PixelBounds> {
    let checked = match (crop_window, pixel_bounds) {
        (None, None) => return Ok(PixelBounds::full(width, height)),
        (Some(c), _) => {
            let &[x0, x1, y0, y1] = c else {
                usage_bail!("--cropwindow takes four numbers: x0 x1 y0 y1");
            };
            fraction_window([x0, x1, y0, y1], (width, height)).map_err(|e| ("--cropwindow", e))
        }
        (None, Some(p)) => {
            let &[x0, x1, y0, y1] = p else {
                usage_bail!("--pixelbounds takes four numbers: x0 x1 y0 y1");
            };
            window([x0, x1, y0, y1], (width, height)).map_err(|e| ("--pixelbounds", e))
        }
    };
    match checked {
        Ok(bounds) => Ok(bounds),
        Err((flag, e)) => usage_bail!("{flag} {e}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn b(x0: u32, x1: u32, y0: u32, y1: u32, w: u32) -> PixelBounds {
        PixelBounds {
            x0,
            x1,
            y0,
            y1,
            full_width: w,
        }
    }

    #[test]
    fn crop_window_rounds_up_like_pbrt() {
        assert_eq!(
            pixel_bounds(64, 32, None, None).unwrap(),
            b(0, 64, 0, 32, 64)
        );
        // ceil(0.25 * 64) = 16, ceil(0.5 * 64) = 32, ceil(0.1 * 32) = 4, ceil(0.9 * 32) = 29.
        let c = [0.25, 0.5, 0.1, 0.9];
        assert_eq!(
            pixel_bounds(64, 32, Some(&c), None).unwrap(),
            b(16, 32, 4, 29, 64)
        );
        let whole = [0.0, 1.0, 0.0, 1.0];
        assert_eq!(
            pixel_bounds(64, 32, Some(&whole), None).unwrap(),
            b(0, 64, 0, 32, 64)
        );
        assert_eq!(
            pixel_bounds(64, 32, None, Some(&[3, 9, 0, 1])).unwrap(),
            b(3, 9, 0, 1, 64)
        );
    }

    #[test]
    fn bad_windows_are_refused_with_the_rule() {
        for c in [
            [0.5, 0.5, 0.0, 1.0],
            [0.6, 0.5, 0.0, 1.0],
            [-0.1, 0.5, 0.0, 1.0],
            [0.0, 1.5, 0.0, 1.0],
            [0.0, 1.0, 0.0, f64::NAN],
        ]
        .iter()
        {
            let err = pixel_bounds(64, 32, Some(c), None).unwrap_err().to_string();
            assert!(err.contains("--cropwindow"), "{err}");
        }
        let err = pixel_bounds(64, 32, Some(&[0.999, 1.0, 0.0, 1.0]), None)
            .unwrap_err()
            .to_string();
        assert!(err.contains("covers no pixel"), "{err}");
        for p in [[0, 65, 0, 1], [5, 5, 0, 1], [0, 1, 2, 1]] {
            let err = pixel_bounds(64, 32, None, Some(&p))
                .unwrap_err()
                .to_string();
            assert!(
                err.contains("--pixelbounds") && err.contains("64x32"),
                "{err}"
            );
        }
    }
}
