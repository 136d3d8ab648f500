//! Random numbers, warps from the unit square, orthonormal frames and discrete distributions.
//!
//! Randomness is keyed, never tied to a thread: [`Rng::new`] takes `(seed, iteration, index)`
//! where the index is a pixel or a light path, so the same seed renders the same image at any
//! thread count.

use glam::{Vec2, Vec3};
use rand::RngCore;
use rand_pcg::Pcg32;
use std::f32::consts::{FRAC_1_PI, PI};

/// A small, fast generator (PCG32) keyed by seed, iteration and sample index.
#[derive(Clone, Debug)]
pub struct Rng(Pcg32);

/// SplitMix64 finaliser: spreads nearby keys (iteration 1, 2, 3...) over the whole state space.
fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl Rng {
    /// The stream for one `index` (pixel or light path) of one `iteration` of a render with `seed`.
    pub fn new(seed: u64, iteration: u64, index: u64) -> Self {
        let state = mix64(seed ^ mix64(iteration.wrapping_add(0x5851_f42d)));
        // PCG streams are selected by an odd increment; distinct indices give distinct streams.
        Rng(Pcg32::new(state, mix64(index)))
    }

    /// A uniform number in [0, 1), with 24 bits of resolution so that it never rounds to 1.
    #[inline]
    pub fn uniform(&mut self) -> f32 {
        (self.0.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Two uniform numbers in [0, 1).
    #[inline]
    pub fn uniform2(&mut self) -> Vec2 {
        Vec2::new(self.uniform(), self.uniform())
    }
}

/// An orthonormal basis whose `z` axis is a given unit normal (Duff et al. 2017, branchless).
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    pub x: Vec3,
    pub y: Vec3,
    pub z: Vec3,
}

impl Frame {
    /// A frame around the unit vector `n`.
    #[inline]
    pub fn new(n: Vec3) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        Frame {
            x: Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
            y: Vec3::new(b, sign + n.y * n.y * a, -n.y),
            z: n,
        }
    }

    /// World to local coordinates.
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.x), v.dot(self.y), v.dot(self.z))
    }

    /// Local to world coordinates.
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.x * v.x + self.y * v.y + self.z * v.z
    }
}

/// Cosine-weighted direction on the +z hemisphere (Malley's method on a concentric disc).
/// pdf(w) = cos(theta) / pi.
#[inline]
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = concentric_disc(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// The pdf of [`cosine_hemisphere`] with respect to solid angle.
#[inline]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * FRAC_1_PI
}

/// Shirley-Chiu concentric map of the unit square onto the unit disc (area preserving).
#[inline]
pub fn concentric_disc(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    // The angle is pi/4 times a ratio in [-1, 1] (in the second wedge pi/2 minus it, whose
    // cosine and sine are the sine and cosine of the small angle), so a quarter-range sincos
    // does, cheaper than libm's sincosf with its general range reduction (this runs for every
    // diffuse bounce).
    if o.x.abs() > o.y.abs() {
        let (sin, cos) = sin_cos_quarter((PI / 4.0) * (o.y / o.x));
        o.x * Vec2::new(cos, sin)
    } else {
        let (sin, cos) = sin_cos_quarter((PI / 4.0) * (o.x / o.y));
        o.y * Vec2::new(sin, cos)
    }
}

/// `(sin x, cos x)` for |x| <= pi/4: the Taylor polynomials to degree 9 and 8. The first
/// terms left out, x^11 / 11! < 2e-9 and x^10 / 10! < 3e-8, are below a quarter of an f32
/// ulp of the results there (the cosine lies in [0.7, 1]), so the error is that of the
/// Horner evaluation: within 2 ulps (tested against f64).
#[inline]
fn sin_cos_quarter(x: f32) -> (f32, f32) {
    let x2 = x * x;
    let sin = x
        * (1.0
            + x2 * (-1.0 / 6.0
                + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362_880.0)))));
    let cos = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40_320.0))));
    (sin, cos)
}

