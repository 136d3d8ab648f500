//! Lambertian plus the normalized modified Phong lobe (Lafortune & Willems 1994).

use super::{luminance, reflect, BsdfFlags, BsdfSample, Diffuse, Lobe};
use crate::sampling::{cosine_hemisphere, Frame};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

/// `diffuse / pi + specular (n + 2) / (2 pi) max(0, cos(alpha))^n`, with alpha the angle
/// between `wi` and the mirror direction `reflect(wo)`. The (n + 2) / (2 pi) normalisation makes
/// the glossy albedo exactly `specular` at normal incidence and smaller elsewhere, so
/// `diffuse + specular <= 1` conserves energy. Two-sided like [`super::Diffuse`].
///
/// Either coefficient may be zero (the glossy part, [`Phong::glossy_part`], is a copy with
/// `diffuse = 0`); the lobe is then never sampled and not among the flags.
#[derive(Clone, Copy, Debug)]
pub struct Phong {
    /// Lambertian albedo.
    pub diffuse: Vec3,
    /// Glossy albedo at normal incidence.
    pub specular: Vec3,
    /// Phong exponent n >= 0; larger is shinier.
    pub exponent: f32,
}

impl Phong {
    /// The largest exponent rendered; larger ones are rendered as this one.
    ///
    /// The lobe's half width at half maximum, from cos^n(alpha) = 1/2, is about
    /// sqrt(2 ln 2 / n): 1.2e-5 rad (0.0007 degrees) here, below a pixel of any image but a
    /// telephoto one. Its peak pdf (n + 1) / (2 pi), 1.6e9, keeps the squares of pdfs and pdf
    /// ratios that vcm's power heuristic multiplies along a path within f32's range; at
    /// n = 1e20 they overflow, and weights become 0 or NaN.
    pub const MAX_EXPONENT: f32 = 1e10;

    /// A Phong BSDF; the caller ensures `diffuse + specular <= 1` per channel. An exponent
    /// above [`Phong::MAX_EXPONENT`] is rendered as that.
    pub fn new(diffuse: Vec3, specular: Vec3, exponent: f32) -> Self {
        Phong {
            diffuse,
            specular,
            exponent: exponent.min(Self::MAX_EXPONENT),
        }
    }

    /// A diffuse lobe where `diffuse` is non-zero, a glossy one where `specular` is; both
    /// reflect.
    #[inline]
    pub fn flags(&self) -> BsdfFlags {
        let mut flags = BsdfFlags::NONE;
        if self.diffuse.max_element() > 0.0 {
            flags |= BsdfFlags::DIFFUSE | BsdfFlags::REFLECTION;
        }
        if self.specular.max_element() > 0.0 {
            flags |= BsdfFlags::GLOSSY | BsdfFlags::REFLECTION;
        }
        flags
    }

    /// The Lambertian lobe `diffuse / pi`, if `diffuse` is non-zero.
    #[inline]
    pub fn diffuse_part(&self) -> Option<Diffuse> {
        (self.diffuse.max_element() > 0.0).then_some(Diffuse {
            albedo: self.diffuse,
        })
    }

    /// The glossy lobe alone (this model with `diffuse = 0`), if `specular` is non-zero.
    #[inline]
    pub fn glossy_part(&self) -> Option<Phong> {
        (self.specular.max_element() > 0.0).then_some(Phong {
            diffuse: Vec3::ZERO,
            ..*self
        })
    }

    /// Probability of sampling the glossy lobe, proportional to its albedo.
    #[inline]
    pub(super) fn glossy_probability(&self) -> f32 {
        let (d, s) = (luminance(self.diffuse), luminance(self.specular));
        if s <= 0.0 {
            0.0
        } else {
            s / (d + s)
        }
    }

    /// max(0, cos(alpha))^n, alpha between `wi` and the mirror direction r of `wo`. The dot
    /// product with r = `reflect(wo)` is the same in the flipped frame, so it serves both sides.
    /// Zero for alpha >= 90 degrees even when n = 0 (where powf would give 0^0 = 1).
    #[inline]
    fn cos_alpha_pow(&self, wo: Vec3, wi: Vec3) -> f32 {
        let r = reflect(wo);
        if r.dot(wi) <= 0.0 {
            return 0.0;
        }
        // cos(alpha) = 1 - |r - wi|^2 / 2, so cos^n = exp(n ln(1 - |r - wi|^2 / 2)). Near the
        // peak cos(alpha) rounds to 1 in f32, which would cost cos^1000 four digits; the chord
        // length keeps them.
        // Directions a few ulps off unit length can make h >= 1 although r . wi > 0 (alpha
        // a hair under 90 degrees): ln_1p(-h) would then be -inf or NaN. cos^n is 0 there.
        let h = 0.5 * (r - wi).length_squared();
        if h >= 1.0 {
            return 0.0;
        }
        (self.exponent * (-h).ln_1p()).exp()
    }

