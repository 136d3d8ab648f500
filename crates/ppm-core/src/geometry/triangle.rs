//! The watertight ray-triangle test.

use glam::Vec3;

/// A triangle's vertices.
#[derive(Clone, Copy, Debug)]
pub struct Triangle {
    pub v: [Vec3; 3],
}

/// Watertight ray-triangle intersection (Woop, Benthin and Wald 2013). Returns (t, b1, b2)
/// with t in (0, t_max). TODO(geometry helper).
pub fn intersect_triangle(_tri: &Triangle, _origin: Vec3, _dir: Vec3, _t_max: f32) -> Option<(f32, f32, f32)> {
    todo!()
}
