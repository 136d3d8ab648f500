//! `{ type: environment }` lights of scene format v1: a constant `color` or a lat-long
//! radiance map `file` (radiance in W/(m^2 sr)), times `scale`, turned by `rotate` (or the
//! matrix `to_world`). The map's
//! frame (`envmap.rs` in ppm-core) is Mitsuba 3's: its top row is +y, its left edge looks
//! along -z and a quarter of the way across along +x.

use crate::error::LoadError;
use crate::yaml::LightDesc;
use glam::Mat3;
use ppm_core::light::{EnvironmentLight, EnvironmentMap, Light};
use std::path::Path;
use std::sync::Arc;

/// The environment light of `l` (at `field` of the scene file `path`).
pub(crate) fn light(l: &LightDesc, field: &str, path: &Path) -> Result<Light, LoadError> {
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
    let rotation = match (&l.rotate, &l.to_world) {
        (Some(_), Some(_)) => {
            return Err(invalid(
                "",
                "an environment light takes `rotate` or `to_world`, not both".into(),
            ))
        }
        (None, Some(m)) => {
            let rows: Vec<f32> = m.iter().map(|x| x.0).collect();
            let rows: [f32; 9] = rows.try_into().map_err(|_| {
                invalid(
                    ".to_world",
                    format!("{} numbers; a 3 x 3 matrix is 9, row by row", m.len()),
                )
            })?;
            let to_world = Mat3::from_cols_array(&rows).transpose();
            let orthonormal = (to_world.transpose() * to_world).abs_diff_eq(Mat3::IDENTITY, 1e-3)
                && (to_world.determinant() - 1.0).abs() < 1e-3;
            if !orthonormal {
                return Err(invalid(
                    ".to_world",
                    "not a rotation (its rows must be orthonormal, its determinant 1)".into(),
                ));
            }
            to_world
        }
        (None, None) => Mat3::IDENTITY,
        (Some(r), None) => {
            let axis = r.axis.value();
            let Some(axis) = axis.try_normalize() else {
                return Err(invalid(".rotate.axis", format!("{axis} has no direction")));
            };
            Mat3::from_axis_angle(axis, r.angle.0.to_radians())
        }
    };
    EnvironmentLight::new(map, scale, rotation)
        .map(Light::Environment)
        .ok_or_else(|| invalid("", "not a valid environment light".into()))
}
