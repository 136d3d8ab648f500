//! Plastic: a dielectric coating, smooth or rough, over a Lambertian base.

use super::conductor::{glossy_sample, reflection_pdf};
use super::microfacet::{rough_dielectric_albedo, Microfacet};
use super::Lobe;
use super::{fresnel_dielectric, fresnel_diffuse_reflectance, reflect, BsdfFlags, BsdfSample};
use crate::sampling::cosine_hemisphere;
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;
use std::sync::Mutex;

/// Entries of the rough coating's transmittance table, over cos in [0, 1] (as Mitsuba 3).
const TABLE_SIZE: usize = 64;

/// A Lambertian base of albedo `diffuse_reflectance` under a dielectric coating of relative
/// index `eta` (interior over exterior), smooth or rough (Mitsuba 3's `plastic` and
/// `roughplastic`, with their default `nonlinear = false`). One-sided: black from behind.
///
/// Two lobes, with both directions above the surface (cos_o, cos_i > 0):
/// - the coating's reflection, tinted by `specular_reflectance`: smooth, the delta
///   `F(cos_o) delta(wi - reflect(wo)) / cos_i`; rough, the microfacet reflection
///   `F(wo . h) D(h) G(wo, wi, h) / (4 cos_o cos_i)` of the microfacet interface (Walter et al. 2007,
///   eq. 20);
/// - the base seen through the coating (Weidlich & Wilkie 2007; Mitsuba's linear form):
///   `f = rho / (1 - F_int) / (pi eta^2) T(cos_o) T(cos_i)`, where T is the coating's
///   transmittance in each direction, `1 - F(cos)` when smooth; when rough, the directional
///   transmittance of the rough interface (the integral of its transmission lobe, table
///   below). `1 / (1 - F_int)` sums the internal bounces (coating to base and back, with the
///   base's own albedo left out of the series: `nonlinear = false`), where `F_int` is the
///   coating's hemispherical reflectance from inside: smooth, the fit of
///   [`fresnel_diffuse_reflectance`] at `1 / eta`; rough, `2 \int R(mu) mu dmu` of the rough
///   interface from inside, as Mitsuba's mean over 64 evenly spaced mu. `1 / eta^2` is the
///   radiance's compression into the denser medium's smaller solid angle, undone on the way
///   out.
///
/// The base lobe is not Lambertian (it falls off with T at grazing angles), so it is a
/// **glossy** lobe here, traced by photon mapping rather than density-estimated: plastic has
/// no [`super::Bsdf::diffuse_part`].
///
/// Sampling (Mitsuba's): the coating's lobe with probability
/// `p_s = w F_o / (w F_o + (1 - w)(1 - F_o))`, where `F_o` is F(cos_o) (smooth) or
/// `1 - T(cos_o)` (rough) and `w = mean(specular) / (mean(specular) + mean(diffuse))`;
/// the base by cosine-weighted sampling otherwise. pdf = `p_s pdf_coating + (1 - p_s) cos_i / pi`
/// (the delta coating of the smooth plastic adds no density: only its probability).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plastic {
    /// Albedo of the Lambertian base.
    pub diffuse_reflectance: Vec3,
    /// Tint of the coating's reflection.
    pub specular_reflectance: Vec3,
    /// Interior over exterior index of refraction of the coating.
    pub eta: f32,
    /// The coating's microfacet distribution; `None` for a smooth coating.
    pub roughness: Option<Microfacet>,
    /// F_int, the coating's hemispherical reflectance from inside.
    internal_reflectance: f32,
    /// w, the share of the coating in lobe selection.
    specular_sampling_weight: f32,
    /// The rough coating's directional transmittance at cos = i / (TABLE_SIZE - 1).
    transmittance: Option<&'static [f32; TABLE_SIZE]>,
}

