//! The Mitsuba-style materials of scene format v1 (`conductor`, `roughconductor`,
//! `dielectric`, `roughdielectric`, `thindielectric`, `plastic`, `roughplastic`, `twosided`):
//! their parameters, named and defaulted as Mitsuba 3 names and defaults them, checked and
//! mapped to ppm-core BSDFs. See `docs/scene-format.md`.

use crate::build::check_fields;
use crate::error::LoadError;
use crate::ior::named_ior;
use crate::yaml::{MaterialDesc, MaterialType};
use glam::Vec3;
use ppm_core::bsdf::metals::{metal, METALS};
use ppm_core::bsdf::{Beckmann, Bsdf, Dielectric, Ggx, Microfacet, ThinDielectric};
use std::path::Path;

/// Mitsuba's default roughness of its rough materials.
const DEFAULT_ALPHA: f32 = 0.1;

/// Every field a material may have, with whether `d` has it.
pub(crate) fn present_fields(d: &MaterialDesc) -> [(&'static str, bool); 21] {
    [
        ("color", d.color.is_some()),
        ("emission", d.emission.is_some()),
        ("ior", d.ior.is_some()),
        ("diffuse", d.diffuse.is_some()),
        ("specular", d.specular.is_some()),
        ("exponent", d.exponent.is_some()),
        ("alpha", d.alpha.is_some()),
        ("alpha_u", d.alpha_u.is_some()),
        ("alpha_v", d.alpha_v.is_some()),
        ("distribution", d.distribution.is_some()),
        ("int_ior", d.int_ior.is_some()),
        ("ext_ior", d.ext_ior.is_some()),
        ("eta", d.eta.is_some()),
        ("k", d.k.is_some()),
        ("material", d.material.is_some()),
        ("specular_reflectance", d.specular_reflectance.is_some()),
        ("specular_transmittance", d.specular_transmittance.is_some()),
        ("diffuse_reflectance", d.diffuse_reflectance.is_some()),
        ("bsdf", d.bsdf.is_some()),
        ("absorption", d.absorption.is_some()),
        ("ext_absorption", d.ext_absorption.is_some()),
    ]
}

/// The fields each Mitsuba-style type takes (besides `type`), `emission` included: a
/// `twosided`'s nested material may not emit (it is checked separately).
fn allowed(kind: MaterialType) -> &'static [&'static str] {
    const ROUGH: [&str; 4] = ["alpha", "alpha_u", "alpha_v", "distribution"];
    match kind {
        MaterialType::Conductor => &["eta", "k", "material", "specular_reflectance", "emission"],
        MaterialType::RoughConductor => &[
            "eta",
            "k",
            "material",
            "specular_reflectance",
            "emission",
            ROUGH[0],
            ROUGH[1],
            ROUGH[2],
            ROUGH[3],
        ],
        MaterialType::Dielectric => &[
            "int_ior",
            "ext_ior",
            "specular_reflectance",
            "specular_transmittance",
            "emission",
            "absorption",
            "ext_absorption",
        ],
        MaterialType::ThinDielectric => &[
            "int_ior",
            "ext_ior",
            "specular_reflectance",
            "specular_transmittance",
            "emission",
        ],
        MaterialType::RoughDielectric => &[
            "int_ior",
            "ext_ior",
            "specular_reflectance",
            "specular_transmittance",
            "emission",
            "absorption",
            "ext_absorption",
            ROUGH[0],
            ROUGH[1],
            ROUGH[2],
            ROUGH[3],
        ],
        MaterialType::Plastic => &[
            "int_ior",
            "ext_ior",
            "diffuse_reflectance",
            "specular_reflectance",
            "emission",
        ],
        MaterialType::RoughPlastic => &[
            "int_ior",
            "ext_ior",
            "diffuse_reflectance",
            "specular_reflectance",
            "emission",
            ROUGH[0],
            ROUGH[3],
        ],
        MaterialType::TwoSided => &["bsdf", "emission"],
        MaterialType::Diffuse
        | MaterialType::Mirror
        | MaterialType::Glass
        | MaterialType::Phong => &[],
    }
}

