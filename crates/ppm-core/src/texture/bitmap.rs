//! Mitsuba 3's `bitmap`: an RGB image looked up by uv, bilinearly filtered or nearest.

use super::UvTransform;
use glam::{Vec2, Vec3};
use std::sync::Arc;

/// How a look-up between texel centres is filtered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    /// The texel the point falls in.
    Nearest,
    /// The four nearest texel centres, weighted by the point's distance to them.
    Bilinear,
}

/// What a texel coordinate outside the image reads (Mitsuba's `wrap_mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WrapMode {
    /// The image tiles the plane: texel `x mod width`.
    Repeat,
    /// The image tiles the plane, every other copy mirrored.
    Mirror,
    /// The border texels extend outward.
    Clamp,
}

impl WrapMode {
    /// The texel index in `0..n` that integer coordinate `x` reads.
    #[inline]
    fn wrap(self, x: i64, n: i64) -> usize {
        let i = match self {
            WrapMode::Repeat => x.rem_euclid(n),
            WrapMode::Clamp => x.clamp(0, n - 1),
            // Period 2n: 0..n as is, n..2n backward (n -> n - 1, 2n - 1 -> 0).
            WrapMode::Mirror => {
                let m = x.rem_euclid(2 * n);
                if m >= n {
                    2 * n - 1 - m
                } else {
                    m
                }
            }
        };
        i as usize
    }
}

/// An RGB image of linear values over the uv square: texel (x, y) (row y from the top)
/// covers `[x / width, (x + 1) / width] x [y / height, (y + 1) / height]` of transformed uv,
/// its centre at `((x + 1/2) / width, (y + 1/2) / height)` (Mitsuba 3's `bitmap`).
///
/// Bilinear filtering: with `s = u' width - 1/2`, `t = v' height - 1/2`, `x0 = floor(s)`,
/// `y0 = floor(t)`, `a = s - x0`, `b = t - y0`, the value is
/// `(1-a)(1-b) T(x0, y0) + a(1-b) T(x0+1, y0) + (1-a) b T(x0, y0+1) + a b T(x0+1, y0+1)`,
/// each index wrapped. Nearest: `T(floor(u' width), floor(v' height))`, wrapped.
#[derive(Clone, Debug)]
pub struct Bitmap {
    width: u32,
    height: u32,
    /// Row-major from the top row, linear RGB.
    texels: Arc<[Vec3]>,
    pub filter: Filter,
    pub wrap: WrapMode,
    pub transform: UvTransform,
    /// The mean and the largest value, computed once.
    mean: Vec3,
    max_value: f32,
}

impl Bitmap {
    /// An image of `width` x `height` linear RGB texels, row-major from the top row; `None`
    /// if the sizes do not match or the image is empty.
    pub fn new(
        width: u32,
        height: u32,
        texels: Vec<Vec3>,
        filter: Filter,
        wrap: WrapMode,
        transform: UvTransform,
    ) -> Option<Self> {
        if width == 0 || height == 0 || texels.len() != width as usize * height as usize {
            return None;
        }
        // The mean in double precision, so a large image's sum does not drift.
        let sum = texels
            .iter()
            .fold(glam::DVec3::ZERO, |s, t| s + t.as_dvec3());
        let mean = (sum / texels.len() as f64).as_vec3();
        let max_value = texels.iter().fold(0.0f32, |m, t| m.max(t.max_element()));
        Some(Bitmap {
            width,
            height,
            texels: texels.into(),
            filter,
            wrap,
            transform,
            mean,
            max_value,
        })
    }

    /// (width, height) in texels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The texels, row-major from the top row.
    pub fn texels(&self) -> &[Vec3] {
        &self.texels
    }

    /// Texel at integer coordinates, wrapped.
    #[inline]
    fn texel(&self, x: i64, y: i64) -> Vec3 {
        let (w, h) = (self.width as i64, self.height as i64);
        let (x, y) = (self.wrap.wrap(x, w), self.wrap.wrap(y, h));
        self.texels[y * self.width as usize + x]
    }

