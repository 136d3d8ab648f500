//! A shape's `interior` and `exterior` media to ppm's [`MediumInterface`]: ppm renders
//! purely absorbing media (Beer-Lambert, `ppm_core::medium`), which Mitsuba 3 writes as a
//! `homogeneous` medium of albedo 0. Any medium that scatters (albedo > 0, the default 0.75),
//! or another plugin (`heterogeneous`), is an error naming it, never approximated.

use super::unsupported;
use crate::mitsuba::props::Props;
use crate::mitsuba::spectrum::Role;
use crate::mitsuba::tree::{SceneTree, Value};
use crate::LoadError;
use glam::DVec3;
use ppm_core::medium::MediumInterface;

/// The media of the shape whose properties are `shape`: `<medium name="interior">` (the side
/// opposite the normal, as in Mitsuba) and `<medium name="exterior">`, nested or referenced;
/// clear where absent. A medium under another name is an error.
pub fn shape_media(shape: &Props) -> Result<MediumInterface, LoadError> {
    let side = |name: &str| -> Result<Option<usize>, LoadError> {
        match shape.get(name).map(|p| (&p.value, &p.location)) {
            None => Ok(None),
            Some((Value::Object(o), _)) if shape.tree.objects[*o].class == "medium" => Ok(Some(*o)),
            Some((_, location)) => Err(location.error(format!(
                "`{name}` of {} must be a <medium>",
                shape.object.describe()
            ))),
        }
    };
    let (interior, exterior) = (side("interior")?, side("exterior")?);
    if let Some(&other) = shape
        .objects("medium")
        .iter()
        .find(|&&o| Some(o) != interior && Some(o) != exterior)
    {
        let o = &shape.tree.objects[other];
        return Err(o.location.error(format!(
            "{} at {} in {} has no name `interior` or `exterior`: ppm cannot tell which side it fills",
            o.describe(),
            o.location,
            shape.object.describe()
        )));
    }
    let sigma = |m: Option<usize>| m.map_or(Ok(DVec3::ZERO), |m| absorption(shape.tree, m));
    Ok(MediumInterface {
        interior: sigma(interior)?.as_vec3(),
        exterior: sigma(exterior)?.as_vec3(),
    })
}

/// The first of the top-level `media` that none of `shapes` names as its `interior` or
/// `exterior` (such a medium could only be the camera's, which ppm does not read).
pub fn unplaced(tree: &SceneTree, media: &[usize], shapes: &[usize]) -> Option<usize> {
    let placed = |m: usize| {
        shapes.iter().any(|&s| {
            tree.objects[s].properties.iter().any(|p| {
                matches!(p.value, Value::Object(o) if o == m)
                    && (p.name == "interior" || p.name == "exterior")
            })
        })
    };
    media.iter().copied().find(|&m| !placed(m))
}

/// sigma_a (per scene unit) of `<medium type="homogeneous">` with `albedo` 0: every
/// extinction event absorbs, so sigma_a = sigma_t * scale (Mitsuba's defaults: sigma_t 1,
/// scale 1). Its `phase` (nested) and the sampling flags do not change an absorbing medium.
fn absorption(tree: &SceneTree, index: usize) -> Result<DVec3, LoadError> {
    let p = Props::new(tree, index);
    if p.object.plugin != "homogeneous" {
        return Err(unsupported(p.object));
    }
    // Mitsuba's default albedo is 0.75: a medium that does not say 0 scatters.
    let albedo = p.colour("albedo", DVec3::splat(0.75), Role::Reflectance)?;
    if albedo != DVec3::ZERO {
        return Err(p.error(format!(
            "{} at {} scatters (albedo {albedo}): ppm renders only absorbing media, `albedo` 0",
            p.object.describe(),
            p.object.location
        )));
    }
    // An extinction coefficient is unbounded: its spectrum is converted without an illuminant.
    let sigma_t = p.colour("sigma_t", DVec3::ONE, Role::Emission)?;
    let scale = p.float("scale", 1.0)?;
    let sigma_a = sigma_t * scale;
    if !(sigma_a.is_finite() && sigma_a.min_element() >= 0.0 && sigma_a.as_vec3().is_finite()) {
        return Err(p.error(format!(
            "{}: sigma_t * scale = {sigma_a} must be finite and non-negative",
            p.object.describe()
        )));
    }
    p.objects("phase");
    p.ignore(&["sample_emitters", "has_spectral_extinction"]);
    p.finish()?;
    Ok(sigma_a)
}
