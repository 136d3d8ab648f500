//! An emissive sphere: a one-sided Lambertian area light, emitting outward (or inward).

use super::area::Emitter;
use crate::geometry::Sphere;
use crate::sampling::uniform_sphere;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// An emissive sphere, emitting radiance `le` outward, or inward when `sphere.inward` is set.
#[derive(Clone, Copy, Debug)]
pub struct SphereLight {
    pub sphere: Sphere,
    pub le: Vec3,
    /// Global primitive id of the sphere.
    pub prim: u32,
}

impl SphereLight {
    /// Phi = pi A Le.
    pub fn power(&self) -> Vec3 {
        PI * self.sphere.area() * self.le
    }

    /// A point uniform by area (pdf 1/A) over the whole sphere, with the emitting normal.
    /// Points on the far side from a shading point face away and are rejected by
    /// next-event estimation (the pdf counts them: it is not renormalised to the visible cap).
    #[inline]
    pub(super) fn emitter(&self, u: Vec2) -> Emitter {
        let d = uniform_sphere(u);
        let n = if self.sphere.inward { -d } else { d };
        Emitter {
            q: self.sphere.center + d * self.sphere.radius.abs(),
            n,
            area: self.sphere.area(),
            le: self.le,
        }
    }
}
