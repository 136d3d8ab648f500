//! TODO(bsdf helper)
use super::BsdfSample;
use glam::Vec3;
/// Perfect specular reflection.
#[derive(Clone, Copy, Debug)]
pub struct Mirror { pub color: Vec3 }
impl Mirror {
    pub fn sample(&self, _wo: Vec3) -> Option<BsdfSample> { todo!() }
}
