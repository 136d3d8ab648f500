//! An emissive triangle: a one-sided Lambertian area light.

use super::area::Emitter;
use crate::geometry::Triangle;
use crate::sampling::uniform_triangle;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// An emissive triangle, emitting radiance `le` toward the side its normal points to.
#[derive(Clone, Copy, Debug)]
pub struct TriangleLight {
    pub tri: Triangle,
    /// Unit geometric normal, (v1 - v0) x (v2 - v0) normalised: the emitting side.
    pub normal: Vec3,
    pub area: f32,
    pub le: Vec3,
    /// Global primitive id of the triangle.
    pub prim: u32,
}

impl TriangleLight {
    /// The light on `tri` with radiance `le`; `None` for a degenerate triangle.
    pub fn new(tri: Triangle, le: Vec3, prim: u32) -> Option<Self> {
        let c = (tri.v[1] - tri.v[0]).cross(tri.v[2] - tri.v[0]);
        let area = 0.5 * c.length();
        (area > 0.0 && area.is_finite()).then(|| TriangleLight {
            tri,
            normal: c.normalize(),
            area,
            le,
            prim,
        })
    }

    /// Phi = pi A Le.
    pub fn power(&self) -> Vec3 {
        PI * self.area * self.le
    }

    /// A point uniform by area (pdf 1/A; barycentrics by [`uniform_triangle`]).
    #[inline]
    pub(super) fn emitter(&self, u: Vec2) -> Emitter {
        let b = uniform_triangle(u);
        let [v0, v1, v2] = self.tri.v;
        Emitter {
            q: v0 * (1.0 - b.x - b.y) + v1 * b.x + v2 * b.y,
            n: self.normal,
            area: self.area,
            le: self.le,
        }
    }
}
