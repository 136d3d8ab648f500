//! An equal-area octahedral radiance map, pbrt-v4's format for `ImageInfiniteLight` (Pharr et
//! al. 2023, sec. 3.8.3 and 12.5.2), and its sampling distribution.
//!
//! # Parameterisation
//! Clarberg's equal-area mapping (Clarberg 2008, "Fast equal-area mapping of the
//! (hemi)sphere using SIMD", eqs. 5-8) takes the square (u, v) in [-1, 1]^2 to the unit
//! sphere. With r the distance from the square's centre in the L1 norm folded at the
//! diamond |u| + |v| = 1,
//!
//! r = 1 - |1 - |u| - |v||,  z = sign(1 - |u| - |v|) (1 - r^2),
//! phi = pi/4 ((|v| - |u|) / r + 1) (in the quadrant of (u, v)),
//! (x, y) = r sqrt(2 - r^2) (sign(u) cos phi, sign(v) sin phi).
//!
//! The diamond's inside is the hemisphere z > 0, the four corners' triangles fold onto
//! z < 0. The L1 disk of radius r covers 2 r^2 of the square's area 4, and the cap z > 1 - r^2
//! covers 2 pi r^2 of the sphere's 4 pi: the same fraction, and phi is linear along each
//! diamond, so the map preserves area: every texel of an N x N image subtends 4 pi / N^2.
//!
//! Texel (i, j) (row i from the top, column j from the left) covers s in [j/N, (j+1)/N],
//! t in [i/N, (i+1)/N], with (u, v) = (2 s - 1, 2 t - 1): pbrt-v4's image coordinates, where
//! the local direction is the light-space direction toward the light (+z up). The radiance
//! is constant over a texel (pbrt-v4's `ImageLe` looks up the nearest texel).
//!
//! # Sampling
//! A texel with probability P_ij proportional to its luminance (all texels subtend the same
//! solid angle), then a point uniform in it. The map's Jacobian is the constant 4 pi (over
//! s, t in [0, 1]^2), so the solid-angle density is p(w) = P_ij N^2 / (4 pi).

use crate::bsdf::luminance;
use crate::light::envmap::{check_texels, MapError};
use crate::sampling::Distribution1D;
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// The unit direction of the point (s, t) of the unit square (see the module documentation).
#[inline]
pub fn square_to_sphere(st: Vec2) -> Vec3 {
    let (u, v) = (2.0 * st.x - 1.0, 2.0 * st.y - 1.0);
    let (au, av) = (u.abs(), v.abs());
    let signed = 1.0 - (au + av);
    let r = 1.0 - signed.abs();
    let phi = if r == 0.0 {
        FRAC_PI_4
    } else {
        ((av - au) / r + 1.0) * FRAC_PI_4
    };
    let z = (1.0 - r * r).copysign(signed);
    let sin_theta = r * (2.0 - r * r).max(0.0).sqrt();
    let (sin_phi, cos_phi) = phi.sin_cos();
    Vec3::new(
        cos_phi.copysign(u) * sin_theta,
        sin_phi.copysign(v) * sin_theta,
        z,
    )
}

/// The point (s, t) of the unit square of a unit direction: the inverse of
/// [`square_to_sphere`]. r = sqrt(1 - |z|), phi = atan2(|y|, |x|) in [0, pi/2];
/// |v| = r phi / (pi/2), |u| = r - |v| on the upper hemisphere; on the lower one the point is
/// folded across the diamond, (|u|, |v|) -> (1 - |v|, 1 - |u|); then the signs of x and y.
#[inline]
pub fn sphere_to_square(w: Vec3) -> Vec2 {
    let r = (1.0 - w.z.abs()).max(0.0).sqrt();
    let phi = w.y.abs().atan2(w.x.abs());
    let mut av = r * (phi / FRAC_PI_2);
    let mut au = r - av;
    if w.z < 0.0 {
        (au, av) = (1.0 - av, 1.0 - au);
    }
    let u = au.copysign(w.x);
    let v = av.copysign(w.y);
    Vec2::new(
        (0.5 * (u + 1.0)).clamp(0.0, 1.0),
        (0.5 * (v + 1.0)).clamp(0.0, 1.0),
    )
}

