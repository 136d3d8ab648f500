//! Lambertian reflection.

use super::{BsdfFlags, BsdfSample, Lobe};
use crate::sampling::cosine_hemisphere;
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// Lambertian reflection: f = albedo / pi on the side of `wo`, zero across the surface.
#[derive(Clone, Copy, Debug)]
pub struct Diffuse {
    /// Directional-hemispherical reflectance, per channel in [0, 1].
    pub albedo: Vec3,
}

impl Diffuse {
    /// One diffuse reflection lobe (even when black: photons are still stored on it).
    #[inline]
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::DIFFUSE | BsdfFlags::REFLECTION
    }

    /// f(wo, wi) = albedo / pi when both directions are on the same side, else 0.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z * wi.z > 0.0 {
            self.albedo * FRAC_1_PI
        } else {
            Vec3::ZERO
        }
    }

    /// Cosine-weighted density on `wo`'s side: pdf = |cos(wi)| / pi.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z * wi.z > 0.0 {
            wi.z.abs() * FRAC_1_PI
        } else {
            0.0
        }
    }

    /// Cosine-weighted sampling; the weight f |cos| / pdf = albedo exactly.
    #[inline]
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<BsdfSample> {
        let mut wi = cosine_hemisphere(u);
        // Two-sided: sample the hemisphere wo is in.
        wi.z = wi.z.copysign(wo.z);
        let pdf = self.pdf(wo, wi);
        // wo or wi in the tangent plane: a zero-measure event that carries nothing.
        (pdf > 0.0).then_some(BsdfSample {
            wi,
            weight: self.albedo,
            pdf,
            lobe: Lobe::Diffuse,
        })
    }
}
