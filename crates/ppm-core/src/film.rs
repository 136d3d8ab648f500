//! Accumulation of per-iteration estimates into an image (no file formats here).

use glam::Vec3;

/// A linear RGB image, row-major from the top-left pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
}

impl Image {
    /// A black image.
    pub fn new(width: u32, height: u32) -> Self {
        Image {
            width,
            height,
            pixels: vec![Vec3::ZERO; (width * height) as usize],
        }
    }

    /// The pixel at column x, row y.
    pub fn get(&self, x: u32, y: u32) -> Vec3 {
        self.pixels[(y * self.width + x) as usize]
    }

    /// Mean over all pixels, per channel (summed in f64).
    pub fn mean(&self) -> Vec3 {
        let mut s = [0.0f64; 3];
        for p in &self.pixels {
            s[0] += p.x as f64;
            s[1] += p.y as f64;
            s[2] += p.z as f64;
        }
        let n = self.pixels.len().max(1) as f64;
        Vec3::new((s[0] / n) as f32, (s[1] / n) as f32, (s[2] / n) as f32)
    }
}

/// The running average of one estimate per pixel per iteration.
///
/// Sums are kept in f64: after 10^5 iterations of values near 1 an f32 sum would have lost
/// about 7 of its 24 bits, an f64 sum loses nothing that matters.
#[derive(Clone, Debug)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    sum: Vec<[f64; 3]>,
    iterations: u64,
    /// Samples dropped because they were NaN or infinite.
    rejected: u64,
    /// (iteration, pixel) of the first dropped sample: random streams are keyed by them, so
    /// the offending path can be traced again in isolation.
    first_rejected: Option<(u64, u32)>,
}

impl Film {
    /// An empty film.
    pub fn new(width: u32, height: u32) -> Self {
        Film {
            width,
            height,
            sum: vec![[0.0; 3]; (width * height) as usize],
            iterations: 0,
            rejected: 0,
            first_rejected: None,
        }
    }

    /// Adds one iteration: one estimate per pixel, row-major. Non-finite or negative estimates
    /// are dropped (counted in [`Film::rejected`]) and count as zero.
    pub fn add_iteration(&mut self, estimates: &[Vec3]) {
        assert_eq!(estimates.len(), self.sum.len());
        for (pixel, (s, e)) in self.sum.iter_mut().zip(estimates).enumerate() {
            if e.is_finite() && e.min_element() >= 0.0 {
                s[0] += e.x as f64;
                s[1] += e.y as f64;
                s[2] += e.z as f64;
            } else {
                self.rejected += 1;
                self.first_rejected
                    .get_or_insert((self.iterations, pixel as u32));
            }
        }
        self.iterations += 1;
    }

    /// Adds to the rejected-sample count (for samples dropped before they reached the film).
    pub fn count_rejected(&mut self, n: u64) {
        self.rejected += n;
    }

    /// Iterations accumulated.
    pub fn iterations(&self) -> u64 {
        self.iterations
    }

    /// Non-finite samples dropped so far.
    pub fn rejected(&self) -> u64 {
        self.rejected
    }

    /// (iteration, pixel) of the first sample dropped as NaN, infinite or negative.
    pub fn first_rejected(&self) -> Option<(u64, u32)> {
        self.first_rejected
    }

    /// The average of all iterations (black before the first).
    pub fn image(&self) -> Image {
        let inv = 1.0 / self.iterations.max(1) as f64;
        Image {
            width: self.width,
            height: self.height,
            pixels: self
                .sum
                .iter()
                .map(|s| {
                    Vec3::new(
                        (s[0] * inv) as f32,
                        (s[1] * inv) as f32,
                        (s[2] * inv) as f32,
                    )
                })
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn average_and_rejection() {
        let mut film = Film::new(2, 1);
        film.add_iteration(&[Vec3::ONE, Vec3::splat(3.0)]);
        film.add_iteration(&[Vec3::splat(f32::NAN), Vec3::splat(1.0)]);
        let img = film.image();
        assert_eq!(img.pixels[0], Vec3::splat(0.5));
        assert_eq!(img.pixels[1], Vec3::splat(2.0));
        assert_eq!(film.rejected(), 1);
    }

    #[test]
    fn long_accumulation_keeps_precision() {
        // 10^5 iterations of a value that f32 cannot represent exactly: the mean must stay
        // within 1e-6 relative of the exact value.
        let mut film = Film::new(1, 1);
        let v = Vec3::splat(0.1);
        for _ in 0..100_000 {
            film.add_iteration(&[v]);
        }
        let m = film.image().pixels[0].x as f64;
        assert!((m - 0.1f32 as f64).abs() / 0.1 < 1e-6, "{m}");
    }
}
