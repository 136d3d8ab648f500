//! The two-sided wrapper: a one-sided reflector seen the same from both sides.

use super::{BsdfFlags, BsdfSample, Conductor, Plastic};
use glam::{Vec2, Vec3};

/// A reflection model defined for the front side only (`wo.z > 0`), black from behind.
pub trait FrontSided {
    /// f(wo, wi) without the cosine.
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3;
    /// Density of `sample`.
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32;
    /// A direction and its weight.
    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample>;
    /// The kinds of lobes.
    fn flags(&self) -> BsdfFlags;
}

impl FrontSided for Conductor {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        Conductor::eval(self, wo, wi)
    }
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        Conductor::pdf(self, wo, wi)
    }
    fn sample(&self, wo: Vec3, _u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        Conductor::sample(self, wo, u)
    }
    fn flags(&self) -> BsdfFlags {
        Conductor::flags(self)
    }
}

impl FrontSided for Plastic {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        Plastic::eval(self, wo, wi)
    }
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        Plastic::pdf(self, wo, wi)
    }
    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        Plastic::sample(self, wo, u_lobe, u)
    }
    fn flags(&self) -> BsdfFlags {
        Plastic::flags(self)
    }
}

/// `B` on both sides (Mitsuba 3's `twosided` with one nested BSDF): for `wo` behind the
/// surface, both directions are mirrored through the tangent plane (z -> -z), the front-side
/// model is evaluated there, and a sampled direction is mirrored back. So
/// `f(wo, wi) = f_B(flip(wo), flip(wi))` below and `f_B(wo, wi)` above; the pdf and the
/// sample weights follow unchanged (mirroring preserves solid angle and |cos|). Reflection
/// only: a pair across the surface is zero on both sides, as for `B`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoSided<B>(pub B);

/// Mirror through the tangent plane.
#[inline]
fn flip(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

impl<B: FrontSided> TwoSided<B> {
    /// The nested model's flags (the same lobes on each side).
    #[inline]
    pub fn flags(&self) -> BsdfFlags {
        self.0.flags()
    }

    /// f_B on `wo`'s side.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z < 0.0 {
            self.0.eval(flip(wo), flip(wi))
        } else {
            self.0.eval(wo, wi)
        }
    }

    /// pdf_B on `wo`'s side.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z < 0.0 {
            self.0.pdf(flip(wo), flip(wi))
        } else {
            self.0.pdf(wo, wi)
        }
    }

    /// B's sample on `wo`'s side.
    #[inline]
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z < 0.0 {
            self.0.sample(flip(wo), u_lobe, u).map(|s| BsdfSample {
                wi: flip(s.wi),
                ..s
            })
        } else {
            self.0.sample(wo, u_lobe, u)
        }
    }
}