    /// The filtered value at surface coordinates `uv`. Non-finite uv reads texel (0, 0).
    #[inline]
    pub fn eval(&self, uv: Vec2) -> Vec3 {
        let uv = self.transform.apply(uv);
        let (w, h) = (self.width as f32, self.height as f32);
        // Coordinates far outside i64 (or NaN) saturate in the cast; the wrap keeps any
        // integer inside the image.
        match self.filter {
            Filter::Nearest => {
                let x = (uv.x * w).floor() as i64;
                let y = (uv.y * h).floor() as i64;
                self.texel(x, y)
            }
            Filter::Bilinear => {
                let s = uv.x * w - 0.5;
                let t = uv.y * h - 0.5;
                let (xf, yf) = (s.floor(), t.floor());
                let (a, b) = (s - xf, t - yf);
                let (a, b) = if a.is_finite() && b.is_finite() {
                    (a, b)
                } else {
                    (0.0, 0.0)
                };
                let (x0, y0) = (xf as i64, yf as i64);
                let (x1, y1) = (x0.wrapping_add(1), y0.wrapping_add(1));
                let top = self.texel(x0, y0) * (1.0 - a) + self.texel(x1, y0) * a;
                let bottom = self.texel(x0, y1) * (1.0 - a) + self.texel(x1, y1) * a;
                top * (1.0 - b) + bottom * b
            }
        }
    }

    /// The mean texel: the image's average over one period of repeated uv.
    pub fn mean(&self) -> Vec3 {
        self.mean
    }

    /// The largest channel value of any texel.
    pub fn max_value(&self) -> f32 {
        self.max_value
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 x 2 image: texel (x, y) has red 1 + x + 2 y, green x, blue y.
    fn image(filter: Filter, wrap: WrapMode) -> Bitmap {
        let texels = (0..2)
            .flat_map(|y| {
                (0..2).map(move |x| Vec3::new((1 + x + 2 * y) as f32, x as f32, y as f32))
            })
            .collect();
        Bitmap::new(2, 2, texels, filter, wrap, UvTransform::IDENTITY).unwrap()
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).abs().max_element() < 1e-6
    }

    /// Bilinear values by hand: at texel centres the texel, between them the weighted mean.
    #[test]
    fn bilinear_interpolates_between_texel_centres() {
        let b = image(Filter::Bilinear, WrapMode::Clamp);
        // Centres at 1/4 and 3/4.
        assert!(close(
            b.eval(Vec2::new(0.25, 0.25)),
            Vec3::new(1.0, 0.0, 0.0)
        ));
        assert!(close(
            b.eval(Vec2::new(0.75, 0.75)),
            Vec3::new(4.0, 1.0, 1.0)
        ));
        // The middle: the mean of the four, (1 + 2 + 3 + 4) / 4 = 2.5.
        assert!(close(b.eval(Vec2::new(0.5, 0.5)), Vec3::new(2.5, 0.5, 0.5)));
        // u = 0.4: s = 0.3, a = 0.3; v = 0.25: top row only: 1 * 0.7 + 2 * 0.3 = 1.3.
        assert!(close(
            b.eval(Vec2::new(0.4, 0.25)),
            Vec3::new(1.3, 0.3, 0.0)
        ));
        // u = 0.625, v = 0.375: s = 0.75, t = 0.25: red = 0.25 0.75 * 2... by the formula:
        // (0.25 * 0.75) 1 + (0.75 * 0.75) 2 + (0.25 * 0.25) 3 + (0.75 * 0.25) 4 = 2.25.
        assert!(close(
            b.eval(Vec2::new(0.625, 0.375)),
            Vec3::new(2.25, 0.75, 0.25)
        ));
        // Clamp: beyond the border centres the border texels.
        assert!(close(b.eval(Vec2::new(0.0, 0.0)), Vec3::new(1.0, 0.0, 0.0)));
        assert!(close(b.eval(Vec2::new(1.0, 0.1)), Vec3::new(2.0, 1.0, 0.0)));
        assert!(close(
            b.eval(Vec2::new(-5.0, 7.0)),
            Vec3::new(3.0, 0.0, 1.0)
        ));
    }