/// Uniform direction on the unit sphere; pdf = 1 / (4 pi).
#[inline]
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Uniform barycentrics (b1, b2) on a triangle; the point is v0 + b1 e1 + b2 e2; pdf = 1 / area.
#[inline]
pub fn uniform_triangle(u: Vec2) -> Vec2 {
    // Square-root parameterisation (pbrt 4, sec. A.5.5): no rejection, monotone in u.
    let su = u.x.sqrt();
    Vec2::new(1.0 - su, u.y * su)
}

/// Veach's power heuristic (beta = 2) for one sample of strategy f among strategies f and g.
/// w_f = pdf_f^2 / (pdf_f^2 + pdf_g^2); both pdfs in the same measure (solid angle here).
#[inline]
pub fn power_heuristic(pdf_f: f32, pdf_g: f32) -> f32 {
    let f2 = pdf_f * pdf_f;
    let g2 = pdf_g * pdf_g;
    if f2 == 0.0 {
        return 0.0;
    }
    if !f2.is_finite() {
        return 1.0;
    }
    f2 / (f2 + g2)
}

/// A discrete distribution proportional to non-negative weights (light selection by power).
#[derive(Clone, Debug, Default)]
pub struct Distribution1D {
    /// cdf[i] = sum of the normalised weights before i; cdf has len + 1 entries, ending at 1.
    cdf: Vec<f32>,
    pmf: Vec<f32>,
}

impl Distribution1D {
    /// The distribution over `weights`; all-zero (or empty) weights give an empty distribution.
    pub fn new(weights: &[f32]) -> Self {
        let total: f64 = weights.iter().map(|&w| w.max(0.0) as f64).sum();
        if total <= 0.0 || !total.is_finite() {
            return Self::default();
        }
        let mut cdf = Vec::with_capacity(weights.len() + 1);
        let mut pmf = Vec::with_capacity(weights.len());
        let mut acc = 0.0f64;
        cdf.push(0.0);
        for &w in weights {
            let p = w.max(0.0) as f64 / total;
            acc += p;
            pmf.push(p as f32);
            cdf.push(acc as f32);
        }
        *cdf.last_mut().unwrap() = 1.0;
        Distribution1D { cdf, pmf }
    }

    /// Number of entries.
    pub fn len(&self) -> usize {
        self.pmf.len()
    }

    /// True when nothing can be sampled.
    pub fn is_empty(&self) -> bool {
        self.pmf.is_empty()
    }

