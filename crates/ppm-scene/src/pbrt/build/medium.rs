//! `MakeNamedMedium` and `MediumInterface` to ppm's absorbing media: ppm renders Beer-Lambert
//! absorption between surfaces (`ppm_core::medium`), which pbrt-v4 writes as a `homogeneous`
//! medium that does not scatter (`sigma_s` 0: pbrt's default is 1, so it must be written) and
//! does not emit. Transmittance over a segment of length t is exp(-sigma_a scale t) per
//! channel (pbrt-v4 `HomogeneousMedium`: sigma_a and sigma_s both multiplied by `scale`).
//! Anything else (a scattering or emitting medium, another type, a `preset`) is an error
//! naming the medium and its directive, never approximated.

use super::super::params::ParamSet;
use super::super::scene::{Description, MediaNames};
use super::super::spectrum::SpectrumValue;
use crate::LoadError;
use glam::DVec3;
use ppm_core::medium::MediumInterface;

/// The absorbing media of a `MediumInterface`: `inside` (opposite the surface's normal) is
/// ppm's interior, `outside` its exterior; "" is no medium.
pub fn interface(desc: &Description, names: &MediaNames) -> Result<MediumInterface, LoadError> {
    let sigma = |name: &str| -> Result<DVec3, LoadError> {
        if name.is_empty() {
            return Ok(DVec3::ZERO);
        }
        absorption(desc, name, names)
    };
    Ok(MediumInterface {
        interior: sigma(&names.inside)?.as_vec3(),
        exterior: sigma(&names.outside)?.as_vec3(),
    })
}

/// sigma_a * scale of the medium `name`, which must be homogeneous, non-scattering and dark.
fn absorption(desc: &Description, name: &str, used: &MediaNames) -> Result<DVec3, LoadError> {
    let entity = desc.media.get(name).ok_or_else(|| {
        used.loc.error(format!(
            "MediumInterface: no medium \"{name}\" (MakeNamedMedium)"
        ))
    })?;
    let p = ParamSet::new(
        format!("MakeNamedMedium \"{name}\""),
        entity.loc.clone(),
        &entity.params,
        &[],
    );
    let kind = p.string_opt("type")?.unwrap_or("");
    if kind != "homogeneous" {
        return Err(p.error(format!(
            "medium type \"{kind}\" is not supported yet (only a homogeneous medium with \"rgb sigma_s\" [0 0 0], which ppm renders as Beer-Lambert absorption)"
        )));
    }
    if p.has("preset") {
        p.get("preset");
        return Err(p.error("a preset (measured scattering coefficients) scatters; ppm renders absorbing media only"));
    }
    let rgb = |what: &str| -> Result<Option<DVec3>, LoadError> {
        match p.spectrum(what)? {
            None => Ok(None),
            Some((SpectrumValue::Rgb(c), _)) if c.min_element() >= 0.0 && c.is_finite() => {
                Ok(Some(c))
            }
            Some((_, param)) => Err(p.error_at(
                param,
                "only a non-negative \"rgb\" value is supported for a medium yet",
            )),
        }
    };
    // pbrt-v4's defaults: sigma_a = sigma_s = 1, scale 1, no emission.
    let sigma_a = rgb("sigma_a")?.unwrap_or(DVec3::ONE);
    let sigma_s = rgb("sigma_s")?.unwrap_or(DVec3::ONE);
    let scale = p.float("scale", 1.0)?;
    if !(scale >= 0.0 && scale.is_finite()) {
        return Err(p.error(format!("scale {scale} is not a non-negative number")));
    }
    if sigma_s != DVec3::ZERO {
        return Err(p.error(format!(
            "it scatters (sigma_s {sigma_s}, pbrt's default 1): ppm renders absorbing media only; write \"rgb sigma_s\" [0 0 0] for absorption alone"
        )));
    }
    if rgb("Le")?.is_some_and(|le| le != DVec3::ZERO) {
        return Err(p.error("an emitting medium (Le) is not supported"));
    }
    // Without scattering the phase function never acts.
    p.ignore(&["g", "Lescale"]);
    p.finish()?;
    Ok(sigma_a * scale)
}
