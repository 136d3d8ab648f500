//! The Beckmann microfacet distribution: normal density, Smith masking and sampling of the
//! normals, Mitsuba 3's default for its rough BSDFs.

use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Beckmann distribution of microfacet normals with roughness `alpha_x` along the local x
/// axis and `alpha_y` along y (isotropic when equal), in the local frame (`z` the macro
/// normal); microfacet normals `m` lie in the upper hemisphere.
///
/// - Normal density (Walter et al. 2007, eq. 25; anisotropic form Heitz 2014, "Understanding
///   the masking-shadowing function", eq. 83):
///   `D(m) = exp(-((mx/ax)^2 + (my/ay)^2) / mz^2) / (pi ax ay mz^4)` for `mz > 0`, so that
///   `integral D(m) mz dm = 1`. Its slopes `(-mx/mz, -my/mz)` are Gaussian with standard
///   deviations `ax / sqrt 2`, `ay / sqrt 2`.
/// - Smith's Lambda (Walter et al. 2007, eq. 27; Heitz 2014, eq. 80):
///   `Lambda(w) = (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi))`, `a = 1 / (alpha_w tan theta)`
///   with `alpha_w^2 tan^2 theta = (ax^2 wx^2 + ay^2 wy^2) / wz^2`; `G1(w, m) =
///   chi+((w . m) / (w . n)) / (1 + Lambda(w))`. Exact (Mitsuba 3 uses Walter's rational
///   approximation of G1, within 0.35 % of it).
/// - Masking-shadowing: separable, `G = G1(wo, m) G1(wi, m)`, as for [`super::Ggx`].
/// - Sampling: `m` with density `D(m) mz` (Walter et al. 2007, eqs. 28-29, in the slope form
///   that covers the anisotropic case): the slopes are Gaussian, drawn by Box-Muller,
///   `r^2 = -ln(1 - u1)`, `phi = 2 pi u2`, slope `= (ax r cos phi, ay r sin phi)`,
///   `m = normalize(-slope, 1)`; `D(m) mz dm` is the slope density's measure (Heitz 2014,
///   eq. 16), so the density over normals is `D(m) mz`. Independent of the view direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Beckmann {
    pub alpha_x: f32,
    pub alpha_y: f32,
}

impl Beckmann {
    /// The smallest roughness used, as [`super::Ggx::MIN_ALPHA`] (the density's peak is the
    /// same `1 / (pi alpha^2)`).
    pub const MIN_ALPHA: f32 = super::Ggx::MIN_ALPHA;

    /// A distribution of roughness `alpha_x` along x and `alpha_y` along y, each clamped to
    /// [`Beckmann::MIN_ALPHA`, 1e3] (the caller rejects non-finite or negative values).
    pub fn new(alpha_x: f32, alpha_y: f32) -> Self {
        Beckmann {
            alpha_x: alpha_x.clamp(Self::MIN_ALPHA, 1e3),
            alpha_y: alpha_y.clamp(Self::MIN_ALPHA, 1e3),
        }
    }

    /// An isotropic distribution of roughness `alpha`.
    pub fn isotropic(alpha: f32) -> Self {
        Self::new(alpha, alpha)
    }

    /// The normal density D(m); zero for `m` in the lower hemisphere.
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let (x, y) = (m.x / self.alpha_x, m.y / self.alpha_y);
        let cos2 = m.z * m.z;
        let d = (-(x * x + y * y) / cos2).exp() / (PI * self.alpha_x * self.alpha_y * cos2 * cos2);
        // The Gaussian tail is flushed to zero below 1e-20, so that a BSDF value and its pdf
        // (D times different factors) vanish together instead of one of them underflowing.
        if d.is_finite() && d >= 1e-20 {
            d
        } else {
            0.0
        }
    }

    /// Smith's Lambda(w), the same for `w` and `-w` (computed in f64: erf(a) - 1 cancels).
    #[inline]
    pub fn lambda(&self, w: Vec3) -> f32 {
        let (x, y) = ((self.alpha_x * w.x) as f64, (self.alpha_y * w.y) as f64);
        let xy2 = x * x + y * y;
        if xy2 == 0.0 {
            return 0.0;
        }
        let a = (w.z as f64).abs() / xy2.sqrt();
        if a == 0.0 {
            return f32::INFINITY;
        }
        // (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi)) = (exp(-a^2) / (a sqrt(pi)) - erfc(a)) / 2.
        let l = 0.5 * ((-a * a).exp() / (a * std::f64::consts::PI.sqrt()) - erfc(a));
        if l.is_finite() {
            l.max(0.0) as f32
        } else {
            f32::INFINITY
        }
    }

    /// Masking of one direction by microfacets of normal `m`: 1 / (1 + Lambda(w)) where `w`
    /// sees the front of `m` from the side of the macro surface it is on, else 0.
    #[inline]
    pub fn g1(&self, w: Vec3, m: Vec3) -> f32 {
        if w.dot(m) * w.z <= 0.0 {
            return 0.0;
        }
        1.0 / (1.0 + self.lambda(w))
    }

    /// A normal with density `D(m) mz` ([`Beckmann::pdf`]).
    #[inline]
    pub fn sample(&self, u: Vec2) -> Vec3 {
        // 1 - u1 is in (0, 1]: r is finite.
        let r = (-(1.0 - u.x).ln()).max(0.0).sqrt();
        let (sin_phi, cos_phi) = (2.0 * PI * u.y).sin_cos();
        let slope = Vec2::new(self.alpha_x * r * cos_phi, self.alpha_y * r * sin_phi);
        Vec3::new(-slope.x, -slope.y, 1.0).normalize()
    }

    /// Density of [`Beckmann::sample`] over the normals (solid angle): `D(m) mz`.
    #[inline]
    pub fn pdf(&self, m: Vec3) -> f32 {
        self.d(m) * m.z.max(0.0)
    }
}

