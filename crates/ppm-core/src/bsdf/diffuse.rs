//! TODO(bsdf helper)
use super::BsdfSample;
use glam::{Vec2, Vec3};
/// Lambertian reflection.
#[derive(Clone, Copy, Debug)]
pub struct Diffuse { pub albedo: Vec3 }
impl Diffuse {
    pub fn eval(&self, _wo: Vec3, _wi: Vec3) -> Vec3 { todo!() }
    pub fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 { todo!() }
    pub fn sample(&self, _wo: Vec3, _u: Vec2) -> Option<BsdfSample> { todo!() }
}
