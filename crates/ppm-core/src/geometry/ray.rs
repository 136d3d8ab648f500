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
pub fn offset_origin(p: Vec3, ng: Vec3, dir: Vec3) -> Vec3 {
    let d = (p.abs().max_element() * OFFSET_SCALE).max(f32::MIN_POSITIVE);
    let offset = if dir.dot(ng) >= 0.0 { ng * d } else { ng * -d };
    let moved = p + offset;
    // Rounding p + offset may have given back up to half an ulp; step one more ulp away.
    let step = |m: f32, o: f32| {
        if o > 0.0 {
            m.next_up()
        } else if o < 0.0 {
            m.next_down()
        } else {
            m
        }
    };
    Vec3::new(
        step(moved.x, offset.x),
        step(moved.y, offset.y),
        step(moved.z, offset.z),
    )
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
