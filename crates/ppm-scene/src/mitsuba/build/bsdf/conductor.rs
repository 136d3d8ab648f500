//! `conductor` and `roughconductor` to ppm's [`Bsdf::conductor`] (Fresnel of a complex
//! index `eta + i k`, `ppm_core::bsdf::Conductor`).

use super::microfacet::roughness;
use super::reflectance;
use crate::mitsuba::props::Props;
use crate::mitsuba::spectrum::Role;
use crate::LoadError;
use glam::{DVec3, Vec3};
use ppm_core::bsdf::metals::{metal, METALS};
use ppm_core::bsdf::Bsdf;

/// `conductor`: a smooth conductor. `material="none"` (Mitsuba 3's default) is the perfect
/// mirror times `specular_reflectance`; otherwise see [`index`].
pub fn conductor(p: &Props) -> Result<Bsdf, LoadError> {
    let tint = reflectance(p, "specular_reflectance", 1.0)?.as_vec3();
    Ok(match index(p)? {
        None => Bsdf::mirror(tint),
        Some((eta, k)) => Bsdf::conductor(eta, k, tint, None),
    })
}

/// `roughconductor`: a rough conductor (see `microfacet.rs` for the distribution and its
/// roughness) of the complex index [`index`] gives.
pub fn roughconductor(p: &Props) -> Result<Bsdf, LoadError> {
    let dist = roughness(p, true)?;
    let tint = reflectance(p, "specular_reflectance", 1.0)?.as_vec3();
    let (eta, k) = index(p)?.unwrap_or((Vec3::ZERO, Vec3::ONE));
    Ok(Bsdf::conductor(eta, k, tint, Some(dist)))
}

/// The complex index, as Mitsuba 3 reads it: with `eta` given, or `material="none"` (the
/// default since Mitsuba 2; 0.6's default was `Cu`, which Mitsuba 3 does not upgrade
/// either), `eta` (default 0) and `k` (default 1), where `material` may only be `none`;
/// otherwise the named `material` from Mitsuba's presets (`ppm_core::bsdf::metals`, the RGB
/// values Mitsuba 3.9.1's `scalar_rgb` uses). `None` for the perfect mirror, eta 0 and k 1
/// given or defaulted (|r| = 1 exactly for a purely imaginary index of modulus 1).
fn index(p: &Props) -> Result<Option<(Vec3, Vec3)>, LoadError> {
    let material = p.string_opt("material")?.unwrap_or("none");
    if p.get("eta").is_some() || material == "none" {
        if material != "none" {
            return Err(p.error(format!(
                "{}: give either `eta` and `k` or `material` (`{material}`), not both",
                p.object.describe()
            )));
        }
        let eta = part(p, "eta", 0.0)?;
        let k = part(p, "k", 1.0)?;
        if eta == DVec3::ZERO && k == DVec3::ONE {
            return Ok(None);
        }
        return Ok(Some((eta.as_vec3(), k.as_vec3())));
    }
    let m = metal(material).ok_or_else(|| {
        let names: Vec<&str> = METALS.iter().map(|m| m.name).collect();
        p.error(format!(
            "{}: unknown material `{material}`; Mitsuba's conductors: none, {}",
            p.object.describe(),
            names.join(", ")
        ))
    })?;
    Ok(Some((m.eta, m.k)))
}

/// `eta` or `k`: a float, an rgb or a spectrum (converted as Mitsuba's RGB variants do, like
/// a reflectance but unclamped), finite and non-negative.
fn part(p: &Props, name: &str, default: f64) -> Result<DVec3, LoadError> {
    let v = p.colour(name, DVec3::splat(default), Role::Index)?;
    if !(v.is_finite() && v.min_element() >= 0.0 && v.as_vec3().is_finite()) {
        return Err(p.error(format!(
            "{}: `{name}` {v} is not a finite, non-negative index",
            p.object.describe()
        )));
    }
    Ok(v)
}
