//! `Material` and `MakeNamedMaterial` to ppm's [`Bsdf`], one function per material type.
//!
//! Roughness: pbrt-v4's `uroughness`/`vroughness` (or `roughness` for both) become the GGX
//! (Trowbridge-Reitz) alpha through `RoughnessToAlpha`, alpha = sqrt(roughness), unless
//! `remaproughness` is false (then alpha = roughness); alpha < 1e-3 is pbrt's "effectively
//! smooth" (`TrowbridgeReitzDistribution::EffectivelySmooth`), a smooth interface. A
//! conductor's or dielectric's roughness may be a float texture (`"texture roughness"`,
//! `texture.rs`): its alphas become the material's [`ColourSlot::Roughness`], with their mean
//! as the nominal alpha. pbrt decides "effectively smooth" per shading point; ppm per
//! material (smooth only if every texel is), so a texel below alpha 1e-3 among rougher ones is
//! rendered as GGX with alpha at least 1e-4, a lobe as narrow as a delta to the eye.

use super::super::params::{Param, ParamSet, ParamType};
use super::super::scene::{Description, MaterialEntity};
use super::super::spectrum::{self, IorPart, SpectrumValue};
use super::texture::{reflectance_texture, roughness_texture};
use crate::LoadError;
use glam::DVec3;
use ppm_core::bsdf::microfacet::{Ggx, Microfacet};
use ppm_core::bsdf::Bsdf;
use ppm_core::texture::{texture_scalar, ColourSlot, Texture};

/// The BSDF of material `m` and the textures that drive its colours (a `diffuse`
/// `reflectance` may be an `imagemap` or `checkerboard` texture, `texture.rs`).
pub fn bsdf(
    desc: &Description,
    m: &MaterialEntity,
    warnings: &mut Vec<String>,
) -> Result<(Bsdf, Vec<(ColourSlot, Texture)>), LoadError> {
    let e = &m.entity;
    let what = match &m.name {
        Some(name) => format!("material \"{name}\""),
        None => format!("Material \"{}\"", e.kind),
    };
    let p = ParamSet::new(what, e.loc.clone(), &e.params, &m.defaults);
    let kind = match m.name {
        Some(_) if e.kind.is_empty() => p
            .string_opt("type")?
            .ok_or_else(|| p.error("needs a \"string type\""))?
            .to_string(),
        _ => e.kind.clone(),
    };
    let mut textures = Vec::new();
    let mut rough = |p: &ParamSet, textures: &mut Vec<(ColourSlot, Texture)>| {
        let (distribution, texture) = roughness(desc, p, warnings)?;
        if let Some(t) = texture {
            textures.push((ColourSlot::Roughness, t));
        }
        Ok::<_, LoadError>(distribution)
    };
    let bsdf = match kind.as_str() {
        "diffuse" => {
            if let Some((SpectrumValue::Texture(t), param)) = p.spectrum("reflectance")? {
                if let Some(texture) = reflectance_texture(desc, &p, param, &t, warnings)? {
                    let mean = texture.mean();
                    textures.push((ColourSlot::DiffuseReflectance, texture));
                    p.finish()?;
                    return Ok((Bsdf::diffuse(mean), textures));
                }
            }
            Bsdf::diffuse(reflectance(desc, &p, "reflectance", 0.5)?.as_vec3())
        }
        "conductor" => {
            let distribution = rough(&p, &mut textures)?;
            conductor(desc, &p, distribution)?
        }
        "dielectric" => {
            let eta = eta(&p)?;
            Bsdf::dielectric(eta as f32, rough(&p, &mut textures)?)
        }
        "thindielectric" => Bsdf::thin_dielectric(eta(&p)? as f32),
        "coateddiffuse" => {
            let (distribution, texture) = roughness(desc, &p, warnings)?;
            if texture.is_some() {
                return Err(p.error(
                    "a roughness texture on coateddiffuse is not supported yet (ppm's plastic tabulates its coating per roughness)",
                ));
            }
            coated_diffuse(desc, &p, distribution, warnings)?
        }
        "interface" | "none" => {
            return Err(p.error(format!(
                "\"{kind}\" (no surface, a medium boundary) is not supported yet"
            )))
        }
        _ => {
            return Err(p.error(format!(
                "material type \"{kind}\" is not supported yet (diffuse, conductor, dielectric, thindielectric and coateddiffuse are)"
            )))
        }
    };
    p.finish()?;
    Ok((bsdf, textures))
}

/// A reflectance-valued parameter (pbrt's albedo spectra): rgb, sampled spectrum, or a
/// `constant` texture of one.
fn reflectance(
    desc: &Description,
    p: &ParamSet,
    name: &str,
    default: f64,
) -> Result<DVec3, LoadError> {
    let Some((value, param)) = p.spectrum(name)? else {
        return Ok(DVec3::splat(default));
    };
    let value = match value {
        SpectrumValue::Texture(t) => constant_texture(desc, p, param, &t)?,
        v => v,
    };
    spectrum::albedo_rgb(&value).map_err(|e| p.error_at(param, e))
}

