//! Analytic spheres.

use glam::{DVec3, Vec3};
use std::f32::consts::PI;

/// A sphere. Its geometric normal points outward, or inward when `inward` is set (a closed
/// room seen from inside, such as the furnace test).
#[derive(Clone, Copy, Debug)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
    pub material: u32,
    pub inward: bool,
}

impl Sphere {
    /// An outward-facing sphere; a negative `radius` gives the inward-facing sphere of radius
    /// `|radius|`.
    pub fn new(center: Vec3, radius: f32, material: u32) -> Self {
        Sphere {
            center,
            radius: radius.abs(),
            material,
            inward: radius < 0.0,
        }
    }

    /// The same sphere with its normal pointing inward.
    pub fn inward(mut self) -> Self {
        self.inward = true;
        self
    }

    /// Surface area.
    pub fn area(&self) -> f32 {
        4.0 * PI * self.radius * self.radius
    }

    /// Smallest t in (0, t_max) where the ray meets the sphere.
    #[inline]
    pub fn intersect(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<f32> {
        intersect_sphere(self.center, self.radius.abs(), origin, dir, t_max).filter(|&t| t < t_max)
    }

    /// The surface point nearest to `p` (a hit point computed as o + t d, reprojected so that
    /// it lies on the sphere to float precision) and its geometric normal.
    ///
    /// No (u, v) parameters: nothing in the renderer textures a sphere, so their atan2 and
    /// acos would be wasted on every hit.
    #[inline]
    pub fn surface(&self, p: Vec3) -> (Vec3, Vec3) {
        // In double precision and rounded once, so the point is within half an ulp per
        // coordinate of the sphere even when center and radius nearly cancel.
        let c = DVec3::from(self.center);
        let mut n = (DVec3::from(p) - c).normalize_or_zero();
        if n == DVec3::ZERO {
            n = DVec3::Z;
        }
        let p = (c + self.radius.abs() as f64 * n).as_vec3();
        let n = n.as_vec3();
        let ng = if self.inward { -n } else { n };
        (p, ng)
    }
}

/// Ray-sphere intersection returning the smallest root in (0, t_max] ("Precision Improvements
/// for Ray/Sphere Intersection", Haines et al., Ray Tracing Gems ch. 7).
///
/// With f = o - c, the roots of a t^2 + 2 b t + c = 0 (a = d.d, b = f.d, c = f.f - r^2) are
/// found from the discriminant in the form b^2 - a c = a (r^2 - |f - (b/a) d|^2), which does not
/// cancel catastrophically for a small sphere far away, and from q = -(b + sign(b) sqrt(a disc)):
/// t0 = c / q, t1 = q / a, which avoids the cancellation in -b + sqrt(..) of the textbook form.
#[inline(always)]
pub(crate) fn intersect_sphere(
    center: Vec3,
    r: f32,
    origin: Vec3,
    dir: Vec3,
    t_max: f32,
) -> Option<f32> {
    let f = origin - center;
    let a = dir.length_squared();
    let b = f.dot(dir);
    let l = f - (b / a) * dir;
    let r2 = r * r;
    let disc = r2 - l.length_squared();
    // Also rejects NaN (a zero direction, a NaN radius) and non-positive radii.
    if disc.is_nan() || disc < 0.0 || r <= 0.0 {
        return None;
    }
    let ff = f.length_squared();
    let c = ff - r2;
    let q = -(b + (a * disc).sqrt().copysign(b));
    // |c| is only known to about a few ulps of |f|^2 + r^2: when it is that close to 0 the ray
    // starts on the surface (it was spawned there) and the root c / q ~ 0 is that surface
    // point itself, not a new hit.
    let c_err = 8.0 * f32::EPSILON * (ff + r2);
    let (t0, t1) = if c.abs() <= c_err {
        (-1.0, q / a)
    } else {
        (c / q, q / a)
    };
    let (near, far) = if t0 < t1 { (t0, t1) } else { (t1, t0) };
    if near > 0.0 && near <= t_max {
        Some(near)
    } else if far > 0.0 && far <= t_max {
        Some(far)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_near_side_from_outside_and_far_side_from_inside() {
        let s = Sphere::new(Vec3::new(0.0, 0.0, -5.0), 1.0, 0);
        let t = s.intersect(Vec3::ZERO, -Vec3::Z, f32::INFINITY).unwrap();
        assert!((t - 4.0).abs() < 1e-5);
        let t = s
            .intersect(Vec3::new(0.0, 0.0, -5.0), Vec3::X, f32::INFINITY)
            .unwrap();
        assert!((t - 1.0).abs() < 1e-6);
        assert!(s.intersect(Vec3::ZERO, Vec3::Z, f32::INFINITY).is_none());
        assert!(s.intersect(Vec3::ZERO, -Vec3::Z, 3.9).is_none());
    }

    #[test]
    fn tiny_sphere_far_away_is_hit_accurately() {
        // The textbook discriminant b^2 - c loses every digit here.
        let s = Sphere::new(Vec3::new(0.0, 0.0, -1.0e4), 1.0e-2, 0);
        let t = s.intersect(Vec3::ZERO, -Vec3::Z, f32::INFINITY).unwrap();
        assert!((t - (1.0e4 - 1.0e-2)).abs() < 2e-3, "{t}");
        let d = Vec3::new(0.9e-6, 0.0, -1.0).normalize();
        assert!(s.intersect(Vec3::ZERO, d, f32::INFINITY).is_some());
    }

    #[test]
    fn negative_radius_means_inward() {
        let s = Sphere::new(Vec3::ZERO, -2.0, 0);
        assert!(s.inward && s.radius == 2.0);
        let (_, ng) = s.surface(Vec3::new(0.0, 2.0, 0.0));
        assert!((ng - Vec3::NEG_Y).length() < 1e-6);
    }
}
