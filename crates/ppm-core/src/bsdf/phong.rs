//! TODO(bsdf helper)
use super::BsdfSample;
use glam::{Vec2, Vec3};
/// Diffuse + normalized modified Phong.
#[derive(Clone, Copy, Debug)]
pub struct Phong { pub diffuse: Vec3, pub specular: Vec3, pub exponent: f32 }
impl Phong {
    pub fn new(diffuse: Vec3, specular: Vec3, exponent: f32) -> Self { Phong { diffuse, specular, exponent } }
    pub fn eval(&self, _wo: Vec3, _wi: Vec3) -> Vec3 { todo!() }
    pub fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 { todo!() }
    pub fn sample(&self, _wo: Vec3, _u_lobe: f32, _u: Vec2) -> Option<BsdfSample> { todo!() }
}
