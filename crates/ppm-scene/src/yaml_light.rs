//! The lights of a YAML scene's `lights:` list: which fields each type takes, the required
//! ones named when missing, and the mapping to ppm-core's point, spot, directional and
//! environment lights.

use crate::build::check_fields;
use crate::error::LoadError;
use crate::object_transform::object_matrix;
use crate::yaml::{LightDesc, LightType};
use glam::{DMat4, DVec3};
use ppm_core::light::{Light, PointLight};
use std::path::Path;

/// A light of the `lights:` list (at `field`), its points made relative to `origin`.
pub(crate) fn light(
    l: &LightDesc,
    field: &str,
    origin: DVec3,
    path: &Path,
) -> Result<Light, LoadError> {
    let kind = light_type_name(l.kind);
    let present = [
        ("position", l.position.is_some()),
        ("intensity", l.intensity.is_some()),
        ("irradiance", l.irradiance.is_some()),
        ("direction", l.direction.is_some()),
        ("look_at", l.look_at.is_some()),
        ("cone_angle", l.cone_angle.is_some()),
        ("falloff_start", l.falloff_start.is_some()),
        ("color", l.color.is_some()),
        ("file", l.file.is_some()),
        ("scale", l.scale.is_some()),
        ("rotate", l.rotate.is_some()),
        ("mapping", l.mapping.is_some()),
        ("to_world", l.to_world.is_some()),
        ("transform", l.transform.is_some()),
    ];
    let allowed: &[&str] = match l.kind {
        LightType::Point => &["position", "intensity", "transform"],
        LightType::Spot => &[
            "position",
            "intensity",
            "direction",
            "look_at",
            "cone_angle",
            "falloff_start",
            "transform",
        ],
        LightType::Directional => &["direction", "irradiance", "transform"],
        LightType::Environment => &[
            "color",
            "file",
            "scale",
            "rotate",
            "to_world",
            "mapping",
            "transform",
        ],
    };
    check_fields(path, field, kind, &present, allowed)?;
    let invalid = |name: &str, why: String| LoadError::invalid(path, format!("{field}{name}"), why);
    // The light's transform, followed by the move to camera-relative coordinates: points by
    // it (in f64, rounded once), directions by its linear part. Without one, points are
    // made relative to `origin` and directions kept as written.
    let placement = match &l.transform {
        Some(steps) => Some(DMat4::from_translation(-origin) * object_matrix(steps, field, path)?),
        None => None,
    };
    let place_point = |p: DVec3| match placement {
        Some(m) => m.transform_point3(p).as_vec3(),
        None => (p - origin).as_vec3(),
    };
    let place_direction = |d: DVec3| match placement {
        Some(m) => m.transform_vector3(d).as_vec3(),
        None => d.as_vec3(),
    };
    // The required fields, each named when missing (a transformed light's position may be
    // left out: the transform places the origin).
    let position = || match (&l.position, placement) {
        (Some(p), _) => Ok(place_point(p.0)),
        (None, Some(_)) => Ok(place_point(DVec3::ZERO)),
        (None, None) => Err(invalid("", format!("a {kind} needs `position`"))),
    };
    let intensity = || {
        l.intensity
            .as_ref()
            .map(|i| i.value())
            .ok_or_else(|| invalid("", format!("a {kind} needs `intensity`")))
    };
    match l.kind {
        LightType::Environment => crate::environment::light(l, field, path, placement),
        LightType::Point => Ok(Light::Point(PointLight {
            position: position()?,
            intensity: intensity()?,
        })),
        LightType::Directional => {
            let direction = l.direction.as_ref().ok_or_else(|| {
                invalid(
                    "",
                    "a directional light needs `direction` (the way its light travels)".into(),
                )
            })?;
            let direction = place_direction(direction.0);
            let irradiance = l
                .irradiance
                .as_ref()
                .ok_or_else(|| invalid("", "a directional light needs `irradiance`".into()))?
                .value();
            Light::directional(direction, irradiance).ok_or_else(|| {
                invalid(".direction", "a zero direction has no way to travel".into())
            })
        }
        LightType::Spot => {
            let (position, intensity) = (position()?, intensity()?);
            let direction = match (&l.direction, &l.look_at) {
                (Some(d), None) => place_direction(d.0),
                (None, Some(target)) => place_point(target.0) - position,
                (Some(_), Some(_)) => {
                    return Err(invalid(
                        "",
                        "a spot light takes `direction` or `look_at`, not both".into(),
                    ))
                }
                (None, None) => {
                    return Err(invalid(
                        "",
                        "a spot light needs `direction` or `look_at`".into(),
                    ))
                }
            };
            let axis = if l.direction.is_some() {
                ".direction"
            } else {
                ".look_at"
            };
            if !(direction.is_finite() && direction.length() > 0.0) {
                return Err(invalid(
                    axis,
                    "the axis has no direction (a zero direction, or look_at at position)".into(),
                ));
            }
            let cone = l
                .cone_angle
                .as_ref()
                .ok_or_else(|| invalid("", "a spot light needs `cone_angle`".into()))?;
            let (cone, cone_radians) = (cone.degrees, cone.radians);
            if cone > 180.0 {
                return Err(invalid(
                    ".cone_angle",
                    format!("{cone} degrees is more than 180 (the whole sphere)"),
                ));
            }
            // No falloff start: full intensity up to the cone's edge.
            let (start, start_radians) = l
                .falloff_start
                .as_ref()
                .map_or((cone, cone_radians), |s| (s.degrees, s.radians));
            if start > cone {
                return Err(invalid(
                    ".falloff_start",
                    format!("{start} degrees is beyond cone_angle ({cone} degrees)"),
                ));
            }
            Light::spot(position, direction, intensity, cone_radians, start_radians)
                .ok_or_else(|| invalid("", "not a valid spot light".into()))
        }
    }
}

fn light_type_name(kind: LightType) -> &'static str {
    match kind {
        LightType::Point => "point light",
        LightType::Spot => "spot light",
        LightType::Directional => "directional light",
        LightType::Environment => "environment light",
    }
}
