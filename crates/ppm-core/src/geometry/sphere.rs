//! Analytic spheres.

use glam::Vec3;

/// A sphere. Its geometric normal points outward, or inward when `inward` is set (a closed
/// room seen from inside, such as the furnace test).
#[derive(Clone, Copy, Debug)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
    pub material: u32,
    pub inward: bool,
}

impl Sphere {
    /// An outward-facing sphere.
    pub fn new(center: Vec3, radius: f32, material: u32) -> Self {
        Sphere { center, radius, material, inward: false }
    }

    /// The same sphere with its normal pointing inward.
    pub fn inward(mut self) -> Self {
        self.inward = true;
        self
    }

    /// Surface area.
    pub fn area(&self) -> f32 {
        4.0 * std::f32::consts::PI * self.radius * self.radius
    }

    /// Smallest t in (0, t_max) where the ray meets the sphere. TODO(geometry helper).
    pub fn intersect(&self, _origin: Vec3, _dir: Vec3, _t_max: f32) -> Option<f32> {
        todo!()
    }
}