/// An equal-area radiance image (W/(m^2 sr) per texel, linear RGB, N x N) with its sampling
/// distribution, built once.
#[derive(Clone, Debug)]
pub struct EqualAreaMap {
    size: usize,
    /// Row-major, row 0 at the top (t = 0).
    texels: Vec<Vec3>,
    /// The choice of a row, proportional to the sum of its texels' luminances.
    rows: Distribution1D,
    /// The choice of a column given the row.
    columns: Vec<Distribution1D>,
    /// Integral of the radiance over the sphere, per channel (W/m^2).
    integral: Vec3,
}

impl EqualAreaMap {
    /// The map of `texels` (row-major, `size` x `size`, row 0 at the top).
    pub fn new(size: usize, texels: Vec<Vec3>) -> Result<Self, MapError> {
        check_texels(size, size, &texels)?;
        let mut columns = Vec::with_capacity(size);
        let mut row_weights = Vec::with_capacity(size);
        let mut weights = vec![0.0f32; size];
        let mut sum = [0.0f64; 3];
        for row in texels.chunks_exact(size) {
            for (w, t) in weights.iter_mut().zip(row) {
                *w = luminance(*t);
            }
            row_weights.push(weights.iter().map(|&w| w as f64).sum::<f64>() as f32);
            columns.push(Distribution1D::new(&weights));
            for t in row {
                for (c, acc) in sum.iter_mut().enumerate() {
                    *acc += t[c] as f64;
                }
            }
        }
        // Every texel subtends 4 pi / N^2.
        let omega = 4.0 * std::f64::consts::PI / (size * size) as f64;
        Ok(EqualAreaMap {
            size,
            texels,
            rows: Distribution1D::new(&row_weights),
            columns,
            integral: Vec3::new(
                (sum[0] * omega) as f32,
                (sum[1] * omega) as f32,
                (sum[2] * omega) as f32,
            ),
        })
    }

    /// The side N in texels.
    pub fn size(&self) -> usize {
        self.size
    }

    /// The texels, row-major from the top row.
    pub fn texels(&self) -> &[Vec3] {
        &self.texels
    }

    /// The integral of the radiance over the sphere: the sum of the texels times 4 pi / N^2.
    pub fn integral(&self) -> Vec3 {
        self.integral
    }

    /// The texel (row, column) a local direction falls in.
    #[inline]
    fn texel_of(&self, w: Vec3) -> (usize, usize) {
        let st = sphere_to_square(w);
        let n = self.size;
        let i = ((st.y * n as f32) as usize).min(n - 1);
        let j = ((st.x * n as f32) as usize).min(n - 1);
        (i, j)
    }

    /// Radiance toward local direction `w` (unit; the direction the light comes from).
    #[inline]
    pub fn eval(&self, w: Vec3) -> Vec3 {
        let (i, j) = self.texel_of(w);
        self.texels[i * self.size + j]
    }

    /// Solid-angle density of sampling local direction `w`: P_ij N^2 / (4 pi); 0 for texels
    /// of zero luminance.
    #[inline]
    pub fn pdf(&self, w: Vec3) -> f32 {
        if self.rows.is_empty() {
            return 0.0;
        }
        let (i, j) = self.texel_of(w);
        let p = self.rows.pmf(i) * self.columns[i].pmf(j);
        p * (self.size * self.size) as f32 / (4.0 * PI)
    }

