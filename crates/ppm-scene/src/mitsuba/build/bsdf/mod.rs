//! BSDF plugins to ppm's [`Bsdf`]: one function per plugin, dispatched by [`bsdf`]. Adding a
//! plugin is one arm and one function. The conductors are in `conductor.rs`, the dielectrics
//! and plastics in `dielectric.rs`, the microfacet parameters they share in `microfacet.rs`.

mod conductor;
mod dielectric;
mod microfacet;

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

/// The BSDF of object `index`; what it approximates goes to `warnings`.
pub fn bsdf(tree: &SceneTree, index: usize, warnings: &mut Vec<String>) -> Result<Bsdf, LoadError> {
    bsdf_at(tree, index, 0, warnings)
}

fn bsdf_at(
    tree: &SceneTree,
    index: usize,
    depth: usize,
    warnings: &mut Vec<String>,
) -> Result<Bsdf, LoadError> {
    let p = Props::new(tree, index);
    if depth > MAX_NESTING {
        return Err(p.error(format!("BSDFs nested more than {MAX_NESTING} deep")));
    }
    let bsdf = match p.object.plugin.as_str() {
        "diffuse" => diffuse(&p)?,
        "conductor" => conductor::conductor(&p)?,
        "roughconductor" => conductor::roughconductor(&p)?,
        "dielectric" => dielectric::dielectric(&p, None)?,
        "roughdielectric" => {
            let dist = microfacet::roughness(&p, true)?;
            dielectric::dielectric(&p, Some(dist))?
        }
        "thindielectric" => dielectric::thindielectric(&p)?,
        "plastic" => dielectric::plastic(&p, None)?,
        "roughplastic" => {
            let dist = microfacet::roughness(&p, false)?;
            dielectric::plastic(&p, Some(dist))?
        }
        "twosided" => twosided(&p, depth, warnings)?,
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

/// `twosided` around one BSDF: the inner BSDF seen from both sides
/// ([`Bsdf::two_sided`]: conductors and plastics mirrored to the back, the models that are
/// two-sided already unchanged). Mitsuba's two different BSDFs for the two sides are an
/// error (ppm's wrapper has one), and so is a refracting inner BSDF (its two sides are two
/// media; Mitsuba refuses it too).
fn twosided(p: &Props, depth: usize, warnings: &mut Vec<String>) -> Result<Bsdf, LoadError> {
    let inner = p.objects("bsdf");
    let one = match inner.as_slice() {
        [one] => *one,
        [a, b] if a == b => *a,
        [a, b] => {
            return Err(p.error(format!(
                "twosided with two different BSDFs ({} at {} in front, {} at {} behind) is not supported yet: ppm shows one BSDF on both sides",
                p.tree.objects[*a].describe(),
                p.tree.objects[*a].location,
                p.tree.objects[*b].describe(),
                p.tree.objects[*b].location
            )))
        }
        _ => {
            return Err(p.error(format!(
                "twosided takes one or two BSDFs, not {}",
                inner.len()
            )))
        }
    };
    let bsdf = bsdf_at(p.tree, one, depth + 1, warnings)?;
    bsdf.two_sided().ok_or_else(|| {
        p.error(format!(
            "twosided around {} at {}: it refracts, so its two sides are two media and cannot be made the same",
            p.tree.objects[one].describe(),
            p.tree.objects[one].location
        ))
    })
}
