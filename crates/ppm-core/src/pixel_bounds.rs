//! The rectangle of pixels a render computes: the whole image, or a crop window of it.
//!
//! Random streams are keyed by (seed, iteration, pixel index in the *full* image), so a pixel
//! rendered inside a crop window gets exactly the value it has in the full render.

/// Pixels `x0..x1` by `y0..y1` (half-open) of a `width` x `height` image, row-major.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelBounds {
    pub x0: u32,
    pub x1: u32,
    pub y0: u32,
    pub y1: u32,
    /// Width of the full image, for turning a local index into a full-image pixel index.
    pub full_width: u32,
}

impl PixelBounds {
    /// The whole `width` x `height` image.
    pub fn full(width: u32, height: u32) -> Self {
        PixelBounds {
            x0: 0,
            x1: width,
            y0: 0,
            y1: height,
            full_width: width,
        }
    }

    /// The same window of the image resized from `from` to `to` (width, height) pixels: each
    /// edge e at ceil(e * to / from), the rounding of a crop window given in fractions of the
    /// image (pbrt-v4's `cropwindow`), in integers so that `from == to` keeps every edge.
    /// `None` if the resized window holds no pixel.
    pub fn resized(&self, from: (u32, u32), to: (u32, u32)) -> Option<PixelBounds> {
        let edge = |e: u32, from: u32, to: u32| -> u32 {
            let (e, from, to) = (e as u64, from.max(1) as u64, to as u64);
            ((e * to).div_ceil(from)).min(to) as u32
        };
        let b = PixelBounds {
            x0: edge(self.x0, from.0, to.0),
            x1: edge(self.x1, from.0, to.0),
            y0: edge(self.y0, from.1, to.1),
            y1: edge(self.y1, from.1, to.1),
            full_width: to.0,
        };
        (b.x0 < b.x1 && b.y0 < b.y1).then_some(b)
    }

    /// Columns in the window.
    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    /// Rows in the window.
    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }

    /// Pixels in the window.
    pub fn len(&self) -> usize {
        self.width() as usize * self.height() as usize
    }

    /// True for an empty window.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The full-image pixel index of the window's `local`-th pixel (row-major in the window).
    /// A window of whole rows (the whole image, the usual case) is one contiguous run of the
    /// full image: its index is an addition, without the division a narrower window needs
    /// (called once per pixel per iteration).
    #[inline]
    pub fn full_index(&self, local: usize) -> usize {
        let w = self.width() as usize;
        let fw = self.full_width as usize;
        let first = self.y0 as usize * fw + self.x0 as usize;
        if w == fw {
            first + local
        } else {
            first + (local / w) * fw + local % w
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn local_to_full_index() {
        let full = PixelBounds::full(7, 5);
        assert!((0..35).all(|i| full.full_index(i) == i));
        let crop = PixelBounds {
            x0: 2,
            x1: 5,
            y0: 1,
            y1: 3,
            full_width: 7,
        };
        let got: Vec<usize> = (0..crop.len()).map(|i| crop.full_index(i)).collect();
        assert_eq!(got, [9, 10, 11, 16, 17, 18]);
        // A band of whole rows (the contiguous case, no division).
        let band = PixelBounds {
            x0: 0,
            x1: 7,
            y0: 2,
            y1: 4,
            full_width: 7,
        };
        assert!((0..band.len()).all(|i| band.full_index(i) == 14 + i));
    }

    #[test]
    fn resizing_keeps_the_window_in_place() {
        let crop = PixelBounds {
            x0: 9,
            x1: 25,
            y0: 5,
            y1: 27,
            full_width: 32,
        };
        assert_eq!(crop.resized((32, 32), (32, 32)), Some(crop));
        // Twice the size: every edge doubles.
        let doubled = PixelBounds {
            x0: 18,
            x1: 50,
            y0: 10,
            y1: 54,
            full_width: 64,
        };
        assert_eq!(crop.resized((32, 32), (64, 64)), Some(doubled));
        // Half the width: ceil(9 / 2) = 5, ceil(25 / 2) = 13.
        let halved = crop.resized((32, 32), (16, 32)).unwrap();
        assert_eq!((halved.x0, halved.x1, halved.full_width), (5, 13, 16));
        // A one-pixel window shrunk to nothing.
        let thin = PixelBounds {
            x0: 3,
            x1: 4,
            y0: 0,
            y1: 1,
            full_width: 32,
        };
        assert_eq!(thin.resized((32, 32), (8, 8)), None);
    }
}