/// A `constant` spectrum texture's value; any other texture is not supported yet.
fn constant_texture(
    desc: &Description,
    p: &ParamSet,
    param: &Param,
    name: &str,
) -> Result<SpectrumValue, LoadError> {
    let t = desc
        .textures
        .get(name)
        .ok_or_else(|| p.error_at(param, format!("no texture \"{name}\"")))?;
    let tp = ParamSet::new(
        format!("Texture \"{name}\""),
        t.entity.loc.clone(),
        &t.entity.params,
        &[],
    );
    if t.entity.kind != "constant" || t.value_type != "spectrum" {
        return Err(p.error_at(
            param,
            format!(
                "texture \"{name}\" ({} \"{}\" at {}) is not supported yet here: only constant spectrum textures are (and imagemap or checkerboard as a diffuse reflectance)",
                t.value_type, t.entity.kind, t.entity.loc
            ),
        ));
    }
    let value = match tp.spectrum("value")? {
        Some((v, _)) => v,
        None => SpectrumValue::Rgb(DVec3::ONE),
    };
    tp.finish()?;
    if matches!(value, SpectrumValue::Texture(_)) {
        return Err(tp.error("a texture's value cannot be another texture"));
    }
    Ok(value)
}

/// A float parameter that must not be a texture.
fn plain_float(p: &ParamSet, name: &str, default: f64) -> Result<f64, LoadError> {
    match p.float_or_texture(name)? {
        None => Ok(default),
        Some(Ok(v)) => Ok(v),
        Some(Err((t, param))) => Err(p.error_at(
            param,
            format!("float textures (\"{t}\") are not supported yet"),
        )),
    }
}

/// A roughness parameter: a float, or the name of a texture (and its parameter).
#[derive(Clone)]
enum RoughnessParam<'a> {
    Value(f64),
    Texture(String, &'a Param),
}

/// Roughness parameter `name` of `p`, `default` when not given.
fn roughness_param<'a>(
    p: &ParamSet<'a>,
    name: &str,
    default: RoughnessParam<'a>,
) -> Result<RoughnessParam<'a>, LoadError> {
    Ok(match p.float_or_texture(name)? {
        None => default,
        Some(Ok(r)) => RoughnessParam::Value(r),
        Some(Err((t, param))) => RoughnessParam::Texture(t, param),
    })
}

/// The GGX distribution of `roughness`/`uroughness`/`vroughness` (see the module
/// documentation), `None` when effectively smooth, and the texture of its alphas when the
/// roughness is a texture.
fn roughness(
    desc: &Description,
    p: &ParamSet,
    warnings: &mut Vec<String>,
) -> Result<(Option<Microfacet>, Option<Texture>), LoadError> {
    let both = roughness_param(p, "roughness", RoughnessParam::Value(0.0))?;
    let u = roughness_param(p, "uroughness", both.clone())?;
    let v = roughness_param(p, "vroughness", both)?;
    let remap = p.bool("remaproughness", true)?;
    let (u, v) = match (u, v) {
        (RoughnessParam::Value(u), RoughnessParam::Value(v)) => (u, v),
        (RoughnessParam::Texture(tu, param), RoughnessParam::Texture(tv, _)) if tu == tv => {
            match roughness_texture(desc, p, param, &tu, remap, warnings)? {
                Ok(r) => (r, r),
                Err(texture) => {
                    let alpha = texture_scalar(texture.mean());
                    if texture.max_value() < 1e-3 {
                        return Ok((None, None));
                    }
                    return Ok((Some(Ggx::isotropic(alpha).into()), Some(texture)));
                }
            }
        }
        _ => {
            return Err(p.error(
                "anisotropic roughness (uroughness and vroughness not the same texture) is not supported yet: ppm's meshes carry no surface tangent to orient it",
            ))
        }
    };
    for r in [u, v] {
        if !(r >= 0.0 && r.is_finite()) {
            return Err(p.error(format!("roughness {r} is negative")));
        }
    }
    let alpha = |r: f64| if remap { r.sqrt() } else { r };
    let (ax, ay) = (alpha(u), alpha(v));
    if ax.max(ay) < 1e-3 {
        return Ok((None, None));
    }
    if ax != ay {
        return Err(p.error(format!(
            "anisotropic roughness (u {u}, v {v}) is not supported yet: ppm's meshes carry no surface tangent to orient it"
        )));
    }
    Ok((Some(Ggx::isotropic(ax as f32).into()), None))
}

