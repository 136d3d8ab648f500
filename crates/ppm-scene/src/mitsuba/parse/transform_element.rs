//! The `<transform>` element and the `x`/`y`/`z` (or `value`) attributes of its operations:
//! `translate`, `scale`, `rotate`, `lookat` and `matrix`, composed in order (`transform.rs`
//! makes each matrix).

use super::super::transform;
use super::super::values::{parse_number, parse_numbers, parse_triple};
use super::{tag, File, Parser};
use crate::LoadError;
use glam::{DMat4, DVec3};
use roxmltree::Node;

impl Parser {
    /// `x`, `y`, `z` attributes (missing ones `default`) or `value="x, y, z"` (or one value
    /// for all three).
    pub(super) fn parse_xyz(
        &self,
        file: &File,
        node: Node,
        default: f64,
    ) -> Result<DVec3, LoadError> {
        let location = file.location(node);
        if let Some(v) = self.attr(file, node, "value")? {
            return parse_triple(&v).ok_or_else(|| {
                location.error(format!(
                    "<{}>: expected 1 or 3 numbers, got `{v}`",
                    tag(node)
                ))
            });
        }
        let mut out = DVec3::splat(default);
        for (i, axis) in ["x", "y", "z"].into_iter().enumerate() {
            if let Some(v) = self.attr(file, node, axis)? {
                out[i] = parse_number(&v).ok_or_else(|| {
                    location.error(format!(
                        "<{}>: `{axis}` is not a finite number: `{v}`",
                        tag(node)
                    ))
                })?;
            }
        }
        Ok(out)
    }

    /// A `<transform>`: its operations composed in order (`transform.rs`).
    pub(super) fn parse_transform(&self, file: &File, node: Node) -> Result<DMat4, LoadError> {
        let mut m = DMat4::IDENTITY;
        for op in node.children().filter(|n| n.is_element()) {
            let location = file.location(op);
            let vector = |name: &str| -> Result<DVec3, LoadError> {
                let v = self.need(file, op, name)?;
                parse_triple(&v).ok_or_else(|| {
                    location.error(format!(
                        "<{}>: `{name}` needs 3 numbers, got `{v}`",
                        tag(op)
                    ))
                })
            };
            let step = match tag(op) {
                "translate" => transform::translate(self.parse_xyz(file, op, 0.0)?),
                "scale" => transform::scale(self.parse_xyz(file, op, 1.0)?),
                "rotate" => {
                    let axis = self.parse_xyz(file, op, 0.0)?;
                    let a = self.need(file, op, "angle")?;
                    let angle = parse_number(&a).ok_or_else(|| {
                        location.error(format!("<rotate>: angle `{a}` is not a finite number"))
                    })?;
                    transform::rotate(axis, angle)
                        .ok_or_else(|| location.error("<rotate>: the axis is zero"))?
                }
                "lookat" | "lookAt" => {
                    let up = match self.attr(file, op, "up")? {
                        Some(_) => vector("up")?,
                        None => DVec3::ZERO,
                    };
                    transform::look_at(vector("origin")?, vector("target")?, up).ok_or_else(
                        || {
                            location.error(
                                "<lookat>: origin equals target, or up is parallel to the view",
                            )
                        },
                    )?
                }
                "matrix" => {
                    let v = self.need(file, op, "value")?;
                    let numbers = parse_numbers(&v)
                        .ok_or_else(|| location.error(format!("<matrix>: not numbers: `{v}`")))?;
                    transform::matrix(&numbers).ok_or_else(|| {
                        location.error(format!(
                            "<matrix> needs 16 or 9 values, got {}",
                            numbers.len()
                        ))
                    })?
                }
                other => {
                    return Err(location.error(format!("unexpected <{other}> inside <transform>")))
                }
            };
            m = step * m;
        }
        Ok(m)
    }
}
