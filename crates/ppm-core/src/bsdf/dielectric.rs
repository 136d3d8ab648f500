//! Dielectric interfaces between two media: smooth (Fresnel-weighted mirror and refraction)
//! and rough (GGX or Beckmann microfacets, Walter et al. 2007).

use super::conductor::glossy_sample;
use super::microfacet::Microfacet;
use super::TransportMode;
use super::{fresnel_dielectric, reflect, refract_about, BsdfFlags, BsdfSample, Lobe};
use glam::{Vec2, Vec3};

/// The interface between an exterior medium (the side `z > 0`) and an interior one (`z < 0`),
/// of relative index `eta = int_ior / ext_ior` (Mitsuba 3's `dielectric` and
/// `roughdielectric`). `eta < 1` is allowed: water (1.33) in a glass (1.5) is one surface
/// with `eta = 1.33 / 1.5`. Reflection is tinted by `specular_reflectance`, transmission by
/// `specular_transmittance` (both 1 for a physical interface).
///
/// Notation: for a pair (wo, wi), `eta_w = eta_wi / eta_wo`, the index of `wi`'s side over
/// `wo`'s side (`eta` for wo outside, `1 / eta` inside).
///
/// - Smooth (`roughness` None): both lobes are deltas, chosen with the Fresnel reflectance F
///   as probability (the same as [`super::Glass`], which is this with `eta = ior`):
///   reflection weight R, refraction weight `T s` with `s = 1 / eta_w^2` on camera paths
///   ([`TransportMode::Radiance`]: radiance over the squared index is what crosses unchanged)
///   and `s = 1` on light paths (flux is only split; Veach 1997, sec. 5.2).
/// - Rough: Walter et al. 2007 with a [`Microfacet`] distribution. With the generalised half vector
///   `m = ±normalize(wo + eta_w wi)` (eq. 16; `eta_w = 1` for reflection), oriented up:
///   - reflection (eq. 20): `f = R F(wo . m) D(m) G(wo, wi, m) / (4 |cos_o| |cos_i|)`;
///   - transmission (eq. 21, divided through by the index of wo's side):
///     `f = T s (1 - F) D G eta_w^2 |wo . m| |wi . m| / (|cos_o| |cos_i| (wo . m + eta_w wi . m)^2)`,
///     with the same `s` (Walter's eq. 21 is the radiance BSDF; the adjoint drops the
///     `1 / eta_w^2`).
///
///   Computed in the equivalent form with the two sides' indices, `m ∝ eta_o wo + eta_i wi`
///   and `eta_o^2` (radiance) or `eta_i^2` (importance) over `(eta_o wo . m + eta_i wi . m)^2`,
///   which rounds the same when the arguments are swapped.
///
///   `sample` draws a normal by `sample_m` (on `wo`'s side), then reflects with
///   probability F(wo . m) or refracts. Its density at `wi`: `pdf_m(m)` (`D_wo(m)` for
///   GGX, `D(m) mz` for Beckmann) times F or 1 - F times
///   the Jacobian `1 / (4 |wi . m|)` (reflection, eq. 14) or
///   `eta_w^2 |wi . m| / (wo . m + eta_w wi . m)^2` (refraction, eq. 17).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    /// Interior over exterior index of refraction.
    pub eta: f32,
    /// Tint of the reflected light.
    pub specular_reflectance: Vec3,
    /// Tint of the transmitted light, at each crossing.
    pub specular_transmittance: Vec3,
    /// The microfacet distribution; `None` for a smooth interface.
    pub roughness: Option<Microfacet>,
}

impl Dielectric {
    /// Reflection and transmission, delta or glossy.
    #[inline]
    pub fn flags(&self) -> BsdfFlags {
        let kind = if self.roughness.is_some() {
            BsdfFlags::GLOSSY
        } else {
            BsdfFlags::SPECULAR
        };
        let mut flags = BsdfFlags::NONE;
        if self.specular_reflectance.max_element() > 0.0 {
            flags |= kind | BsdfFlags::REFLECTION;
        }
        if self.specular_transmittance.max_element() > 0.0 {
            flags |= kind | BsdfFlags::TRANSMISSION;
        }
        flags
    }

