//! Emitter plugins to ppm's lights: one function per plugin, dispatched by [`add_emitter`].
//! `area` belongs to a shape and gives its material's emission ([`area_radiance`]).

use super::unsupported;
use crate::mitsuba::props::Props;
use crate::mitsuba::spectrum::Role;
use crate::mitsuba::tree::SceneTree;
use crate::LoadError;
use glam::{DMat4, DVec3, Vec3};
use ppm_core::light::{Light, PointLight};
use ppm_core::scene::SceneBuilder;

/// A top-level emitter, added to `builder`; what it approximates goes to `warnings`.
pub fn add_emitter(
    tree: &SceneTree,
    index: usize,
    builder: &mut SceneBuilder,
    warnings: &mut Vec<String>,
) -> Result<(), LoadError> {
    let p = Props::new(tree, index);
    let light = match p.object.plugin.as_str() {
        "point" => point(&p)?,
        "spot" => spot(&p, warnings)?,
        "directional" => directional(&p)?,
        "area" => return Err(p.error("emitter `area` must be nested in a <shape>")),
        "constant" | "envmap" => return super::environment::add(tree, index, builder, warnings),
        _ => return Err(unsupported(p.object)),
    };
    p.finish()?;
    builder.add_light(light);
    Ok(())
}

/// A non-negative, finite colour of an emitter.
pub(super) fn emission(p: &Props, name: &str, default: Option<DVec3>) -> Result<Vec3, LoadError> {
    let c = match (p.colour_opt(name, Role::Emission)?, default) {
        (Some(c), _) | (None, Some(c)) => c,
        (None, None) => {
            return Err(p.error(format!("emitter `{}` needs `{name}`", p.object.plugin)))
        }
    };
    let c = c.as_vec3();
    if !(c.is_finite() && c.min_element() >= 0.0) {
        return Err(p.error(format!(
            "emitter `{}`: `{name}` {c} is negative or out of single-precision range",
            p.object.plugin
        )));
    }
    Ok(c)
}

/// `<emitter type="area">` on a shape: its `radiance`, emitted on the side the shape's
/// normal faces (ppm's area lights are one-sided like Mitsuba's).
pub fn area_radiance(tree: &SceneTree, index: usize) -> Result<Vec3, LoadError> {
    let p = Props::new(tree, index);
    if p.object.plugin != "area" {
        return Err(unsupported(p.object));
    }
    let le = emission(&p, "radiance", None)?;
    p.finish()?;
    Ok(le)
}

/// `point`: `intensity` in W/sr (default 1), at `position` or the origin moved by
/// `to_world`.
fn point(p: &Props) -> Result<Light, LoadError> {
    let intensity = emission(p, "intensity", Some(DVec3::ONE))?;
    let m = p.transform("to_world")?;
    let position = match p.point_opt("position")? {
        Some(x) => x,
        None => m.transform_point3(DVec3::ZERO),
    };
    Ok(Light::Point(PointLight {
        position: position.as_vec3(),
        intensity,
    }))
}

/// The unit +z axis of `to_world`, or an error if the transform collapses it.
fn axis(p: &Props, m: &DMat4) -> Result<DVec3, LoadError> {
    m.transform_vector3(DVec3::Z)
        .try_normalize()
        .ok_or_else(|| {
            p.error(format!(
                "{}: `to_world` maps the +z axis to no direction",
                p.object.describe()
            ))
        })
}

/// `spot`: radiant intensity `intensity` (W/sr, default 1) on the axis, the +z axis of
/// `to_world` from its origin; full within `beam_width` (degrees, default 3/4 of the cutoff),
/// none beyond `cutoff_angle` (default 20).
///
/// Mitsuba 3's falloff between the two is linear in the angle theta,
/// `(theta_e - theta) / (theta_e - theta_s)`; ppm's spot (`ppm_core::light::SpotLight`, as
/// pbrt-v4's) is a smoothstep in cos theta. The two curves differ inside the band by up to
/// about 0.1 of the axis's intensity, and the powers by the ratio the warning states:
/// integrating each over the band (Mitsuba's by parts),
/// `Phi_mitsuba / (2 pi I0) = (1 - cos theta_s) + cos theta_s + (sin theta_s - sin theta_e) / (theta_e - theta_s)`
/// `= 1 + (sin theta_s - sin theta_e) / (theta_e - theta_s)`
/// and `Phi_ppm / (2 pi I0) = (1 - cos theta_s) + (cos theta_s - cos theta_e) / 2`
/// (ppm's 1.3 % brighter at Mitsuba's defaults, 15 and 20 degrees).
fn spot(p: &Props, warnings: &mut Vec<String>) -> Result<Light, LoadError> {
    let intensity = emission(p, "intensity", Some(DVec3::ONE))?;
    let m = p.transform("to_world")?;
    let cutoff = p.float("cutoff_angle", 20.0)?;
    let beam = p.float("beam_width", 0.75 * cutoff)?;
    if !(cutoff > 0.0 && cutoff <= 180.0 && beam >= 0.0 && beam <= cutoff) {
        return Err(p.error(format!(
            "emitter `spot`: needs 0 <= beam_width <= cutoff_angle <= 180 with cutoff_angle > 0 (degrees), got beam_width {beam} and cutoff_angle {cutoff}"
        )));
    }
    let (theta_s, theta_e) = (beam.to_radians(), cutoff.to_radians());
    if theta_s < theta_e {
        let band = theta_e - theta_s;
        let mitsuba = 1.0 + (theta_s.sin() - theta_e.sin()) / band;
        let ppm = 1.0 - theta_s.cos() + 0.5 * (theta_s.cos() - theta_e.cos());
        warnings.push(format!(
            "{}: emitter `spot`: between beam_width {beam}° and cutoff_angle {cutoff}° Mitsuba's falloff is linear in the angle, ppm's a smoothstep in its cosine: the light's power differs by {:+.2} %",
            p.location(),
            100.0 * (ppm / mitsuba - 1.0)
        ));
    }
    let position = m.transform_point3(DVec3::ZERO);
    let direction = axis(p, &m)?;
    Light::spot(
        position.as_vec3(),
        direction.as_vec3(),
        intensity,
        theta_e as f32,
        theta_s as f32,
    )
    .ok_or_else(|| {
        p.error("emitter `spot`: not a valid spot light (position or direction out of range)")
    })
}

/// `directional`: parallel light of `irradiance` (W/m², default 1, on a surface facing it)
/// travelling along `direction`, or along the +z axis of `to_world` (not both, as in
/// Mitsuba 3).
fn directional(p: &Props) -> Result<Light, LoadError> {
    let irradiance = emission(p, "irradiance", Some(DVec3::ONE))?;
    let given = p.point_opt("direction")?;
    let direction = match (given, p.get("to_world").is_some()) {
        (Some(_), true) => {
            return Err(
                p.error("emitter `directional`: give either `direction` or `to_world`, not both")
            )
        }
        (Some(d), false) => d
            .try_normalize()
            .ok_or_else(|| p.error("emitter `directional`: `direction` is zero or not finite"))?,
        (None, _) => axis(p, &p.transform("to_world")?)?,
    };
    Light::directional(direction.as_vec3(), irradiance)
        .ok_or_else(|| p.error("emitter `directional`: `direction` is out of range"))
}
