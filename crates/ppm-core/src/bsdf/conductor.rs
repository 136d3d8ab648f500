//! Conductors: smooth (a Fresnel-weighted mirror) and rough (GGX or Beckmann microfacets).

use super::microfacet::Microfacet;
use super::{fresnel_conductor, reflect, BsdfFlags, BsdfSample, Lobe};
use glam::{Vec2, Vec3};

/// A conductor of complex relative index `eta + i k` per channel, its reflection tinted by
/// `specular_reflectance` (Mitsuba 3's `conductor` and `roughconductor`).
///
/// One-sided like Mitsuba's: it reflects only light arriving from the side of the normal
/// (`wo.z > 0`, `wi.z > 0`) and is black from behind (wrap it in
/// [`super::TwoSided`] for both sides).
///
/// - Smooth (`roughness` None): the delta `F(cos_o) R delta(wi - reflect(wo)) / cos(wi)`,
///   with F the conductor Fresnel reflectance ([`fresnel_conductor`]) and R the tint; `sample`
///   returns it with weight `F R` and discrete probability 1.
/// - Rough: the microfacet BRDF of Walter et al. 2007 (eq. 20) with a [`Microfacet`] D and G,
///   `f(wo, wi) = R F(wo . h) D(h) G(wo, wi, h) / (4 cos_o cos_i)`, `h = normalize(wo + wi)`.
///   `sample` draws a normal `m` by [`Microfacet::sample_m`] (GGX: visible from `wo`,
///   `m ~ D_wo`; Beckmann: `m ~ D(m) mz`) and reflects `wo` about it; the density of `wi` is
///   `pdf_m(h) / (4 |wo . h|)` (Walter et al. 2007, eq. 14, the reflection Jacobian), for GGX
///   `G1(wo, h) D(h) / (4 cos_o)` with the weight `R F(wo . h) G1(wi, h)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    /// Real part of the relative index of refraction, per channel.
    pub eta: Vec3,
    /// Imaginary part (extinction coefficient), per channel.
    pub k: Vec3,
    /// Tint multiplying the Fresnel reflectance (1 for a physical conductor).
    pub specular_reflectance: Vec3,
    /// The microfacet distribution; `None` for a smooth conductor.
    pub roughness: Option<Microfacet>,
}

impl Conductor {
    /// A smooth conductor's delta reflection, or a rough one's glossy reflection; none when
    /// the tint is black.
    #[inline]
    pub fn flags(&self) -> BsdfFlags {
        if self.specular_reflectance.max_element() <= 0.0 {
            return BsdfFlags::NONE;
        }
        let kind = if self.roughness.is_some() {
            BsdfFlags::GLOSSY
        } else {
            BsdfFlags::SPECULAR
        };
        kind | BsdfFlags::REFLECTION
    }

    /// The Fresnel reflectance times the tint at incidence cosine `cos`.
    #[inline]
    fn reflectance(&self, cos: f32) -> Vec3 {
        self.specular_reflectance * fresnel_conductor(cos, self.eta, self.k)
    }

    /// f(wo, wi) without the cosine; zero for a smooth conductor and across the surface.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let Some(dist) = &self.roughness else {
            return Vec3::ZERO;
        };
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let h = (wo + wi).normalize();
        let dg = dist.d(h) * dist.g(wo, wi, h);
        if dg <= 0.0 || !h.is_finite() {
            return Vec3::ZERO;
        }
        // F at the mean of the two equal cosines, so that f(wi, wo) rounds as f(wo, wi).
        let f = self.reflectance(0.5 * (wo.dot(h) + wi.dot(h))) * (dg / (4.0 * wo.z * wi.z));
        if f.is_finite() {
            f
        } else {
            Vec3::ZERO
        }
    }

    /// `G1(wo, h) D(h) / (4 cos_o)` for the rough conductor; zero for a smooth one.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some(dist) = &self.roughness else {
            return 0.0;
        };
        reflection_pdf(dist, wo, wi)
    }

    /// The mirror direction (smooth) or a reflection about a visible normal (rough).
    #[inline]
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 || self.flags().is_empty() {
            return None;
        }
        let Some(dist) = &self.roughness else {
            return Some(BsdfSample {
                wi: reflect(wo),
                weight: self.reflectance(wo.z),
                pdf: 1.0,
                lobe: Lobe::Specular,
            });
        };
        let m = dist.sample_m(wo, u);
        let wi = 2.0 * wo.dot(m) * m - wo;
        glossy_sample(wi, self.pdf(wo, wi), self.eval(wo, wi))
    }
}

/// Density of reflecting `wo` about a normal drawn by [`Microfacet::sample_m`], at `wi`:
/// `pdf_m(wo, h) / (4 |wo . h|)` (for GGX `G1(wo, h) D(h) / (4 cos_o)`), for both directions
/// above the surface.
#[inline]
pub(super) fn reflection_pdf(dist: &Microfacet, wo: Vec3, wi: Vec3) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let h = (wo + wi).normalize();
    let pdf = dist.reflection_pdf_h(wo, h);
    if pdf.is_finite() {
        pdf
    } else {
        0.0
    }
}

/// A glossy sample `wi` with its pdf and f (without the cosine), the weight f |cos| / pdf:
/// `None` where the pdf is zero (below the horizon, or outside the support by rounding).
#[inline]
pub(super) fn glossy_sample(wi: Vec3, pdf: f32, f: Vec3) -> Option<BsdfSample> {
    if !(pdf > 0.0 && pdf.is_finite() && wi.is_finite()) {
        return None;
    }
    let weight = f * wi.z.abs() / pdf;
    if !weight.is_finite() {
        return None;
    }
    Some(BsdfSample {
        wi,
        weight,
        pdf,
        lobe: Lobe::Glossy,
    })
}
