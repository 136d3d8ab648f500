//! `dielectric`, `roughdielectric`, `thindielectric`, `plastic` and `roughplastic`: the
//! interfaces of relative index `int_ior / ext_ior` (Fresnel reflection and refraction depend
//! only on the ratio), as ppm's [`Dielectric`], [`ThinDielectric`] and plastic.

use super::{index_of_refraction, reflectance};
use crate::mitsuba::props::Props;
use crate::LoadError;
use ppm_core::bsdf::{Bsdf, Dielectric, Microfacet, ThinDielectric};

/// Mitsuba's default indices: `bk7` inside the dielectrics, `polypropylene` in the
/// plastics' coating, `air` outside.
const BK7: f64 = 1.5046;
const POLYPROPYLENE: f64 = 1.49;
const AIR: f64 = 1.000277;

/// `int_ior / ext_ior`, which may not be 1 (the interface would not be there).
fn relative_index(p: &Props, default_int: f64) -> Result<f32, LoadError> {
    let int_ior = index_of_refraction(p, "int_ior", default_int)?;
    let ext_ior = index_of_refraction(p, "ext_ior", AIR)?;
    let eta = (int_ior / ext_ior) as f32;
    if eta == 1.0 {
        return Err(p.error(format!(
            "{}: int_ior and ext_ior are both {int_ior}: the interface would not be there",
            p.object.describe()
        )));
    }
    Ok(eta)
}

/// `dielectric` (`roughness` None) and `roughdielectric`: the interface between `int_ior`
/// (default bk7) on the side the normal points away from and `ext_ior` (default air) on the
/// other, ppm's two-media [`Dielectric`] of `eta = int_ior / ext_ior`, so `eta < 1` (water
/// inside glass) works as in Mitsuba. `specular_reflectance` and `specular_transmittance`
/// tint the two lobes.
pub fn dielectric(p: &Props, roughness: Option<Microfacet>) -> Result<Bsdf, LoadError> {
    let eta = relative_index(p, BK7)?;
    Ok(Bsdf::Dielectric(Dielectric {
        eta,
        specular_reflectance: reflectance(p, "specular_reflectance", 1.0)?.as_vec3(),
        specular_transmittance: reflectance(p, "specular_transmittance", 1.0)?.as_vec3(),
        roughness,
    }))
}

/// `thindielectric`: a sheet of `int_ior` (default bk7) in `ext_ior` (default air), its
/// internal reflections summed ([`ThinDielectric`]).
pub fn thindielectric(p: &Props) -> Result<Bsdf, LoadError> {
    let eta = relative_index(p, BK7)?;
    Ok(Bsdf::ThinDielectric(ThinDielectric {
        eta,
        specular_reflectance: reflectance(p, "specular_reflectance", 1.0)?.as_vec3(),
        specular_transmittance: reflectance(p, "specular_transmittance", 1.0)?.as_vec3(),
    }))
}

/// `plastic` (`roughness` None) and `roughplastic`: a Lambertian base of
/// `diffuse_reflectance` (default 0.5) under a coating of `int_ior` (default polypropylene,
/// 1.49) in `ext_ior` (air), its reflection tinted by `specular_reflectance`
/// (`ppm_core::bsdf::Plastic`, Mitsuba's model). ppm has Mitsuba's default
/// `nonlinear = false` only; `true` is an error. The smooth coating's internal reflectance
/// is a polynomial fit that exceeds 1 above a relative index of about 3.9, so its index must
/// lie in (1, 3].
pub fn plastic(p: &Props, roughness: Option<Microfacet>) -> Result<Bsdf, LoadError> {
    let eta = relative_index(p, POLYPROPYLENE)?;
    if p.boolean("nonlinear", false)? {
        return Err(p.error(format!(
            "{}: nonlinear=\"true\" (the base's colour saturated by internal bounces) is not supported yet",
            p.object.describe()
        )));
    }
    if roughness.is_none() && !(eta > 1.0 && eta <= 3.0) {
        return Err(p.error(format!(
            "{}: int_ior / ext_ior is {eta}; a plastic's coating needs a relative index in (1, 3]",
            p.object.describe()
        )));
    }
    let diffuse = reflectance(p, "diffuse_reflectance", 0.5)?.as_vec3();
    let specular = reflectance(p, "specular_reflectance", 1.0)?.as_vec3();
    Ok(Bsdf::plastic(diffuse, specular, eta, roughness))
}