impl Plastic {
    /// A plastic; `eta` must be positive and not 1.
    pub fn new(
        diffuse_reflectance: Vec3,
        specular_reflectance: Vec3,
        eta: f32,
        roughness: Option<Microfacet>,
    ) -> Self {
        let specular_sampling_weight =
            Self::sampling_weight(diffuse_reflectance, specular_reflectance);
        let (internal_reflectance, transmittance) = match &roughness {
            None => (fresnel_diffuse_reflectance(1.0 / eta), None),
            Some(dist) => {
                let (f_int, table) = rough_coating_tables(dist, eta);
                (f_int, Some(table))
            }
        };
        Plastic {
            diffuse_reflectance,
            specular_reflectance,
            eta,
            roughness,
            internal_reflectance,
            specular_sampling_weight,
            transmittance,
        }
    }

    /// w = mean(specular) / (mean(specular) + mean(diffuse)), 1/2 when both are black.
    fn sampling_weight(diffuse: Vec3, specular: Vec3) -> f32 {
        let mean = |c: Vec3| (c.x + c.y + c.z) / 3.0;
        let (d, s) = (mean(diffuse), mean(specular));
        if d + s > 0.0 {
            s / (d + s)
        } else {
            0.5
        }
    }

    /// The same coating over other colours (a texture's values at a hit): the coating's
    /// tables depend on eta and roughness only and are kept; the sampling weight follows
    /// the colours. Equal to [`Plastic::new`] with these colours.
    #[inline]
    pub fn with_reflectances(mut self, diffuse: Vec3, specular: Vec3) -> Self {
        self.diffuse_reflectance = diffuse;
        self.specular_reflectance = specular;
        self.specular_sampling_weight = Self::sampling_weight(diffuse, specular);
        self
    }

    /// The coating's lobe (delta or glossy) if its tint is not black, the base's (glossy)
    /// if its albedo is not black; both reflect.
    #[inline]
    pub fn flags(&self) -> BsdfFlags {
        let mut flags = BsdfFlags::NONE;
        if self.specular_reflectance.max_element() > 0.0 {
            flags |= BsdfFlags::REFLECTION;
            flags |= if self.roughness.is_some() {
                BsdfFlags::GLOSSY
            } else {
                BsdfFlags::SPECULAR
            };
        }
        if self.diffuse_reflectance.max_element() > 0.0 {
            flags |= BsdfFlags::GLOSSY | BsdfFlags::REFLECTION;
        }
        flags
    }

    /// T(cos): the coating's transmittance into the base at incidence cosine `cos`.
    #[inline]
    fn coating_transmittance(&self, cos: f32) -> f32 {
        match self.transmittance {
            None => 1.0 - fresnel_dielectric(cos, self.eta),
            Some(table) => {
                // Linear interpolation between the entries at cos = i / (TABLE_SIZE - 1).
                let x = cos.clamp(0.0, 1.0) * (TABLE_SIZE - 1) as f32;
                let i = (x as usize).min(TABLE_SIZE - 2);
                let t = x - i as f32;
                table[i] * (1.0 - t) + table[i + 1] * t
            }
        }
    }

    /// p_s, the probability of sampling the coating's lobe from `cos_o`.
    #[inline]
    fn specular_probability(&self, cos_o: f32) -> f32 {
        let coating = self.specular_reflectance.max_element() > 0.0;
        let base = self.diffuse_reflectance.max_element() > 0.0;
        match (coating, base) {
            (true, true) => {
                let f_o = 1.0 - self.coating_transmittance(cos_o);
                let w = self.specular_sampling_weight;
                let (s, d) = (f_o * w, (1.0 - f_o) * (1.0 - w));
                if s + d > 0.0 {
                    s / (s + d)
                } else {
                    0.0
                }
            }
            (true, false) => 1.0,
            _ => 0.0,
        }
    }

    /// The base lobe, seen through the coating, without the cosine.
    #[inline]
    fn base(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let t = self.coating_transmittance(wo.z) * self.coating_transmittance(wi.z);
        self.diffuse_reflectance
            * (t * FRAC_1_PI / (self.eta * self.eta * (1.0 - self.internal_reflectance)))
    }

