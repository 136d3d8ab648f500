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
    /// No (u, v) parameters: only a textured material needs them, and it asks for them
    /// after the hit (`Geometry::texture_uv`), so their atan2 and acos are not paid on
    /// every hit.
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
///
/// In double precision: c = |f|^2 - r^2 is the difference of two numbers of the size of r^2,
/// so in single precision its error, about r^2 / 2^21, is the error of a hit near a large
/// sphere's surface (a sphere of radius 1e6 as a ground plane: whole scene units). The inputs
/// are exact in f64 and f = o - c is computed exactly, so only the last rounding to f32 is left.
#[inline(always)]
pub(crate) fn intersect_sphere(
    center: Vec3,
    r: f32,
    origin: Vec3,
    dir: Vec3,
    t_max: f32,
) -> Option<f32> {
    let f = DVec3::from(origin) - DVec3::from(center);
    let dir = DVec3::from(dir);
    let r = r as f64;
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
    let c_err = 8.0 * f64::EPSILON * (ff + r2);
    let (t0, t1) = if c.abs() <= c_err {
        (-1.0, q / a)
    } else {
        (c / q, q / a)
    };
    let (near, far) = if t0 < t1 { (t0, t1) } else { (t1, t0) };
    // Rounded to f32 before the comparisons, so the caller's `t < t_max` sees the same value.
    let (near, far) = (near as f32, far as f32);
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

    /// A sphere of radius 1e6 used as a ground plane is hit where its surface is, within the
    /// scene's own precision: from heights of 1 down to 0.001 (in single precision the near
    /// root was lost below a height of about 1 and the ray went through the ground).
    #[test]
    fn a_huge_sphere_is_hit_where_its_surface_is() {
        let ground = Sphere::new(Vec3::new(0.0, -1e6, 0.0), 1e6, 0);
        for h in [1.0f32, 0.3, 0.01, 0.001] {
            for (sin, cos) in [(0.0f32, 1.0f32), (0.8, 0.6)] {
                let origin = Vec3::new(0.25, h, -0.5);
                let dir = Vec3::new(sin, -cos, 0.0);
                let t = ground.intersect(origin, dir, f32::INFINITY).unwrap();
                // The plane's distance; the curvature moves it by less than 1e-6 here.
                let expected = h / cos;
                assert!(
                    (t - expected).abs() <= 1e-5 * expected.max(1.0),
                    "height {h}, cos {cos}: t {t}, expected {expected}"
                );
            }
        }
    }

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