/// The type's name in the file.
pub(crate) fn type_name(kind: MaterialType) -> &'static str {
    match kind {
        MaterialType::Diffuse => "diffuse",
        MaterialType::Mirror => "mirror",
        MaterialType::Glass => "glass",
        MaterialType::Phong => "phong",
        MaterialType::Conductor => "conductor",
        MaterialType::RoughConductor => "roughconductor",
        MaterialType::Dielectric => "dielectric",
        MaterialType::RoughDielectric => "roughdielectric",
        MaterialType::ThinDielectric => "thindielectric",
        MaterialType::Plastic => "plastic",
        MaterialType::RoughPlastic => "roughplastic",
        MaterialType::TwoSided => "twosided",
    }
}

/// The BSDF of a Mitsuba-style material `d` (at `field`, e.g. `materials.gold`); `None` for
/// the original four types, which `build.rs` maps.
pub(crate) fn mitsuba_bsdf(
    d: &MaterialDesc,
    field: &str,
    path: &Path,
) -> Result<Option<Bsdf>, LoadError> {
    let kind = d.kind;
    let name = type_name(kind);
    if allowed(kind).is_empty() {
        return Ok(None);
    }
    check_fields(
        path,
        field,
        &format!("{name} material"),
        &present_fields(d),
        allowed(kind),
    )?;
    let err = |sub: &str, msg: String| LoadError::invalid(path, format!("{field}{sub}"), msg);
    let white =
        |c: &Option<crate::texture_desc::Colour>| c.as_ref().map_or(Vec3::ONE, |c| c.value());
    let bsdf = match kind {
        MaterialType::Conductor | MaterialType::RoughConductor => {
            let (eta, k) = conductor_index(d, &err)?;
            let roughness = if kind == MaterialType::RoughConductor {
                Some(roughness(d, true, &err)?)
            } else {
                None
            };
            Bsdf::conductor(eta, k, white(&d.specular_reflectance), roughness)
        }
        MaterialType::Dielectric | MaterialType::RoughDielectric | MaterialType::ThinDielectric => {
            let eta = relative_index(d, "bk7", &err)?;
            let (specular_reflectance, specular_transmittance) = (
                white(&d.specular_reflectance),
                white(&d.specular_transmittance),
            );
            match kind {
                MaterialType::ThinDielectric => Bsdf::ThinDielectric(ThinDielectric {
                    eta,
                    specular_reflectance,
                    specular_transmittance,
                }),
                _ => Bsdf::Dielectric(Dielectric {
                    eta,
                    specular_reflectance,
                    specular_transmittance,
                    roughness: (kind == MaterialType::RoughDielectric)
                        .then(|| roughness(d, true, &err))
                        .transpose()?,
                }),
            }
        }
        MaterialType::Plastic | MaterialType::RoughPlastic => {
            let eta = relative_index(d, "polypropylene", &err)?;
            let diffuse = d
                .diffuse_reflectance
                .as_ref()
                .map_or(Vec3::splat(0.5), |c| c.value());
            let roughness = (kind == MaterialType::RoughPlastic)
                .then(|| roughness(d, false, &err))
                .transpose()?;
            // The smooth coating's internal reflectance is a polynomial fit (Mitsuba's) that
            // exceeds 1, creating energy, above a relative index of about 3.9.
            if roughness.is_none() && !(eta > 1.0 && eta <= 3.0) {
                return Err(err(
                    "",
                    format!(
                        "int_ior / ext_ior is {eta}; a plastic's coating needs a relative index \
                         in (1, 3]"
                    ),
                ));
            }
            Bsdf::plastic(diffuse, white(&d.specular_reflectance), eta, roughness)
        }
        MaterialType::TwoSided => {
            let nested = d.bsdf.as_deref().ok_or_else(|| {
                err(
                    "",
                    "a twosided material needs `bsdf`, the material it shows on both sides".into(),
                )
            })?;
            let nested_field = format!("{field}.bsdf");
            if nested.emission.is_some() {
                return Err(LoadError::invalid(
                    path,
                    nested_field,
                    "`emission` belongs to the twosided material, not to its `bsdf`",
                ));
            }
            let inner = match mitsuba_bsdf(nested, &nested_field, path)? {
                Some(b) => b,
                None => crate::build::classic_bsdf(nested, &nested_field, path, &mut Vec::new())?,
            };
            inner.two_sided().ok_or_else(|| {
                LoadError::invalid(
                    path,
                    nested_field,
                    format!(
                        "a {} material refracts: its two sides are two media and cannot be made \
                         the same (twosided takes conductors, plastics and the reflecting types)",
                        type_name(nested.kind)
                    ),
                )
            })?
        }
        MaterialType::Diffuse
        | MaterialType::Mirror
        | MaterialType::Glass
        | MaterialType::Phong => {
            unreachable!("handled above")
        }
    };
    Ok(Some(bsdf))
}

