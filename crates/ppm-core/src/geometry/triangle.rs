//! The watertight ray-triangle test of Woop, Benthin and Wald (2013), "Watertight Ray/Triangle
//! Intersection", JCGT 2(1).
//!
//! The ray is turned into a coordinate frame in which it runs along +z from the origin: the axes
//! are permuted so z is the direction's largest component, then x and y are sheared. Each
//! triangle then only needs 2D edge functions at the origin. The same vertex is transformed
//! identically for every triangle that shares it, and an edge function that rounds to exactly
//! zero is recomputed in double precision (where the products of floats are exact), so a ray
//! through a shared edge or vertex is never lost between two triangles.
//!
//! Hits nearer than the conservative error bound on t of pbrt-v4 (sec. 6.8.4), where single
//! precision cannot tell t from 0, get their t recomputed in double precision: the surface a
//! ray was spawned from is never reported again, and a wall a corner ray meets after 1e-5 of the
//! scene's size is not lost either (pbrt-v4 rejects every hit below the bound).

use glam::Vec3;

/// A triangle's vertices.
#[derive(Clone, Copy, Debug)]
pub struct Triangle {
    pub v: [Vec3; 3],
}

impl Triangle {
    /// Unnormalised geometric normal `cross(v1 - v0, v2 - v0)` (its length is twice the area).
    #[inline]
    pub fn cross(&self) -> Vec3 {
        (self.v[1] - self.v[0]).cross(self.v[2] - self.v[0])
    }

    /// Surface area.
    #[inline]
    pub fn area(&self) -> f32 {
        0.5 * self.cross().length()
    }
}

/// gamma(n) = n u / (1 - n u), u = 2^-24: the bound on the relative error of n roundings
/// (Higham; pbrt-v4 eq. 6.30).
#[inline(always)]
pub(crate) const fn gamma(n: i32) -> f32 {
    let u = f32::EPSILON * 0.5;
    n as f32 * u / (1.0 - n as f32 * u)
}

/// Per-ray constants of the watertight test: the axis permutation and the shear.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShearedRay {
    pub(super) origin: Vec3,
    dir: Vec3,
    /// Permutation: `kz` is the axis of the largest |dir| component.
    pub(super) kx: usize,
    pub(super) ky: usize,
    pub(super) kz: usize,
    /// Shear: x' = x - sx z, y' = y - sy z, z' = sz z (after permutation).
    pub(super) sx: f32,
    pub(super) sy: f32,
    pub(super) sz: f32,
}

impl ShearedRay {
    #[inline(always)]
    pub(crate) fn new(origin: Vec3, dir: Vec3) -> Self {
        let a = dir.abs();
        let kz = if a.x > a.y {
            if a.x > a.z {
                0
            } else {
                2
            }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let mut kx = if kz == 2 { 0 } else { kz + 1 };
        let mut ky = if kx == 2 { 0 } else { kx + 1 };
        let d = dir.to_array();
        // Swapping x and y keeps the winding (and so the sign of the determinant) intact.
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        ShearedRay {
            origin,
            dir,
            kx,
            ky,
            kz,
            sx: d[kx] / d[kz],
            sy: d[ky] / d[kz],
            sz: 1.0 / d[kz],
        }
    }

    /// A vertex relative to the origin, permuted and sheared in x and y (z is still unsheared).
    #[inline(always)]
    fn transform(&self, v: Vec3) -> (f32, f32, f32) {
        let p = (v - self.origin).to_array();
        let z = p[self.kz];
        (p[self.kx] - self.sx * z, p[self.ky] - self.sy * z, z)
    }

    /// The watertight test against a triangle. Returns (t, b1, b2) with t in (0, t_max]:
    /// callers that need a strict bound compare the returned t themselves, so that exactly
    /// equal distances are resolved the same way everywhere.
    #[inline(always)]
    pub(crate) fn intersect(
        &self,
        v0: Vec3,
        v1: Vec3,
        v2: Vec3,
        t_max: f32,
    ) -> Option<(f32, f32, f32)> {
        let (x0, y0, z0) = self.transform(v0);
        let (x1, y1, z1) = self.transform(v1);
        let (x2, y2, z2) = self.transform(v2);

        // Edge functions; e0 is opposite v0, so e_i / det is the barycentric of v_i.
        let mut e0 = x1 * y2 - y1 * x2;
        let mut e1 = x2 * y0 - y2 * x0;
        let mut e2 = x0 * y1 - y0 * x1;
        if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
            // The ray passes (in float) through an edge or vertex: decide exactly. Products of
            // two floats are exact in double, so the sign of each difference is exact.
            let f =
                |a: f32, b: f32, c: f32, d: f32| (a as f64 * b as f64 - c as f64 * d as f64) as f32;
            e0 = f(x1, y2, y1, x2);
            e1 = f(x2, y0, y2, x0);
            e2 = f(x0, y1, y0, x1);
        }
        if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
            return None;
        }
        let det = e0 + e1 + e2;
        if det == 0.0 {
            return None;
        }

