//! Perfect specular reflection.

use super::{reflect, BsdfFlags, BsdfSample, Lobe};
use glam::Vec3;

/// A perfect mirror whose reflectance is `color` (no Fresnel term: a conductor idealised).
///
/// The BSDF is the delta `color * delta(wi - reflect(wo)) / |cos(wi)|`, so `eval` and `pdf` are
/// zero and only [`Mirror::sample`] produces the reflected direction.
#[derive(Clone, Copy, Debug)]
pub struct Mirror {
    /// Reflectance per channel.
    pub color: Vec3,
}

impl Mirror {
    /// One specular reflection lobe.
    #[inline]
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::SPECULAR | BsdfFlags::REFLECTION
    }

    /// The reflected direction with weight `color` and discrete probability 1. Two-sided:
    /// `wi` is on `wo`'s side of the surface. `None` for `wo` in the tangent plane.
    #[inline]
    pub fn sample(&self, wo: Vec3) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi: reflect(wo),
            weight: self.color,
            pdf: 1.0,
            lobe: Lobe::Specular,
        })
    }
}