    /// f(wo, wi) without the cosine; zero across the surface.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z * wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let n = self.exponent;
        let glossy = (n + 2.0) * (0.5 * FRAC_1_PI) * self.cos_alpha_pow(wo, wi);
        self.diffuse * FRAC_1_PI + self.specular * glossy
    }

    /// The mixture density of [`Phong::sample`]:
    /// `(1 - p_s) |cos(wi)| / pi + p_s (n + 1) / (2 pi) max(0, cos(alpha))^n`
    /// on `wo`'s side, with p_s the glossy-lobe probability.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z * wi.z <= 0.0 {
            return 0.0;
        }
        let p_s = self.glossy_probability();
        if luminance(self.diffuse) <= 0.0 && p_s <= 0.0 {
            return 0.0;
        }
        let n = self.exponent;
        let diffuse = wi.z.abs() * FRAC_1_PI;
        let glossy = (n + 1.0) * (0.5 * FRAC_1_PI) * self.cos_alpha_pow(wo, wi);
        (1.0 - p_s) * diffuse + p_s * glossy
    }

    /// Picks a lobe with `u_lobe` (glossy with probability p_s), then samples
    /// cos(wi) / pi or (n + 1) / (2 pi) cos^n(alpha) around the mirror direction.
    /// The weight is f |cos(wi)| / mixture pdf. `None` below the horizon.
    #[inline]
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 || (luminance(self.diffuse) <= 0.0 && luminance(self.specular) <= 0.0) {
            return None;
        }
        let p_s = self.glossy_probability();
        let (wi, lobe) = if u_lobe < p_s {
            // cos(alpha) = u^(1 / (n + 1)) inverts the cdf 1 - cos^(n+1) of the lobe; computed
            // as 1 - h with h = -expm1(ln(u) / (n + 1)) so that small angles keep their digits.
            let h = -(u.x.ln() / (self.exponent + 1.0)).exp_m1();
            let cos_a = 1.0 - h;
            let sin_a = (h * (2.0 - h)).max(0.0).sqrt();
            let phi = 2.0 * PI * u.y;
            let local = Vec3::new(sin_a * phi.cos(), sin_a * phi.sin(), cos_a);
            (Frame::new(reflect(wo)).to_world(local), Lobe::Glossy)
        } else {
            let mut wi = cosine_hemisphere(u);
            wi.z = wi.z.copysign(wo.z);
            (wi, Lobe::Diffuse)
        };
        // A glossy sample may fall through the surface: it is lost (pdf keeps its mass).
        if wo.z * wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf(wo, wi);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let weight = self.eval(wo, wi) * wi.z.abs() / pdf;
        Some(BsdfSample {
            wi,
            weight,
            pdf,
            lobe,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{uniform_sphere, Rng};

    #[test]
    fn finite_when_wi_is_almost_perpendicular_to_the_mirror_direction() {
        // Found in a render (1 sample in 10^8 was NaN): a light direction a few ulps longer
        // than 1, nearly perpendicular to reflect(wo), gave h > 1 and ln_1p(-h) = NaN.
        let mut rng = Rng::new(11, 0, 0);
        for exponent in [0.0, 1.0, 30.0, 1000.0] {
            let phong = Phong::new(Vec3::splat(0.2), Vec3::splat(0.7), exponent);
            for _ in 0..100_000 {
                let mut wo = uniform_sphere(rng.uniform2());
                wo.z = wo.z.abs().max(1e-3);
                let wo = wo.normalize();
                let r = reflect(wo);
                let perp = r.any_orthonormal_vector();
                let lean = (rng.uniform() - 0.5) * 1e-6;
                let stretch = 1.0 + (rng.uniform() - 0.5) * 8.0 * f32::EPSILON;
                let wi = (perp + r * lean).normalize() * stretch;
                let (f, pdf) = (phong.eval(wo, wi), phong.pdf(wo, wi));
                assert!(
                    f.is_finite() && f.min_element() >= 0.0,
                    "n {exponent}: f {f}"
                );
                assert!(pdf.is_finite() && pdf >= 0.0, "n {exponent}: pdf {pdf}");
            }
        }
    }
}
