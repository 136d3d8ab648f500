//! Rays and the offset that keeps a spawned ray from re-hitting the surface it leaves.

use glam::Vec3;

/// A ray `origin + t * dir`, `t` in (0, t_max). `dir` is unit length.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
    pub t_max: f32,
}

/// Relative size of the offset: a few hundred ulps of the largest coordinate, well above the
/// rounding error of a hit point computed from barycentrics (about gamma(7) |p|) and far below
/// any feature of a scene at any scale.
const OFFSET_SCALE: f32 = 1.0 / (1 << 18) as f32;

/// Moves `p` off its surface along the geometric normal `ng`, to the side `dir` leaves toward.
///
/// The distance scales with the magnitude of `p` (not a fixed epsilon), so a scene far from the
/// origin or a tiny scene is as safe as a unit-sized one.
#[inline]
pub fn offset_origin(p: Vec3, ng: Vec3, dir: Vec3) -> Vec3 {
    let d = (p.abs().max_element() * OFFSET_SCALE).max(f32::MIN_POSITIVE);
    let offset = ng * d;
    let moved = if dir.dot(ng) >= 0.0 {
        p + offset
    } else {
        p - offset
    };
    // Round each coordinate away from p once more so the offset survives the addition.
    let step = |m: f32, o: f32| {
        if o > 0.0 {
            m.next_up()
        } else if o < 0.0 {
            m.next_down()
        } else {
            m
        }
    };
    let sign = if dir.dot(ng) >= 0.0 { 1.0 } else { -1.0 };
    Vec3::new(
        step(moved.x, sign * offset.x),
        step(moved.y, sign * offset.y),
        step(moved.z, sign * offset.z),
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
