//! Smooth dielectric: Fresnel-weighted mirror reflection and refraction.

use super::{fresnel_dielectric, reflect, BsdfFlags, BsdfSample, Lobe, TransportMode};
use glam::Vec3;

/// A smooth dielectric interface between vacuum (index 1, the side `z > 0`) and a medium of
/// index `ior` (the side `z < 0`), with the transmitted light tinted by `color` at each crossing.
///
/// Both lobes are deltas, chosen with the Fresnel reflectance F as probability, so the
/// sample weights carry no F:
/// - reflection: f |cos| = F, pdf = F, weight 1;
/// - refraction: f |cos| = (1 - F) color s, pdf = 1 - F, weight = color s, where in
///   [`TransportMode::Radiance`] `s = 1 / eta^2` with `eta = eta_wi / eta_wo` (the index of
///   `wi`'s side over `wo`'s side), because radiance divided by the squared index is what is
///   invariant across the interface: looking into the glass from outside, the camera sees the
///   radiance inside divided by ior^2. In [`TransportMode::Importance`] `s = 1`: a photon
///   carries flux, which is only split between the two lobes (Veach 1997, sec. 5.2).
#[derive(Clone, Copy, Debug)]
pub struct Glass {
    /// Index of refraction of the medium (below the surface), against vacuum above.
    pub ior: f32,
    /// Transmission tint, per channel.
    pub color: Vec3,
}

impl Glass {
    /// Specular reflection and specular transmission.
    #[inline]
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::SPECULAR | BsdfFlags::REFLECTION | BsdfFlags::TRANSMISSION
    }

    /// Chooses reflection with probability F (`u_lobe < F`), refraction otherwise.
    /// `wo.z > 0` means `wo` is outside, in vacuum.
    #[inline]
    pub fn sample(&self, wo: Vec3, u_lobe: f32, mode: TransportMode) -> Option<BsdfSample> {
        let f = fresnel_dielectric(wo.z, self.ior);
        if u_lobe < f {
            return Some(BsdfSample {
                wi: reflect(wo),
                weight: Vec3::ONE,
                pdf: f,
                lobe: Lobe::Specular,
            });
        }
        // eta = eta_wi / eta_wo: entering the medium when wo is outside.
        let eta = if wo.z > 0.0 { self.ior } else { 1.0 / self.ior };
        let wi = refract(wo, eta)?;
        let scale = match mode {
            TransportMode::Radiance => 1.0 / (eta * eta),
            TransportMode::Importance => 1.0,
        };
        Some(BsdfSample {
            wi,
            weight: self.color * scale,
            pdf: 1.0 - f,
            lobe: Lobe::Specular,
        })
    }
}

/// Refracts `wo` (pointing away from the surface) through the interface about the local `z`
/// axis, into the other side; `eta` is the index of the other side over `wo`'s side. `None` on
/// total internal reflection.
///
/// With n the normal on `wo`'s side, Snell's law sin_t = sin_o / eta gives
/// `wi = -wo / eta + (cos_o / eta - cos_t) n`: tangential part -wo_t / eta, normal part -cos_t n.
#[inline]
fn refract(wo: Vec3, eta: f32) -> Option<Vec3> {
    let cos_o = wo.z.abs();
    let sin2_t = (1.0 - cos_o * cos_o).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let n = Vec3::new(0.0, 0.0, 1.0f32.copysign(wo.z));
    Some(-wo / eta + (cos_o / eta - cos_t) * n)
}