    /// Probability of choosing entry `i`.
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        self.pmf.get(i).copied().unwrap_or(0.0)
    }

    /// Chooses an entry with `u` in [0, 1); returns (index, pmf). Never returns a zero-pmf entry.
    #[inline]
    pub fn sample(&self, u: f32) -> (usize, f32) {
        // First i with cdf[i + 1] > u.
        let n = self.pmf.len();
        let mut i = self.cdf[1..].partition_point(|&c| c <= u).min(n - 1);
        while self.pmf[i] == 0.0 && i > 0 {
            i -= 1;
        }
        (i, self.pmf[i])
    }

    /// As [`Distribution1D::sample`], with `u` also remapped into the chosen entry: (index,
    /// pmf, (u - cdf_i) / pmf_i in [0, 1)), so that one uniform number both chooses the entry
    /// and places a point inside it (a piecewise-constant density over [0, len)).
    #[inline]
    pub fn sample_continuous(&self, u: f32) -> (usize, f32, f32) {
        let (i, pmf) = self.sample(u);
        let t = ((u - self.cdf[i]) / pmf).clamp(0.0, 1.0 - f32::EPSILON / 2.0);
        (i, pmf, if t.is_nan() { 0.5 } else { t })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_sin_cos_is_within_a_few_ulps_of_libm() {
        let n = 200_000;
        for i in 0..=n {
            let x = (-1.0 + 2.0 * i as f32 / n as f32) * (PI / 4.0);
            let (sin, cos) = sin_cos_quarter(x);
            let (sin64, cos64) = (x as f64).sin_cos();
            // Relative error in units of f32 epsilon; the sine is relative to itself (exact
            // to the last bits near 0 too).
            let sin_err = (sin as f64 - sin64).abs() / sin64.abs().max(f64::MIN_POSITIVE);
            let cos_err = (cos as f64 - cos64).abs() / cos64;
            let eps = f32::EPSILON as f64;
            assert!(sin_err <= 2.0 * eps, "sin({x}): {sin} vs {sin64}");
            assert!(cos_err <= 2.0 * eps, "cos({x}): {cos} vs {cos64}");
        }
        assert_eq!(sin_cos_quarter(0.0), (0.0, 1.0));
    }

    #[test]
    fn concentric_disc_matches_the_polar_form() {
        // Shirley-Chiu in its textbook form, in f64.
        let reference = |u: Vec2| {
            let (x, y) = (2.0 * u.x as f64 - 1.0, 2.0 * u.y as f64 - 1.0);
            let quarter = std::f64::consts::FRAC_PI_4;
            let (r, theta) = if x.abs() > y.abs() {
                (x, quarter * (y / x))
            } else {
                (y, 2.0 * quarter - quarter * (x / y))
            };
            (r * theta.cos(), r * theta.sin())
        };
        let n = 300;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new(i as f32 + 0.5, j as f32 + 0.5) / n as f32;
                let d = concentric_disc(u);
                let (x, y) = reference(u);
                assert!(
                    (d.x as f64 - x).abs() <= 4e-7 && (d.y as f64 - y).abs() <= 4e-7,
                    "u = {u}: {d} vs ({x}, {y})"
                );
                assert!(d.length_squared() <= 1.0 + 4.0 * f32::EPSILON);
            }
        }
        assert_eq!(concentric_disc(Vec2::splat(0.5)), Vec2::ZERO);
    }

    #[test]
    fn rng_streams_are_keyed_and_deterministic() {
        let a: Vec<f32> = (0..4).map(|_| Rng::new(7, 1, 3).uniform()).collect();
        assert!(a.windows(2).all(|w| w[0] == w[1]));
        let mut r1 = Rng::new(7, 1, 3);
        let mut r2 = Rng::new(7, 1, 4);
        let mut r3 = Rng::new(7, 2, 3);
        let x1 = r1.uniform();
        assert_ne!(x1, r2.uniform());
        assert_ne!(x1, r3.uniform());
    }

    #[test]
    fn uniform_is_in_unit_interval_with_right_mean() {
        let mut rng = Rng::new(1, 0, 0);
        let n = 200_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let u = rng.uniform();
            assert!((0.0..1.0).contains(&u));
            sum += u as f64;
        }
        // Standard error of the mean is sqrt(1/12/n) ~ 6.5e-4; 5 sigma.
        assert!((sum / n as f64 - 0.5).abs() < 3.3e-3);
    }

    #[test]
    fn frame_is_orthonormal() {
        let mut rng = Rng::new(2, 0, 0);
        for _ in 0..1000 {
            let n = uniform_sphere(rng.uniform2());
            let f = Frame::new(n);
            assert!((f.x.length() - 1.0).abs() < 1e-4);
            assert!((f.y.length() - 1.0).abs() < 1e-4);
            assert!(
                f.x.dot(f.y).abs() < 1e-4 && f.x.dot(n).abs() < 1e-4 && f.y.dot(n).abs() < 1e-4
            );
            let v = uniform_sphere(rng.uniform2());
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-4);
        }
    }

    #[test]
    fn cosine_hemisphere_has_mean_cosine_two_thirds() {
        // E[cos] under pdf cos/pi is (1/pi) * integral cos^2 dw = 2/3.
        let mut rng = Rng::new(3, 0, 0);
        let n = 200_000;
        let mean: f64 = (0..n)
            .map(|_| cosine_hemisphere(rng.uniform2()).z as f64)
            .sum::<f64>()
            / n as f64;
        assert!((mean - 2.0 / 3.0).abs() < 3e-3, "{mean}");
    }

    #[test]
    fn distribution_matches_weights_and_skips_zeros() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0]);
        assert_eq!(d.pmf(1), 0.0);
        assert!((d.pmf(2) - 0.75).abs() < 1e-6);
        let mut counts = [0u32; 3];
        let mut rng = Rng::new(4, 0, 0);
        for _ in 0..100_000 {
            counts[d.sample(rng.uniform()).0] += 1;
        }
        assert_eq!(counts[1], 0);
        assert!((counts[2] as f32 / 100_000.0 - 0.75).abs() < 0.01);
        assert!(Distribution1D::new(&[0.0, 0.0]).is_empty());
    }
}
