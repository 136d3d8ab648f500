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
}
