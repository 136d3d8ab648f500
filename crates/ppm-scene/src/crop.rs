//! The crop windows scene files give (scene format v1's `render.pixel_bounds`, a Mitsuba
//! film's `crop_offset_*` and `crop_width`/`crop_height`, pbrt-v4's `Film` `pixelbounds` and
//! `cropwindow`), checked against the image and made ppm's [`PixelBounds`]: the pixels
//! x0..x1 by y0..y1 (half-open) from the image's top-left corner. A render of the window is
//! an image of its size whose pixels are the full render's there (`ppm_core::pixel_bounds`).

use ppm_core::pixel_bounds::PixelBounds;

/// The window `[x0, x1, y0, y1]` (pixels) of a `(width, height)` image, or what is wrong with
/// it: it must hold at least one pixel and lie inside the image.
pub fn window(edges: [u32; 4], (width, height): (u32, u32)) -> Result<PixelBounds, String> {
    let [x0, x1, y0, y1] = edges;
    if x0 >= x1 || y0 >= y1 || x1 > width || y1 > height {
        return Err(format!(
            "[{x0}, {x1}, {y0}, {y1}]: expected 0 <= x0 < x1 <= {width} and 0 <= y0 < y1 <= {height} (the image is {width}x{height})"
        ));
    }
    Ok(PixelBounds {
        x0,
        x1,
        y0,
        y1,
        full_width: width,
    })
}

/// The window a crop given in fractions of the image covers, `[x0, x1, y0, y1]` with
/// 0 <= x0 < x1 <= 1 and the same for y: pixels ceil(x0 w) .. ceil(x1 w) by ceil(y0 h) ..
/// ceil(y1 h), pbrt-v4's rounding (its film's pixel bounds from `cropwindow`).
pub fn fraction_window(
    fractions: [f64; 4],
    (width, height): (u32, u32),
) -> Result<PixelBounds, String> {
    let [x0, x1, y0, y1] = fractions;
    let unit = 0.0..=1.0;
    if !(unit.contains(&x0) && unit.contains(&x1) && unit.contains(&y0) && unit.contains(&y1))
        || x0 >= x1
        || y0 >= y1
    {
        return Err(format!(
            "[{x0}, {x1}, {y0}, {y1}]: expected fractions of the image with 0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1"
        ));
    }
    let pixel = |f: f64, n: u32| ((f * n as f64).ceil() as u32).min(n);
    window(
        [
            pixel(x0, width),
            pixel(x1, width),
            pixel(y0, height),
            pixel(y1, height),
        ],
        (width, height),
    )
    .map_err(|_| format!("[{x0}, {x1}, {y0}, {y1}] covers no pixel of the {width}x{height} image"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_inside_the_image_are_kept_others_refused() {
        let b = window([9, 25, 5, 27], (32, 32)).unwrap();
        assert_eq!((b.x0, b.x1, b.y0, b.y1, b.full_width), (9, 25, 5, 27, 32));
        assert!(window([0, 32, 0, 32], (32, 32)).is_ok());
        for bad in [[0, 33, 0, 1], [5, 5, 0, 1], [0, 1, 2, 1], [0, 1, 0, 40]] {
            let e = window(bad, (32, 32)).unwrap_err();
            assert!(e.contains("32x32"), "{e}");
        }
    }

    #[test]
    fn fractions_round_up_as_pbrt_does() {
        // ceil(0.25 * 64) = 16, ceil(0.5 * 64) = 32, ceil(0.1 * 32) = 4, ceil(0.9 * 32) = 29.
        let b = fraction_window([0.25, 0.5, 0.1, 0.9], (64, 32)).unwrap();
        assert_eq!((b.x0, b.x1, b.y0, b.y1), (16, 32, 4, 29));
        assert!(fraction_window([0.5, 0.4, 0.0, 1.0], (64, 32)).is_err());
        assert!(fraction_window([0.0, 1.0, 0.0, f64::NAN], (64, 32)).is_err());
        let e = fraction_window([0.999, 1.0, 0.0, 1.0], (64, 32)).unwrap_err();
        assert!(e.contains("covers no pixel"), "{e}");
    }
}
