//! An object's `transform:` in scene format v1: a list of steps, each applied after the ones
//! before it (the running matrix M becomes `step * M`, as Mitsuba's `<transform>`), built with
//! the Mitsuba importer's operations ([`crate::mitsuba::transform`]).

use crate::error::LoadError;
use crate::mitsuba::transform;
use crate::values::{Finite, Num, Point};
use glam::{DMat4, DVec3};
use serde::Deserialize;
use std::path::Path;

/// One step: exactly one of its fields.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransformStep {
    pub translate: Option<Point>,
    pub rotate: Option<RotateDesc>,
    pub scale: Option<ScaleDesc>,
    /// 16 numbers, row by row.
    pub matrix: Option<Vec<Num<Finite>>>,
    pub look_at: Option<LookAtDesc>,
}

/// `rotate: { axis: [x, y, z], angle: degrees }`, counter-clockwise seen from the axis's tip.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotateDesc {
    pub axis: Point,
    pub angle: Num<Finite>,
}

/// `scale: s` (uniform) or `scale: [x, y, z]`.
#[derive(Deserialize)]
#[serde(untagged)]
pub enum ScaleDesc {
    Uniform(Num<Finite>),
    Axes(Point),
}

/// `look_at: { origin, target, up }`: the frame whose +z looks from `origin` at `target`
/// with +y toward `up` (Mitsuba's `<lookat>`), placing an object modelled looking down +z.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LookAtDesc {
    pub origin: Point,
    pub target: Point,
    pub up: Point,
}

/// The matrix of `steps` (of the object at `field`), or an error naming the step's field.
pub fn object_matrix(
    steps: &[TransformStep],
    field: &str,
    path: &Path,
) -> Result<DMat4, LoadError> {
    let mut m = DMat4::IDENTITY;
    for (i, s) in steps.iter().enumerate() {
        let at = format!("{field}.transform[{i}]");
        let invalid = |name: &str, why: &str| LoadError::invalid(path, format!("{at}{name}"), why);
        let given = [
            s.translate.is_some(),
            s.rotate.is_some(),
            s.scale.is_some(),
            s.matrix.is_some(),
            s.look_at.is_some(),
        ];
        if given.iter().filter(|&&g| g).count() != 1 {
            return Err(invalid(
                "",
                "give exactly one of translate, rotate, scale, matrix, look_at",
            ));
        }
        let step = if let Some(t) = &s.translate {
            transform::translate(t.0)
        } else if let Some(r) = &s.rotate {
            transform::rotate(r.axis.0, r.angle.0 as f64)
                .ok_or_else(|| invalid(".rotate.axis", "the axis is zero"))?
        } else if let Some(scale) = &s.scale {
            let v = match scale {
                ScaleDesc::Uniform(s) => DVec3::splat(s.0 as f64),
                ScaleDesc::Axes(v) => v.0,
            };
            if v.x * v.y * v.z == 0.0 {
                return Err(invalid(".scale", "a zero scale flattens the object"));
            }
            transform::scale(v)
        } else if let Some(values) = &s.matrix {
            let values: Vec<f64> = values.iter().map(|v| v.0 as f64).collect();
            if values.len() != 16 {
                return Err(invalid(
                    ".matrix",
                    &format!("{} numbers; a matrix is 16, row by row", values.len()),
                ));
            }
            let m = transform::matrix(&values).expect("16 values");
            if m.row(3) != glam::DVec4::W {
                return Err(invalid(
                    ".matrix",
                    "the last row must be [0, 0, 0, 1] (an affine transform)",
                ));
            }
            m
        } else if let Some(l) = &s.look_at {
            transform::look_at(l.origin.0, l.target.0, l.up.0).ok_or_else(|| {
                invalid(
                    ".look_at",
                    "origin equals target, or up is parallel to the view",
                )
            })?
        } else {
            unreachable!("one step is given")
        };
        m = step * m;
    }
    Ok(m)
}