    /// `eta_w` for wo on its side: the index across the interface over wo's.
    #[inline]
    fn eta_across(&self, wo: Vec3) -> f32 {
        if wo.z > 0.0 {
            self.eta
        } else {
            1.0 / self.eta
        }
    }

    /// The radiance scaling `s` of a refraction out of `wo`'s medium.
    #[inline]
    fn transmission_scale(&self, wo: Vec3, mode: TransportMode) -> f32 {
        match mode {
            TransportMode::Radiance => {
                let eta_w = self.eta_across(wo);
                1.0 / (eta_w * eta_w)
            }
            TransportMode::Importance => 1.0,
        }
    }

    /// The index of the medium on `w`'s side, relative to the exterior.
    #[inline]
    fn side_index(&self, w: Vec3) -> f32 {
        if w.z > 0.0 {
            1.0
        } else {
            self.eta
        }
    }

    /// The generalised half vector of (wo, wi), in the upper hemisphere, with the indices of
    /// wo's and wi's sides (both 1 for a reflection pair) and whether the pair is a reflection.
    /// `m = ±normalize(eta_o wo + eta_i wi)`, symmetric in its two arguments so that the
    /// adjoint's swapped evaluation rounds the same. `None` if degenerate or if either
    /// direction sees the back of m (G would be zero).
    #[inline]
    fn half_vector(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, f32, f32, bool)> {
        if wo.z == 0.0 || wi.z == 0.0 {
            return None;
        }
        let reflection = wo.z * wi.z > 0.0;
        let (eta_o, eta_i) = if reflection {
            (1.0, 1.0)
        } else {
            (self.side_index(wo), self.side_index(wi))
        };
        let m = wo * eta_o + wi * eta_i;
        let m = m * m.z.signum();
        let len = m.length();
        // len is NaN for a NaN input: neither test passes it.
        if len.is_nan() || len <= 0.0 || !len.is_finite() {
            return None;
        }
        let m = m / len;
        if wo.dot(m) * wo.z <= 0.0 || wi.dot(m) * wi.z <= 0.0 {
            return None;
        }
        Some((m, eta_o, eta_i, reflection))
    }