    /// The wrap modes on the edge: repeat blends the last column with the first, mirror
    /// with itself, clamp too; far away repeat and mirror keep their period.
    #[test]
    fn wrap_modes_by_hand() {
        // At u = 0 (s = -0.5, a = 0.5) between column -1 and column 0, v at row 0's centre.
        let at = |wrap, u: f32, v: f32| image(Filter::Bilinear, wrap).eval(Vec2::new(u, v)).x;
        // Repeat: column -1 is column 1: (2 + 1) / 2.
        assert!((at(WrapMode::Repeat, 0.0, 0.25) - 1.5).abs() < 1e-6);
        // Mirror and clamp: column -1 is column 0: 1.
        assert!((at(WrapMode::Mirror, 0.0, 0.25) - 1.0).abs() < 1e-6);
        assert!((at(WrapMode::Clamp, 0.0, 0.25) - 1.0).abs() < 1e-6);
        // Nearest, by texel: u in [1, 1.5) is column 2: repeat 0, mirror 1 (2n-1-2 = 1), clamp 1.
        let near = |wrap, u: f32| image(Filter::Nearest, wrap).eval(Vec2::new(u, 0.1)).x;
        assert_eq!(near(WrapMode::Repeat, 1.2), 1.0);
        assert_eq!(near(WrapMode::Mirror, 1.2), 2.0);
        assert_eq!(near(WrapMode::Clamp, 1.2), 2.0);
        // Column 3 (u in [1.5, 2)): repeat 1, mirror 0, clamp 1.
        assert_eq!(near(WrapMode::Repeat, 1.7), 2.0);
        assert_eq!(near(WrapMode::Mirror, 1.7), 1.0);
        assert_eq!(near(WrapMode::Clamp, 1.7), 2.0);
        // Column -1 (u in [-0.5, 0)): repeat 1, mirror 0, clamp 0.
        assert_eq!(near(WrapMode::Repeat, -0.2), 2.0);
        assert_eq!(near(WrapMode::Mirror, -0.2), 1.0);
        assert_eq!(near(WrapMode::Clamp, -0.2), 1.0);
        // Rows likewise: v in [0.5, 1) is row 1 (red 3 at column 0).
        assert_eq!(
            image(Filter::Nearest, WrapMode::Repeat)
                .eval(Vec2::new(0.1, 0.6))
                .x,
            3.0
        );
        assert_eq!(
            image(Filter::Nearest, WrapMode::Repeat)
                .eval(Vec2::new(0.1, -0.4))
                .x,
            3.0
        );
        // Far coordinates and NaN stay inside the image.
        let r = image(Filter::Bilinear, WrapMode::Repeat);
        assert!(r.eval(Vec2::new(1e30, -1e30)).is_finite());
        assert!(r.eval(Vec2::new(f32::NAN, 0.5)).is_finite());
    }

    #[test]
    fn the_transform_scales_then_offsets() {
        let mut b = image(Filter::Nearest, WrapMode::Repeat);
        b.transform = UvTransform::scale_offset(Vec2::new(2.0, 1.0), Vec2::new(0.5, 0.0));
        // u = 0.1 -> 0.7: column 1.
        assert_eq!(b.eval(Vec2::new(0.1, 0.1)).x, 2.0);
        // u = 0.3 -> 1.1: column 0 of the next copy.
        assert_eq!(b.eval(Vec2::new(0.3, 0.1)).x, 1.0);
        assert!(close(b.mean(), Vec3::new(2.5, 0.5, 0.5)));
        assert_eq!(b.max_value(), 4.0);
        assert!(Bitmap::new(
            2,
            2,
            vec![Vec3::ONE; 3],
            Filter::Nearest,
            WrapMode::Clamp,
            UvTransform::IDENTITY
        )
        .is_none());
    }
}
