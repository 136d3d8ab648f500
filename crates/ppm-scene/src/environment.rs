//! `{ type: environment }` lights of scene format v1: a constant `color` or a radiance map
//! `file` (radiance in W/(m^2 sr)), times `scale`, turned by `rotate` (or the matrix
//! `to_world`). A map is lat-long by default, in Mitsuba 3's frame (`envmap.rs` in ppm-core:
//! its top row is +y, its left edge looks along -z and a quarter of the way across along +x);
//! `mapping: equal_area` reads it as pbrt-v4's equal-area octahedral square (`equal_area.rs`:
//! its centre is +z).

use crate::error::LoadError;
use crate::yaml::{LightDesc, MapMapping};
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
    if l.mapping.is_some() && l.file.is_none() {
        return Err(invalid(
            ".mapping",
            "`mapping` says how an image `file` covers the sphere; this light has no file".into(),
        ));
    }
    let map = match (&l.color, &l.file) {
        (Some(c), None) => EnvironmentMap::Constant(c.value()),
        (None, Some(file)) => {
            let file_path = path.parent().unwrap_or(Path::new("")).join(file);
            let why = |e: String| invalid(".file", format!("{}: {e}", file_path.display()));
            match l.mapping.unwrap_or(MapMapping::Latlong) {
                MapMapping::Latlong => EnvironmentMap::Image(Arc::new(
                    crate::radiance_map::read_map(&file_path).map_err(why)?,
                )),
                MapMapping::EqualArea => EnvironmentMap::EqualArea(Arc::new(
                    crate::radiance_map::read_equal_area_map(&file_path).map_err(why)?,
                )),
            }
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
                && (to_world.determinant().abs() - 1.0).abs() < 1e-3;
            if !orthonormal {
                return Err(invalid(
                    ".to_world",
                    "not a rotation or a mirror (its rows must be orthonormal)".into(),
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
