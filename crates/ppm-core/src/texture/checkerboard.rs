//! Mitsuba 3's `checkerboard`: two colours in alternating squares of half a uv period.

use super::UvTransform;
use glam::{Vec2, Vec3};

/// `color0` where the fractional parts of the transformed u and v are both at most 1/2 or
/// both above, `color1` elsewhere (Mitsuba 3's `checkerboard`: 2 x 2 squares per unit of
/// transformed uv, `color0` in the square at the origin). Defaults there: 0.4 and 0.2.
#[derive(Clone, Debug, PartialEq)]
pub struct Checkerboard {
    pub color0: Vec3,
    pub color1: Vec3,
    pub transform: UvTransform,
}

impl Checkerboard {
    /// The colour at surface coordinates `uv`.
    #[inline]
    pub fn eval(&self, uv: Vec2) -> Vec3 {
        let uv = self.transform.apply(uv);
        let upper_u = uv.x - uv.x.floor() > 0.5;
        let upper_v = uv.y - uv.y.floor() > 0.5;
        if upper_u == upper_v {
            self.color0
        } else {
            self.color1
        }
    }

    /// Half of each colour: over a period the two cover equal areas.
    pub fn mean(&self) -> Vec3 {
        0.5 * (self.color0 + self.color1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn squares_alternate_with_color0_at_the_origin() {
        let c = Checkerboard {
            color0: Vec3::splat(0.4),
            color1: Vec3::splat(0.2),
            transform: UvTransform::IDENTITY,
        };
        let at = |u: f32, v: f32| c.eval(Vec2::new(u, v)).x;
        assert_eq!(at(0.25, 0.25), 0.4);
        assert_eq!(at(0.75, 0.25), 0.2);
        assert_eq!(at(0.25, 0.75), 0.2);
        assert_eq!(at(0.75, 0.75), 0.4);
        // Periodic, also for negative coordinates.
        assert_eq!(at(-0.75, 0.25), 0.4);
        assert_eq!(at(-0.25, 0.25), 0.2);
        assert_eq!(at(3.25, -1.75), 0.4);
        assert_eq!(at(3.25, -1.25), 0.2);
        // 1/2 belongs to the lower half.
        assert_eq!(at(0.5, 0.1), 0.4);
        // A scale of 4 makes squares of 1/8.
        let scaled = Checkerboard {
            transform: UvTransform::scale_offset(Vec2::splat(4.0), Vec2::ZERO),
            ..c.clone()
        };
        assert_eq!(scaled.eval(Vec2::new(0.1, 0.01)).x, 0.4);
        assert_eq!(scaled.eval(Vec2::new(0.2, 0.01)).x, 0.2);
        assert!((c.mean().x - 0.3).abs() < 1e-7);
    }
}
