//! Rays and the offset that keeps a spawned ray from re-hitting the surface it leaves.

use glam::Vec3;

/// A ray `origin + t * dir`, `t` in (0, t_max). `dir` is unit length.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
    pub t_max: f32,
}

/// Relative size of the offset: 4 to 8 ulps of the largest coordinate. A hit point is within
/// half an ulp per coordinate of its surface (triangles and spheres compute it in double
/// precision and round once), and the primitive tests themselves reject hits within their own
/// rounding error of t = 0, so the offset only has to put the origin on the right side of its
/// surface; keeping it small keeps light from leaking through corners.
const OFFSET_SCALE: f32 = 1.0 / (1 << 21) as f32;

/// Moves `p` off its surface along the geometric normal `ng`, to the side `dir` leaves toward.
///
/// The distance scales with the magnitude of `p` (not a fixed epsilon), so a scene far from the
/// origin or a tiny scene is as safe as a unit-sized one.
#[inline]
pub(crate) fn offset_origin(p: Vec3, ng: Vec3, dir: Vec3) -> Vec3 {
    let d = (p.abs().max_element() * OFFSET_SCALE).max(f32::MIN_POSITIVE);
    let offset = if dir.dot(ng) >= 0.0 { ng * d } else { ng * -d };
    let moved = p + offset;
    // Rounding p + offset may have given back up to half an ulp; step one more ulp away.
    let step = |m: f32, o: f32| {
        if o == 0.0 {
            m
        } else {
            next_float(m, o > 0.0)
        }
    };
    Vec3::new(
        step(moved.x, offset.x),
        step(moved.y, offset.y),
        step(moved.z, offset.z),
    )
}

/// The neighbouring float of `x` toward +infinity (`up`) or -infinity (`f32::next_up` and
/// `next_down` need Rust 1.86).
#[inline]
fn next_float(x: f32, up: bool) -> f32 {
    if !x.is_finite() {
        return x;
    }
    if x == 0.0 {
        let tiny = f32::from_bits(1);
        return if up { tiny } else { -tiny };
    }
    // Magnitudes are ordered like their bit patterns; moving away from zero adds one.
    let away_from_zero = (x > 0.0) == up;
    let bits = x.to_bits();
    f32::from_bits(if away_from_zero { bits + 1 } else { bits - 1 })
}

impl Ray {
    /// An unbounded ray.
    #[inline]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Ray {
            origin,
            dir,
            t_max: f32::INFINITY,
        }
    }

    /// A ray leaving the surface point `p` (geometric normal `ng`) in direction `dir`.
    #[inline]
    pub fn spawn(p: Vec3, ng: Vec3, dir: Vec3) -> Self {
        Ray::new(offset_origin(p, ng, dir), dir)
    }

    /// A shadow ray from surface point `p` (normal `ng`) to `target`; both ends are kept off
    /// their surfaces (`target_ng` is the normal at the target, zero for a point light).
    #[inline]
    pub fn spawn_to(p: Vec3, ng: Vec3, target: Vec3, target_ng: Vec3) -> Self {
        let d = target - p;
        let origin = offset_origin(p, ng, d);
        let end = if target_ng == Vec3::ZERO {
            target
        } else {
            offset_origin(target, target_ng, -d)
        };
        let v = end - origin;
        let len = v.length();
        Ray {
            origin,
            dir: v / len,
            t_max: len * (1.0 - 1e-6),
        }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn next_float_steps_one_ulp_either_way() {
        for x in [1.0f32, -1.0, 3.5e-3, -7.0e5, f32::MIN_POSITIVE, 0.0, -0.0] {
            let (up, down) = (next_float(x, true), next_float(x, false));
            assert!(up > x && down < x, "{x}: {down} {up}");
            assert_eq!(next_float(up, false), if x == 0.0 { 0.0 } else { x });
        }
        assert_eq!(next_float(1.0, true), 1.0 + f32::EPSILON);
        assert_eq!(next_float(f32::MAX, true), f32::INFINITY);
    }

    #[test]
    fn offset_moves_to_the_side_of_dir() {
        let p = Vec3::new(1.0e5, -3.0, 0.25);
        let n = Vec3::new(0.0, 0.6, 0.8);
        for (dir, side) in [(n, 1.0), (-n, -1.0), (Vec3::X, 1.0)] {
            let o = offset_origin(p, n, dir);
            assert!(
                (o - p).dot(n) * side > 0.0 && (o - p).length() < 1e5 * 1e-5,
                "{o}"
            );
        }
        // At the origin the offset is the smallest step, but still one.
        assert!(offset_origin(Vec3::ZERO, Vec3::Z, Vec3::Z).z > 0.0);
    }
}