/// A conductor's `eta` and `k`: given as numbers (k defaults to 1, eta to 0) or as a named
/// `material`, not both; neither is Mitsuba's `none`, a perfect mirror (eta 0, k 1).
fn conductor_index(
    d: &MaterialDesc,
    err: &impl Fn(&str, String) -> LoadError,
) -> Result<(Vec3, Vec3), LoadError> {
    match (&d.material, d.eta.is_some() || d.k.is_some()) {
        (Some(_), true) => Err(err(
            "",
            "give either `material` or `eta` and `k`, not both".into(),
        )),
        (Some(name), false) => metal(name).map(|m| (m.eta, m.k)).ok_or_else(|| {
            let names: Vec<&str> = METALS.iter().map(|m| m.name).collect();
            err(
                ".material",
                format!(
                    "unknown conductor `{name}`; Mitsuba's presets: {}",
                    names.join(", ")
                ),
            )
        }),
        (None, _) => Ok((
            d.eta.as_ref().map_or(Vec3::ZERO, |e| e.value()),
            d.k.as_ref().map_or(Vec3::ONE, |k| k.value()),
        )),
    }
}

/// `int_ior / ext_ior`, with Mitsuba's defaults (`default_int`, and air outside); the two
/// must differ.
fn relative_index(
    d: &MaterialDesc,
    default_int: &str,
    err: &impl Fn(&str, String) -> LoadError,
) -> Result<f32, LoadError> {
    let int = d
        .int_ior
        .map_or_else(|| named_ior(default_int).unwrap(), |i| i.0);
    let ext = d.ext_ior.map_or_else(|| named_ior("air").unwrap(), |i| i.0);
    if int == ext {
        return Err(err(
            "",
            format!("int_ior and ext_ior are both {int}: the interface would not be there"),
        ));
    }
    Ok(int / ext)
}

/// The microfacet distribution named by `distribution` (`ggx`, the default, or `beckmann`) of
/// roughness `alpha` (default 0.1) or `alpha_u` and `alpha_v` (both, and only if `anisotropic`
/// is allowed).
fn roughness(
    d: &MaterialDesc,
    anisotropic: bool,
    err: &impl Fn(&str, String) -> LoadError,
) -> Result<Microfacet, LoadError> {
    let beckmann = match d.distribution.as_deref() {
        None => false,
        Some(dist) if dist.eq_ignore_ascii_case("ggx") => false,
        Some(dist) if dist.eq_ignore_ascii_case("beckmann") => true,
        Some(dist) => {
            return Err(err(
                ".distribution",
                format!("`{dist}` is not a microfacet distribution: `ggx` or `beckmann`"),
            ))
        }
    };
    let make = |ax: f32, ay: f32| -> Microfacet {
        if beckmann {
            Beckmann::new(ax, ay).into()
        } else {
            Ggx::new(ax, ay).into()
        }
    };
    match (&d.alpha, &d.alpha_u, &d.alpha_v) {
        (Some(_), Some(_), _) | (Some(_), _, Some(_)) => Err(err(
            "",
            "give either `alpha` or `alpha_u` and `alpha_v`, not both".into(),
        )),
        (None, Some(u), Some(v)) if anisotropic => Ok(make(u.0, v.0)),
        (None, Some(_), None) | (None, None, Some(_)) => Err(err(
            "",
            "an anisotropic roughness needs both `alpha_u` and `alpha_v`".into(),
        )),
        (None, Some(_), Some(_)) => Err(err(
            "",
            "roughplastic takes one `alpha`, no anisotropic roughness (as in Mitsuba)".into(),
        )),
        (alpha, None, None) => {
            let a = alpha.as_ref().map_or(DEFAULT_ALPHA, |a| a.value());
            Ok(make(a, a))
        }
    }
}