/// `eta` of a dielectric: a float, a constant spectrum, or a named glass (its index at 550 nm:
/// ppm does not render dispersion). pbrt-v4's default 1.5.
fn eta(p: &ParamSet) -> Result<f64, LoadError> {
    let eta = match p.param_type("eta") {
        None => 1.5,
        Some(ParamType::Float) => p.float("eta", 1.5)?,
        Some(_) => match p.spectrum("eta")? {
            Some((SpectrumValue::Named(n), param)) => spectrum::glass_eta(&n).ok_or_else(|| {
                p.error_at(param, format!("\"{n}\" is not one of pbrt's named glasses"))
            })?,
            Some((SpectrumValue::Samples(s), _)) if s.iter().all(|x| x.1 == s[0].1) => s[0].1,
            Some((_, param)) => {
                return Err(p.error_at(
                    param,
                    "a spectrally varying eta (dispersion) is not supported yet; give a float",
                ))
            }
            None => 1.5,
        },
    };
    if !(eta > 0.0 && eta.is_finite()) {
        return Err(p.error(format!("eta {eta} is not positive")));
    }
    Ok(eta)
}

/// `conductor`: `eta` + `k` (default pbrt's copper, `metal-Cu-eta`/`metal-Cu-k`), or
/// `reflectance` r, which pbrt-v4 turns into eta = 1, k = 2 sqrt(r) / sqrt(1 - r) (the
/// conductor whose normal-incidence Fresnel reflectance is r).
fn conductor(
    desc: &Description,
    p: &ParamSet,
    roughness: Option<Microfacet>,
) -> Result<Bsdf, LoadError> {
    if p.has("reflectance") {
        if p.has("eta") || p.has("k") {
            return Err(p.error("give either reflectance or eta and k, not both"));
        }
        let r = reflectance(desc, p, "reflectance", 0.0)?.min(DVec3::splat(1.0 - 1e-6));
        let k = DVec3::new(
            2.0 * r.x.sqrt() / (1.0 - r.x).sqrt(),
            2.0 * r.y.sqrt() / (1.0 - r.y).sqrt(),
            2.0 * r.z.sqrt() / (1.0 - r.z).sqrt(),
        );
        return Ok(Bsdf::conductor(
            glam::Vec3::ONE,
            k.as_vec3(),
            glam::Vec3::ONE,
            roughness,
        ));
    }
    let part = |name: &str, part: IorPart, default: &str| -> Result<DVec3, LoadError> {
        match p.spectrum(name)? {
            None => spectrum::conductor_rgb(&SpectrumValue::Named(default.into()), part)
                .map_err(|e| p.error(e)),
            Some((v, param)) => spectrum::conductor_rgb(&v, part).map_err(|e| p.error_at(param, e)),
        }
    };
    let eta = part("eta", IorPart::Eta, "metal-Cu-eta")?;
    let k = part("k", IorPart::K, "metal-Cu-k")?;
    Ok(Bsdf::conductor(
        eta.as_vec3(),
        k.as_vec3(),
        glam::Vec3::ONE,
        roughness,
    ))
}

/// `coateddiffuse` as ppm's plastic (a Lambertian base under a dielectric coating): the same
/// reflectance, coating index and roughness. pbrt-v4 simulates the layers stochastically
/// (Guo et al. 2018's position-free random walk, `LayeredBxDF`) with a medium of `thickness`
/// and `albedo` between them, which attenuates by exp(-thickness / |cos|) per crossing even
/// at albedo 0; ppm's plastic sums the internal reflections in closed form without that
/// attenuation. A warning says so; a scattering layer (albedo > 0) is an error.
fn coated_diffuse(
    desc: &Description,
    p: &ParamSet,
    roughness: Option<Microfacet>,
    warnings: &mut Vec<String>,
) -> Result<Bsdf, LoadError> {
    let base = reflectance(desc, p, "reflectance", 0.5)?;
    let eta = eta(p)?;
    let albedo = reflectance(desc, p, "albedo", 0.0)?;
    if albedo != DVec3::ZERO {
        return Err(p.error("a scattering coating (albedo > 0) is not supported yet"));
    }
    if plain_float(p, "g", 0.0)? != 0.0 {
        return Err(p.error("a coating's phase function g is not supported yet"));
    }
    let thickness = plain_float(p, "thickness", 0.01)?;
    p.ignore(&["maxdepth", "nsamples"]);
    warnings.push(format!(
        "{}: {}: coateddiffuse approximated by ppm's plastic (closed-form sum of the coating's internal reflections instead of pbrt's stochastic layers; no attenuation through a layer of thickness {thickness}, which in pbrt darkens by about {:.1}% at normal incidence)",
        p.loc,
        p.what,
        100.0 * (1.0 - (-2.0 * thickness).exp())
    ));
    Ok(Bsdf::plastic(
        base.as_vec3(),
        glam::Vec3::ONE,
        eta as f32,
        roughness,
    ))
}