    /// f(wo, wi) without the cosine: the base lobe, plus the rough coating's reflection.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let mut f = self.base(wo, wi);
        if let Some(dist) = &self.roughness {
            let h = (wo + wi).normalize();
            let dg = dist.d(h) * dist.g(wo, wi, h);
            // F at the mean of the two equal cosines, so that f(wi, wo) rounds as f(wo, wi).
            let fresnel = fresnel_dielectric(0.5 * (wo.dot(h) + wi.dot(h)), self.eta);
            let coating = fresnel * dg / (4.0 * wo.z * wi.z);
            if coating.is_finite() {
                f += self.specular_reflectance * coating;
            }
        }
        f
    }

    /// The density of the non-delta lobes' sampling at `wi`.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 || self.flags().is_empty() {
            return 0.0;
        }
        let p_s = self.specular_probability(wo.z);
        let mut pdf = (1.0 - p_s) * wi.z * FRAC_1_PI;
        if let Some(dist) = &self.roughness {
            pdf += p_s * reflection_pdf(dist, wo, wi);
        }
        pdf
    }

    /// The coating's lobe with probability p_s, else the base's.
    #[inline]
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 || self.flags().is_empty() {
            return None;
        }
        let p_s = self.specular_probability(wo.z);
        let wi = if u_lobe < p_s {
            match &self.roughness {
                None => {
                    let f = fresnel_dielectric(wo.z, self.eta);
                    return Some(BsdfSample {
                        wi: reflect(wo),
                        weight: self.specular_reflectance * (f / p_s),
                        pdf: p_s,
                        lobe: Lobe::Specular,
                    });
                }
                Some(dist) => {
                    let m = dist.sample_m(wo, u);
                    2.0 * wo.dot(m) * m - wo
                }
            }
        } else {
            cosine_hemisphere(u)
        };
        if wi.z <= 0.0 {
            return None;
        }
        glossy_sample(wi, self.pdf(wo, wi), self.eval(wo, wi))
    }
}

/// The rough coating's tables, computed once per (alpha, eta) for the whole run and shared
/// (they are a few hundred bytes; a scene has a handful of plastics): F_int and the
/// transmittance at cos = i / 63, as Mitsuba 3 computes them (Gauss-Legendre quadrature over
/// the visible normals, 128 x 128 from inside where total internal reflection makes the
/// integrand less smooth), with more points from outside.
fn rough_coating_tables(dist: &Microfacet, eta: f32) -> (f32, &'static [f32; TABLE_SIZE]) {
    type Key = (bool, u32, u32, u32);
    static CACHE: Mutex<Vec<(Key, f32, &'static [f32; TABLE_SIZE])>> = Mutex::new(Vec::new());
    let beckmann = matches!(dist, Microfacet::Beckmann(_));
    let key = (
        beckmann,
        dist.alpha_x().to_bits(),
        dist.alpha_y().to_bits(),
        eta.to_bits(),
    );
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(&(_, f_int, table)) = cache.iter().find(|(k, _, _)| *k == key) {
        return (f_int, table);
    }
    // Mitsuba uses 32 x 32 points from outside; at alpha 0.1 that leaves an error of 1e-4
    // (its own parametrisation of the visible normals, 3e-4): 64 x 64 leaves 2e-5.
    let resolution = |eta: f32| if eta > 1.0 { 64 } else { 128 };
    let mut table = [0.0f32; TABLE_SIZE];
    let mut f_int = 0.0f64;
    for (i, t) in table.iter_mut().enumerate() {
        let mu = (i as f32 / (TABLE_SIZE - 1) as f32).max(1e-6);
        *t = rough_dielectric_albedo(dist, mu, eta, resolution(eta)).1;
        let inside = rough_dielectric_albedo(dist, mu, 1.0 / eta, resolution(1.0 / eta));
        f_int += (inside.0 * mu) as f64;
    }
    let f_int = (2.0 * f_int / TABLE_SIZE as f64) as f32;
    let table: &'static [f32; TABLE_SIZE] = Box::leak(Box::new(table));
    cache.push((key, f_int, table));
    (f_int, table)
}