/// The complementary error function `erfc(x) = 1 - erf(x)` for `x >= 0`, with relative error
/// below 1.2e-7 (Press et al., Numerical Recipes, 2nd ed., sec. 6.2, `erfcc`: a Chebyshev fit
/// of `erfc(x) exp(x^2)` in `t = 1 / (1 + x / 2)`).
fn erfc(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.5 * x);
    let poly = -1.26551223
        + t * (1.00002368
            + t * (0.37409196
                + t * (0.09678418
                    + t * (-0.18628806
                        + t * (0.27886807
                            + t * (-1.13520398
                                + t * (1.48851587 + t * (-0.82215223 + t * 0.17087277))))))));
    t * (-x * x + poly).exp()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{uniform_sphere, Rng};

    #[test]
    fn erfc_matches_tabulated_values() {
        // erfc at 0, 0.5, 1, 2 and 4 (Abramowitz & Stegun, table 7.1, to 16 digits).
        for (x, v) in [
            (0.0, 1.0),
            (0.5, 0.479_500_122_186_953_5),
            (1.0, 0.157_299_207_050_285_13),
            (2.0, 0.004_677_734_981_047_266),
            (4.0, 1.541_725_790_028_002e-8),
        ] {
            assert!((erfc(x) - v).abs() <= 1.2e-7 * v, "erfc({x}) = {}", erfc(x));
        }
    }

    /// D is normalised, integral of D(m) m.z dm = 1, and the visible microfacets project to
    /// the macro surface's area seen from any direction, integral of
    /// G1(w, m) max(0, w . m) D(m) dm = w.z (Heitz 2014, eq. 7): the second holds only with
    /// the right Lambda. By uniform sphere sampling.
    #[test]
    fn normals_are_normalised_and_visible_projected_area_is_the_surface() {
        for (ax, ay) in [(0.2, 0.2), (0.5, 0.5), (1.0, 1.0), (0.3, 0.8)] {
            let dist = Beckmann::new(ax, ay);
            let mut rng = Rng::new(7, 0, 0);
            for w in [
                Vec3::new(0.6, 0.3, 0.5).normalize(),
                Vec3::new(0.2, 0.95, 0.1).normalize(),
            ] {
                let n = 1_000_000;
                let (mut norm, mut visible) = (0.0f64, 0.0f64);
                for _ in 0..n {
                    let m = uniform_sphere(rng.uniform2());
                    norm += (dist.d(m) * m.z.max(0.0)) as f64;
                    visible += (dist.g1(w, m) * w.dot(m).max(0.0) * dist.d(m)) as f64;
                }
                let scale = 4.0 * std::f64::consts::PI / n as f64;
                let (norm, visible) = (norm * scale, visible * scale);
                assert!(
                    (norm - 1.0).abs() < 0.02,
                    "{ax} {ay}: integral D cos = {norm}"
                );
                assert!(
                    (visible - w.z as f64).abs() < 0.02 * w.z as f64,
                    "{ax} {ay} {w}: visible projected area {visible} != {}",
                    w.z
                );
            }
        }
    }

    /// The sampled normals have the density `pdf`: the mean of `g(m) / pdf(m)` over samples is
    /// the integral of g, here of `D(m) mz` restricted to a cone (uniform sphere estimate).
    #[test]
    fn sampled_normals_follow_their_pdf() {
        let dist = Beckmann::new(0.3, 0.6);
        let mut rng = Rng::new(11, 0, 0);
        let n = 400_000;
        let cone = |m: Vec3| m.z > 0.9 && m.x > 0.0;
        let hits = (0..n).filter(|_| cone(dist.sample(rng.uniform2()))).count();
        let mut reference = 0.0f64;
        for _ in 0..n {
            let m = uniform_sphere(rng.uniform2());
            if cone(m) {
                reference += dist.pdf(m) as f64;
            }
        }
        let reference = reference * 4.0 * std::f64::consts::PI / n as f64;
        let fraction = hits as f64 / n as f64;
        assert!(
            (fraction - reference).abs() < 0.01,
            "sampled fraction {fraction} vs integral of pdf {reference}"
        );
    }
}