        // Scaled distance: t = (e0 z0 + e1 z1 + e2 z2) sz / det; beyond t_max is rejected
        // without the division.
        let (z0, z1, z2) = (self.sz * z0, self.sz * z1, self.sz * z2);
        let t_scaled = e0 * z0 + e1 * z1 + e2 * z2;
        if (det < 0.0 && t_scaled < t_max * det) || (det > 0.0 && t_scaled > t_max * det) {
            return None;
        }
        let inv_det = 1.0 / det;
        let t = t_scaled * inv_det;

        // Conservative bound on the rounding error of t (pbrt-v4 sec. 6.8.4). Within it the
        // sign of t is not known in single precision: a ray leaving this very triangle, or a
        // wall met right next to a corner. Those are decided in double precision.
        let max_z = z0.abs().max(z1.abs()).max(z2.abs());
        let max_x = x0.abs().max(x1.abs()).max(x2.abs());
        let max_y = y0.abs().max(y1.abs()).max(y2.abs());
        let max_e = e0.abs().max(e1.abs()).max(e2.abs());
        let delta_t = t_error_bound(max_x, max_y, max_z, max_e, inv_det.abs(), gamma);
        let t = if t > delta_t {
            t
        } else if t >= -delta_t {
            self.near_t(v0, v1, v2)?
        } else {
            return None;
        };
        Some((t, e1 * inv_det, e2 * inv_det))
    }

    /// The distance of a hit too near the origin for the single-precision bound (a ray leaving
    /// this very triangle, or a wall met right next to a corner), decided in double precision:
    /// `None` unless t is certainly positive. Inside/outside stays the single-precision verdict,
    /// which keeps the test watertight; only t is recomputed.
    ///
    /// pbrt-v4 simply rejects such hits, but its bound is about 1e-5 times the size of the
    /// triangle, so rays leaving a point within 1e-5 of a corner would pass through the
    /// adjacent wall. In double precision the translated vertices are exact and the bound is
    /// 2^29 times smaller.
    #[cold]
    #[inline(never)]
    fn near_t(&self, v0: Vec3, v1: Vec3, v2: Vec3) -> Option<f32> {
        let o = self.origin.as_dvec3();
        let d = self.dir.as_dvec3().to_array();
        let (sx, sy, sz) = (
            d[self.kx] / d[self.kz],
            d[self.ky] / d[self.kz],
            1.0 / d[self.kz],
        );
        let transform = |v: Vec3| {
            let p = (v.as_dvec3() - o).to_array();
            let z = p[self.kz];
            (p[self.kx] - sx * z, p[self.ky] - sy * z, sz * z)
        };
        let (x0, y0, z0) = transform(v0);
        let (x1, y1, z1) = transform(v1);
        let (x2, y2, z2) = transform(v2);
        let e0 = x1 * y2 - y1 * x2;
        let e1 = x2 * y0 - y2 * x0;
        let e2 = x0 * y1 - y0 * x1;
        let det = e0 + e1 + e2;
        if det == 0.0 {
            return None;
        }
        let inv_det = 1.0 / det;
        let t = (e0 * z0 + e1 * z1 + e2 * z2) * inv_det;
        let max_z = z0.abs().max(z1.abs()).max(z2.abs());
        let max_x = x0.abs().max(x1.abs()).max(x2.abs());
        let max_y = y0.abs().max(y1.abs()).max(y2.abs());
        let max_e = e0.abs().max(e1.abs()).max(e2.abs());
        let delta_t = t_error_bound(max_x, max_y, max_z, max_e, inv_det.abs(), gamma64);
        let t32 = t as f32;
        (t > delta_t && t32 > 0.0).then_some(t32)
    }
}

