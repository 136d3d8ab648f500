//! TODO(bsdf helper)
/// Unpolarised Fresnel reflectance of a dielectric interface.
pub fn fresnel_dielectric(_cos_i: f32, _eta: f32) -> f32 { todo!() }
