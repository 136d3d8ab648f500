//! A thin dielectric sheet (a window pane): the same medium on both sides.

use super::{fresnel_dielectric, reflect, BsdfFlags, BsdfSample, Lobe};
use glam::Vec3;

/// A sheet of a medium of relative index `eta` so thin that the two parallel interfaces are
/// one surface (Mitsuba 3's `thindielectric`). Light bounces between the two faces; summing
/// the geometric series of internal reflections, with R = F(|cos_o|, eta) at each face and
/// T = 1 - R:
/// ```text
/// R_total = R + T^2 R / (1 - R^2) (= 2 R / (1 + R)),   T_total = 1 - R_total
/// ```
/// and every transmitted path leaves parallel to the incident one, so transmission goes
/// straight through (`wi = -wo`, no refraction and no radiance scaling: the medium on both
/// sides is the same). Both lobes are deltas, chosen with probability R_total, so the weights
/// are the tints `specular_reflectance` and `specular_transmittance`. Two-sided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinDielectric {
    /// Index of the sheet over that of the surrounding medium.
    pub eta: f32,
    /// Tint of the reflected light.
    pub specular_reflectance: Vec3,
    /// Tint of the transmitted light.
    pub specular_transmittance: Vec3,
}

impl ThinDielectric {
    /// Specular reflection and specular transmission (those whose tint is not black).
    #[inline]
    pub fn flags(&self) -> BsdfFlags {
        let mut flags = BsdfFlags::NONE;
        if self.specular_reflectance.max_element() > 0.0 {
            flags |= BsdfFlags::SPECULAR | BsdfFlags::REFLECTION;
        }
        if self.specular_transmittance.max_element() > 0.0 {
            flags |= BsdfFlags::SPECULAR | BsdfFlags::TRANSMISSION;
        }
        flags
    }

    /// R_total of the sheet at incidence cosine `cos`.
    #[inline]
    pub fn reflectance(&self, cos: f32) -> f32 {
        let r = fresnel_dielectric(cos.abs(), self.eta);
        if r < 1.0 {
            2.0 * r / (1.0 + r)
        } else {
            1.0
        }
    }

    /// Reflection with probability R_total, straight transmission otherwise; a lobe whose
    /// tint is black is not sampled (the other then carries its probability in its weight).
    #[inline]
    pub fn sample(&self, wo: Vec3, u_lobe: f32) -> Option<BsdfSample> {
        let flags = self.flags();
        if wo.z == 0.0 || flags.is_empty() {
            return None;
        }
        let r = self.reflectance(wo.z);
        let (p_r, weight_r, weight_t) = match (
            flags.contains(BsdfFlags::REFLECTION),
            flags.contains(BsdfFlags::TRANSMISSION),
        ) {
            (true, true) => (r, Vec3::ONE, Vec3::ONE),
            (true, false) => (1.0, Vec3::splat(r), Vec3::ZERO),
            _ => (0.0, Vec3::ZERO, Vec3::splat(1.0 - r)),
        };
        if u_lobe < p_r {
            Some(BsdfSample {
                wi: reflect(wo),
                weight: self.specular_reflectance * weight_r,
                pdf: p_r,
                lobe: Lobe::Specular,
            })
        } else if p_r < 1.0 {
            Some(BsdfSample {
                wi: -wo,
                weight: self.specular_transmittance * weight_t,
                pdf: 1.0 - p_r,
                lobe: Lobe::Specular,
            })
        } else {
            None
        }
    }
}
