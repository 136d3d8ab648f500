//! BSDF plugins to ppm's [`Bsdf`]: one function per plugin, dispatched by [`bsdf`].
//! Adding a plugin is one arm and one function here.

use super::unsupported;
use crate::mitsuba::ior;
use crate::mitsuba::props::Props;
use crate::mitsuba::spectrum::Role;
use crate::mitsuba::tree::{SceneTree, Value};
use crate::LoadError;
use glam::DVec3;
use ppm_core::bsdf::Bsdf;

/// Deepest nesting of BSDFs inside BSDFs (`twosided`).
const MAX_NESTING: usize = 8;

/// The BSDF of object `index`.
pub fn bsdf(tree: &SceneTree, index: usize) -> Result<Bsdf, LoadError> {
    bsdf_at(tree, index, 0)
}

fn bsdf_at(tree: &SceneTree, index: usize, depth: usize) -> Result<Bsdf, LoadError> {
    let p = Props::new(tree, index);
    if depth > MAX_NESTING {
        return Err(p.error(format!("BSDFs nested more than {MAX_NESTING} deep")));
    }
    let bsdf = match p.object.plugin.as_str() {
        "diffuse" => diffuse(&p)?,
        "dielectric" => dielectric(&p)?,
        "conductor" => conductor(&p)?,
        "twosided" => twosided(&p, depth)?,
        _ => return Err(unsupported(&tree.objects[index])),
    };
    p.finish()?;
    Ok(bsdf)
}

/// A reflectance in [0, 1] (each channel), or a texture (`texture.rs`; its mean here).
fn reflectance(p: &Props, name: &str, default: f64) -> Result<DVec3, LoadError> {
    let c = super::texture::colour_or_texture(p, name, DVec3::splat(default), Role::Reflectance)?;
    if c.min_element() < 0.0 || c.max_element() > 1.0 {
        return Err(p.error(format!(
            "{}: `{name}` is {c}, expected each channel in [0, 1]",
            p.object.describe()
        )));
    }
    Ok(c)
}

/// `diffuse`: Lambertian, f = reflectance / pi (default 0.5). ppm's diffuse reflects on both
/// sides already, as `twosided` makes Mitsuba's.
fn diffuse(p: &Props) -> Result<Bsdf, LoadError> {
    Ok(Bsdf::diffuse(reflectance(p, "reflectance", 0.5)?.as_vec3()))
}

/// An index of refraction: a float or a name from Mitsuba's table (`ior.rs`).
fn index_of_refraction(p: &Props, name: &str, default: f64) -> Result<f64, LoadError> {
    let v = match p.get(name).map(|prop| &prop.value) {
        None => default,
        Some(Value::String(s)) => ior::lookup(s).ok_or_else(|| {
            p.error(format!(
                "{}: `{name}` `{s}` is not a known material (known: {})",
                p.object.describe(),
                ior::names()
            ))
        })?,
        Some(_) => p.float(name, default)?,
    };
    if !(v > 0.0 && v.is_finite()) {
        return Err(p.error(format!(
            "{}: `{name}` {v} is not positive",
            p.object.describe()
        )));
    }
    Ok(v)
}

/// `dielectric`: a smooth interface between `int_ior` (default bk7) inside and `ext_ior`
/// (default air) outside is ppm's glass of relative index int_ior / ext_ior (Fresnel
/// reflection and refraction depend only on the ratio); `specular_transmittance` tints the
/// refracted light. A tinted `specular_reflectance` is not supported yet.
fn dielectric(p: &Props) -> Result<Bsdf, LoadError> {
    let int_ior = index_of_refraction(p, "int_ior", 1.5046)?;
    let ext_ior = index_of_refraction(p, "ext_ior", 1.000277)?;
    let r = reflectance(p, "specular_reflectance", 1.0)?;
    if r != DVec3::ONE {
        return Err(p.error("dielectric: a specular_reflectance other than 1 is not supported yet"));
    }
    let t = reflectance(p, "specular_transmittance", 1.0)?;
    Ok(Bsdf::glass((int_ior / ext_ior) as f32, t.as_vec3()))
}

/// `conductor` with `material="none"`: the perfect mirror, times `specular_reflectance`.
/// Measured metals (the default `Cu`, `eta`/`k`) are not supported yet.
fn conductor(p: &Props) -> Result<Bsdf, LoadError> {
    let material = p.string_opt("material")?;
    if material != Some("none") || p.get("eta").is_some() || p.get("k").is_some() {
        return Err(p.error(format!(
            "conductor `{}`: only material=\"none\" (a perfect mirror) is supported yet",
            material.unwrap_or("Cu")
        )));
    }
    Ok(Bsdf::mirror(
        reflectance(p, "specular_reflectance", 1.0)?.as_vec3(),
    ))
}

/// `twosided` around one BSDF that ppm renders the same from both sides (`diffuse`). Other
/// inner BSDFs, or two different ones, are not supported yet.
fn twosided(p: &Props, depth: usize) -> Result<Bsdf, LoadError> {
    let inner = p.objects("bsdf");
    match inner.as_slice() {
        [one] if matches!(p.tree.objects[*one].plugin.as_str(), "diffuse" | "twosided") => {
            bsdf_at(p.tree, *one, depth + 1)
        }
        [one] => Err(p.error(format!(
            "twosided around {} is not supported yet (only around diffuse)",
            p.tree.objects[*one].describe()
        ))),
        _ => Err(p.error(format!(
            "twosided with {} BSDFs is not supported yet (it takes one, a diffuse)",
            inner.len()
        ))),
    }
}
