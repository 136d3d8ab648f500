//! `{ type: environment }` lights of scene format v1: a constant `color` or a lat-long
//! radiance map `file` (radiance in W/(m^2 sr)), times `scale`, turned by `rotate`. The map's
//! frame (`envmap.rs` in ppm-core) is Mitsuba 3's: its top row is +y, its left edge looks
//! along -z and a quarter of the way across along +x.

use crate::error::LoadError;
use crate::yaml::LightDesc;
use glam::Mat3;
use ppm_core::light::{EnvironmentLight, EnvironmentMap, Light};
use std::path::Path;
use std::sync::Arc;

/// The environment light of `l` (at `field` of the scene file `path`).
///
/// `placement` (the light's `transform`, if any) turns the map after `rotate`; it must be a
/// rotation (orthonormal, determinant 1): an environment at infinity has no position or size.
pub(crate) fn light(
    l: &LightDesc,
    field: &str,
    path: &Path,
    placement: Option<glam::DMat4>,
) -> Result<Light, LoadError> {
    let invalid = |name: &str, why: String| LoadError::invalid(path, format!("{field}{name}"), why);
    let map = match (&l.color, &l.file) {
        (Some(c), None) => EnvironmentMap::Constant(c.value()),
        (None, Some(file)) => {
            let file_path = path.parent().unwrap_or(Path::new("")).join(file);
            let map = crate::radiance_map::read_map(&file_path)
                .map_err(|e| invalid(".file", format!("{}: {e}", file_path.display())))?;
            EnvironmentMap::Image(Arc::new(map))
        }
        (Some(_), Some(_)) => {
            return Err(invalid(
                "",
                "an environment light takes `color` or `file`, not both".into(),
            ))
        }
        (None, None) => return Err(invalid(
            "",
            "an environment light needs `color` (a constant radiance) or `file` (a lat-long map)"
                .into(),
        )),
    };
    let scale = l.scale.as_ref().map_or(1.0, |s| s.0);
    let rotation = match &l.rotate {
        None => Mat3::IDENTITY,
        Some(r) => {
            let axis = r.axis.value();
            let Some(axis) = axis.try_normalize() else {
                return Err(invalid(".rotate.axis", format!("{axis} has no direction")));
            };
            Mat3::from_axis_angle(axis, r.angle.0.to_radians())
        }
    };
    let rotation = match placement {
        None => rotation,
        Some(m) => {
            let r = glam::DMat3::from_mat4(m);
            let orthonormal = (r * r.transpose()).abs_diff_eq(glam::DMat3::IDENTITY, 1e-6);
            if !(orthonormal && r.determinant() > 0.0) {
                return Err(invalid(
                    ".transform",
                    "an environment light takes only rotations (no scale, shear or mirror)".into(),
                ));
            }
            r.as_mat3() * rotation
        }
    };
    EnvironmentLight::new(map, scale, rotation)
        .map(Light::Environment)
        .ok_or_else(|| invalid("", "not a valid environment light".into()))
}
