//! TODO(bsdf helper)
use super::{BsdfSample, TransportMode};
use glam::Vec3;
/// Smooth dielectric.
#[derive(Clone, Copy, Debug)]
pub struct Glass { pub ior: f32, pub color: Vec3 }
impl Glass {
    pub fn sample(&self, _wo: Vec3, _u_lobe: f32, _mode: TransportMode) -> Option<BsdfSample> { todo!() }
}