/// gamma(n) for double precision, u = 2^-53.
#[inline(always)]
fn gamma64(n: i32) -> f64 {
    let u = f64::EPSILON * 0.5;
    n as f64 * u / (1.0 - n as f64 * u)
}

/// Scalars the error bound is evaluated in: f32, f64 and four f32 lanes (the packet test).
pub(super) trait Real:
    Copy + std::ops::Add<Output = Self> + std::ops::Mul<Output = Self>
{
    fn constant(x: f32) -> Self;
}

impl Real for f32 {
    #[inline(always)]
    fn constant(x: f32) -> Self {
        x
    }
}

impl Real for f64 {
    #[inline(always)]
    fn constant(x: f32) -> Self {
        x as f64
    }
}

impl Real for glam::Vec4 {
    #[inline(always)]
    fn constant(x: f32) -> Self {
        glam::Vec4::splat(x)
    }
}

/// pbrt-v4's bound on the error of t = (e0 z0 + e1 z1 + e2 z2) / det, from the largest
/// magnitudes of the transformed coordinates, the edge functions and 1 / |det|. The same
/// expression (and so the same roundings) for every `Real`.
#[inline(always)]
pub(super) fn t_error_bound<F: Real>(
    max_x: F,
    max_y: F,
    max_z: F,
    max_e: F,
    inv_det: F,
    gamma: impl Fn(i32) -> F,
) -> F {
    let delta_z = gamma(3) * max_z;
    let delta_x = gamma(5) * (max_x + max_z);
    let delta_y = gamma(5) * (max_y + max_z);
    let delta_e = F::constant(2.0) * (gamma(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    F::constant(3.0) * (gamma(3) * max_e * max_z + delta_e * max_z + delta_z * max_e) * inv_det
}

/// Watertight ray-triangle intersection (Woop, Benthin and Wald 2013). Returns (t, b1, b2)
/// with t in (0, t_max); the hit point is `(1 - b1 - b2) v0 + b1 v1 + b2 v2`. Hits closer than
/// the rounding error of t (a ray leaving the triangle itself) are not reported.
#[inline]
pub fn intersect_triangle(
    tri: &Triangle,
    origin: Vec3,
    dir: Vec3,
    t_max: f32,
) -> Option<(f32, f32, f32)> {
    ShearedRay::new(origin, dir)
        .intersect(tri.v[0], tri.v[1], tri.v[2], t_max)
        .filter(|&(t, _, _)| t < t_max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_the_inside_and_reports_barycentrics() {
        let tri = Triangle {
            v: [Vec3::ZERO, Vec3::X, Vec3::Y],
        };
        let (t, b1, b2) =
            intersect_triangle(&tri, Vec3::new(0.25, 0.5, 2.0), -Vec3::Z, 10.0).unwrap();
        assert!((t - 2.0).abs() < 1e-6);
        assert!((b1 - 0.25).abs() < 1e-6 && (b2 - 0.5).abs() < 1e-6);
        // From behind, too (no back-face culling), and not beyond t_max or behind the origin.
        assert!(intersect_triangle(&tri, Vec3::new(0.25, 0.25, -1.0), Vec3::Z, 10.0).is_some());
        assert!(intersect_triangle(&tri, Vec3::new(0.25, 0.5, 2.0), -Vec3::Z, 2.0).is_none());
        assert!(intersect_triangle(&tri, Vec3::new(0.25, 0.5, 2.0), Vec3::Z, 10.0).is_none());
        assert!(intersect_triangle(&tri, Vec3::new(0.75, 0.5, 2.0), -Vec3::Z, 10.0).is_none());
    }

    #[test]
    fn parallel_ray_misses() {
        let tri = Triangle {
            v: [Vec3::ZERO, Vec3::X, Vec3::Y],
        };
        assert!(intersect_triangle(&tri, Vec3::new(-1.0, 0.1, 0.0), Vec3::X, 10.0).is_none());
    }
}