    /// f(wo, wi) without the cosine; zero for a smooth interface.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Vec3 {
        let Some(dist) = &self.roughness else {
            return Vec3::ZERO;
        };
        let Some((m, eta_o, eta_i, reflection)) = self.half_vector(wo, wi) else {
            return Vec3::ZERO;
        };
        let (dot_o, dot_i) = (wo.dot(m), wi.dot(m));
        let dot_f = fresnel_cosine(reflection, wo, dot_o, dot_i);
        let f = fresnel_dielectric(dot_f, self.eta);
        let dg = dist.d(m) * dist.g(wo, wi, m);
        let value = if reflection {
            self.specular_reflectance * (f * dg / (4.0 * wo.z.abs() * wi.z.abs()))
        } else {
            // eq. 21 with eta_w = eta_i / eta_o: the squared index of the side the sum is
            // weighted by is eta_o^2 for radiance (Walter's form), eta_i^2 for importance.
            let denom = eta_o * dot_o + eta_i * dot_i;
            let eta_num = match mode {
                TransportMode::Radiance => eta_o,
                TransportMode::Importance => eta_i,
            };
            let t = (1.0 - f) * dg * eta_num * eta_num * (dot_o * dot_i).abs()
                / (wo.z.abs() * wi.z.abs() * denom * denom);
            self.specular_transmittance * t
        };
        if value.is_finite() {
            value
        } else {
            Vec3::ZERO
        }
    }

    /// The density of [`Dielectric::sample`] at `wi`; zero for a smooth interface.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some(dist) = &self.roughness else {
            return 0.0;
        };
        let Some((m, eta_o, eta_i, reflection)) = self.half_vector(wo, wi) else {
            return 0.0;
        };
        let (dot_o, dot_i) = (wo.dot(m), wi.dot(m));
        // The Fresnel factor as eval reads it (see there), so that pdf > 0 wherever f > 0.
        let dot_f = fresnel_cosine(reflection, wo, dot_o, dot_i);
        let (p_r, p_t) = self.lobe_probabilities(dot_f);
        let pdf_m = dist.pdf_m(wo, m);
        let pdf = if reflection {
            p_r * pdf_m / (4.0 * dot_i.abs())
        } else {
            // eq. 17: eta_i^2 |wi . m| / (eta_o wo . m + eta_i wi . m)^2.
            let denom = eta_o * dot_o + eta_i * dot_i;
            p_t * pdf_m * eta_i * eta_i * dot_i.abs() / (denom * denom)
        };
        if pdf.is_finite() {
            pdf
        } else {
            0.0
        }
    }

    /// Probabilities of reflecting and refracting about a normal at cosine `dot_o` with wo:
    /// F and 1 - F, or 1 and 0 when a tint removes the other lobe.
    #[inline]
    fn lobe_probabilities(&self, dot_o: f32) -> (f32, f32) {
        let flags = self.flags();
        let (r, t) = (
            flags.contains(BsdfFlags::REFLECTION),
            flags.contains(BsdfFlags::TRANSMISSION),
        );
        match (r, t) {
            (true, true) => {
                let f = fresnel_dielectric(dot_o, self.eta);
                (f, 1.0 - f)
            }
            (true, false) => (1.0, 0.0),
            (false, true) => (0.0, 1.0),
            (false, false) => (0.0, 0.0),
        }
    }

    /// Reflection with probability F, refraction otherwise, about the macro normal (smooth)
    /// or a visible microfacet normal (rough).
    #[inline]
    pub fn sample(
        &self,
        wo: Vec3,
        u_lobe: f32,
        u: Vec2,
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        if wo.z == 0.0 || self.flags().is_empty() {
            return None;
        }
        let m = match &self.roughness {
            Some(dist) => {
                let m = dist.sample_m(wo, u);
                if wo.z < 0.0 {
                    -m
                } else {
                    m
                }
            }
            None => Vec3::Z * wo.z.signum(),
        };
        // m is on wo's side here; the Fresnel term takes the cosine signed against +z-up m.
        let dot_o = wo.dot(m);
        let (p_r, _) = self.lobe_probabilities(dot_o.abs().copysign(wo.z));
        let reflected = u_lobe < p_r;
        let wi = if reflected {
            2.0 * dot_o * m - wo
        } else {
            refract_about(wo, m, self.eta_across(wo))?
        };
        if self.roughness.is_some() {
            // A reflection about m that ends below the surface, or a refraction that ends
            // above it, is lost (G1 of wi is zero for it): pdf and eval would read the pair
            // as the other lobe.
            if (wi.z * wo.z > 0.0) != reflected {
                return None;
            }
            return glossy_sample(wi, self.pdf(wo, wi), self.eval(wo, wi, mode));
        }
        // Smooth: the weights of the delta lobes, the Fresnel factor cancelled by its
        // probability (when both lobes are sampled).
        if reflected {
            let p = p_r;
            let f = fresnel_dielectric(wo.z, self.eta);
            let weight = if p < 1.0 {
                self.specular_reflectance
            } else {
                self.specular_reflectance * f
            };
            Some(BsdfSample {
                wi: reflect(wo),
                weight,
                pdf: p,
                lobe: Lobe::Specular,
            })
        } else {
            let p = 1.0 - p_r;
            let f = fresnel_dielectric(wo.z, self.eta);
            let t = if p < 1.0 || f >= 1.0 {
                Vec3::ONE
            } else {
                Vec3::splat(1.0 - f)
            };
            Some(BsdfSample {
                wi,
                weight: self.specular_transmittance * t * self.transmission_scale(wo, mode),
                pdf: p,
                lobe: Lobe::Specular,
            })
        }
    }
}

/// The cosine (signed against the upward normal) the Fresnel factor of a pair is read from:
/// for a refraction pair that of the direction on the exterior side, for a reflection pair the
/// mean of the two (equal in exact arithmetic). Either way f(wi, wo) reads the same cosine as
/// f(wo, wi): F is the same from both ends of a pair, but not when each end is rounded from
/// its own cosine, and near the critical angle F is steep.
#[inline]
fn fresnel_cosine(reflection: bool, wo: Vec3, dot_o: f32, dot_i: f32) -> f32 {
    if reflection {
        0.5 * (dot_o + dot_i)
    } else if wo.z > 0.0 {
        dot_o
    } else {
        dot_i
    }
}