    /// A local direction by the distribution (row, column given the row, uniform within the
    /// texel) and its solid-angle density; `None` for an all-black map.
    #[inline]
    pub fn sample(&self, u: Vec2) -> Option<(Vec3, f32)> {
        if self.rows.is_empty() {
            return None;
        }
        let (i, p_row, t_in) = self.rows.sample_continuous(u.y);
        let (j, p_col, s_in) = self.columns[i].sample_continuous(u.x);
        let n = self.size as f32;
        let st = Vec2::new((j as f32 + s_in) / n, (i as f32 + t_in) / n);
        let w = square_to_sphere(st).normalize();
        Some((w, p_row * p_col * n * n / (4.0 * PI)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pbrt_frame() {
        // The centre is +z, the corners -z, the middle of the right edge +x, of the bottom
        // edge (t = 1) +y.
        let at = |s: f32, t: f32| square_to_sphere(Vec2::new(s, t));
        assert!(at(0.5, 0.5).abs_diff_eq(Vec3::Z, 1e-6));
        for c in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
            assert!(at(c.0, c.1).abs_diff_eq(Vec3::NEG_Z, 1e-6), "{c:?}");
        }
        assert!(at(1.0, 0.5).abs_diff_eq(Vec3::X, 1e-6));
        assert!(at(0.0, 0.5).abs_diff_eq(Vec3::NEG_X, 1e-6));
        assert!(at(0.5, 1.0).abs_diff_eq(Vec3::Y, 1e-6));
        assert!(at(0.5, 0.0).abs_diff_eq(Vec3::NEG_Y, 1e-6));
    }

    #[test]
    fn the_mapping_round_trips_and_stays_on_the_sphere() {
        let n = 97;
        for a in 0..=n {
            for b in 0..=n {
                let st = Vec2::new(a as f32 / n as f32, b as f32 / n as f32);
                let w = square_to_sphere(st);
                assert!((w.length() - 1.0).abs() < 1e-5, "{st}: {w}");
                let back = sphere_to_square(w);
                // Points on the square's edges fold onto each other (the octahedral seam):
                // compare the directions there.
                assert!(
                    back.abs_diff_eq(st, 2e-5) || square_to_sphere(back).abs_diff_eq(w, 2e-5),
                    "{st} -> {w} -> {back}"
                );
            }
        }
    }

    #[test]
    fn the_mapping_preserves_area() {
        // |dw/ds x dw/dt| = 4 pi everywhere, by central differences away from the folds.
        let h = 1e-3f64;
        let f = |s: f64, t: f64| square_to_sphere(Vec2::new(s as f32, t as f32)).as_dvec3();
        for &(s, t) in &[
            (0.3, 0.4),
            (0.6, 0.55),
            (0.1, 0.2),
            (0.9, 0.7),
            (0.45, 0.93),
        ] {
            let ds = (f(s + h, t) - f(s - h, t)) / (2.0 * h);
            let dt = (f(s, t + h) - f(s, t - h)) / (2.0 * h);
            let j = ds.cross(dt).length();
            assert!(
                (j / (4.0 * std::f64::consts::PI) - 1.0).abs() < 2e-3,
                "({s}, {t}): {j}"
            );
        }
    }

    #[test]
    fn constant_map_integrates_to_four_pi_and_samples_uniformly() {
        let m = EqualAreaMap::new(8, vec![Vec3::ONE; 64]).unwrap();
        assert!((m.integral() - Vec3::splat(4.0 * PI)).abs().max_element() < 1e-4);
        let (w, pdf) = m.sample(Vec2::new(0.3, 0.7)).unwrap();
        assert!((pdf - 1.0 / (4.0 * PI)).abs() < 1e-6);
        assert_eq!(m.pdf(w), pdf);
    }

    #[test]
    fn samples_land_in_their_texel_with_the_density_of_pdf() {
        // A map with one bright texel in each hemisphere: every sample's direction falls in
        // the texel chosen, and pdf(w) equals the density returned.
        let n = 6;
        let mut texels = vec![Vec3::splat(0.1); n * n];
        texels[2 * n + 3] = Vec3::splat(5.0);
        texels[5 * n] = Vec3::new(0.0, 3.0, 0.0);
        let m = EqualAreaMap::new(n, texels).unwrap();
        for k in 0..500 {
            let u = Vec2::new((k as f32 * 0.618034) % 1.0, (k as f32 + 0.5) / 500.0);
            let (w, pdf) = m.sample(u).unwrap();
            assert!(
                (m.pdf(w) - pdf).abs() <= 1e-4 * pdf,
                "{u}: {} vs {pdf}",
                m.pdf(w)
            );
        }
        let total: f32 = m.texels().iter().map(|t| luminance(*t)).sum();
        let bright = luminance(Vec3::splat(5.0)) / total;
        let centre = square_to_sphere(Vec2::new(3.5 / n as f32, 2.5 / n as f32));
        assert!((m.pdf(centre) - bright * (n * n) as f32 / (4.0 * PI)).abs() < 1e-5);
    }
}
