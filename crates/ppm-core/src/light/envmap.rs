//! A latitude-longitude radiance map and the 2D piecewise-constant distribution that samples
//! it (pbrt-v4, Pharr et al. 2023, sec. A.5.6 and 12.5.2; Mitsuba 3's `envmap`).
//!
//! # Parameterisation
//! Texel (i, j) of a W x H image (row i from the top, column j from the left) covers
//! u in [j/W, (j+1)/W], v in [i/H, (i+1)/H], with theta = pi v (polar angle from +y) and
//! phi = 2 pi u, and the local direction
//!
//! w = (sin theta sin phi, cos theta, -sin theta cos phi):
//!
//! the top row is the +y pole, u = 0 looks along -z and u = 1/4 along +x. This is Mitsuba 3's
//! frame (its `envmap` plugin), so an imported `to_world` means the same thing. The radiance
//! is constant over a texel (no interpolation), so the sampling density below is exactly
//! proportional to what it samples, texel by texel.
//!
//! # Sampling
//! A texel is chosen with probability proportional to luminance(L_ij) sin(theta_i) (theta_i
//! at the row's centre: the solid angle a texel subtends shrinks with sin theta), then a
//! point uniform in its (u, v) rectangle; the density in (u, v) is p(u, v) = P_ij W H. The
//! map (u, v) -> w has Jacobian |dw / (du dv)| = 2 pi^2 sin theta, so the solid-angle density
//! is p(w) = p(u, v) / (2 pi^2 sin theta) (pbrt-v4 eq. 12.12).

use crate::bsdf::luminance;
use crate::sampling::Distribution1D;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// A lat-long radiance image (W/(m^2 sr) per texel, linear RGB) with its sampling
/// distribution, built once.
#[derive(Clone, Debug)]
pub struct LatLongMap {
    width: usize,
    height: usize,
    /// Row-major, row 0 at the top (theta = 0).
    texels: Vec<Vec3>,
    /// The choice of a row, proportional to the sum of its texels' weights.
    rows: Distribution1D,
    /// The choice of a column given the row, one distribution per row.
    columns: Vec<Distribution1D>,
    /// Integral of the radiance over the sphere, per channel (W/m^2).
    integral: Vec3,
}

/// Why a map cannot be built.
#[derive(Clone, Debug, PartialEq)]
pub enum MapError {
    /// The texel buffer does not hold width * height texels, or a side is zero.
    Size {
        width: usize,
        height: usize,
        texels: usize,
    },
    /// A texel is negative, NaN or infinite.
    Texel { x: usize, y: usize, value: Vec3 },
}

impl std::fmt::Display for MapError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MapError::Size {
                width,
                height,
                texels,
            } => write!(
                f,
                "a {width}x{height} map needs {} texels, got {texels}",
                width * height
            ),
            MapError::Texel { x, y, value } => write!(
                f,
                "texel ({x}, {y}) is {value}: radiance must be finite and non-negative"
            ),
        }
    }
}

impl LatLongMap {
    /// The map of `texels` (row-major, `width` x `height`, row 0 at the top). Builds the
    /// sampling distribution and the integral over the sphere.
    pub fn new(width: usize, height: usize, texels: Vec<Vec3>) -> Result<Self, MapError> {
        check_texels(width, height, &texels)?;
        let mut columns = Vec::with_capacity(height);
        let mut row_weights = Vec::with_capacity(height);
        let mut integral = [0.0f64; 3];
        let mut weights = vec![0.0f32; width];
        for i in 0..height {
            let sin_theta = (PI * (i as f32 + 0.5) / height as f32).sin();
            let row = &texels[i * width..(i + 1) * width];
            for (w, t) in weights.iter_mut().zip(row) {
                *w = luminance(*t) * sin_theta;
            }
            row_weights.push(weights.iter().map(|&w| w as f64).sum::<f64>() as f32);
            columns.push(Distribution1D::new(&weights));
            // Solid angle of a texel of row i: (2 pi / W) (cos theta_top - cos theta_bottom).
            let (t0, t1) = (
                std::f64::consts::PI * i as f64 / height as f64,
                std::f64::consts::PI * (i + 1) as f64 / height as f64,
            );
            let omega = 2.0 * std::f64::consts::PI / width as f64 * (t0.cos() - t1.cos());
            for t in row {
                for (c, acc) in integral.iter_mut().enumerate() {
                    *acc += t[c] as f64 * omega;
                }
            }
        }
        Ok(LatLongMap {
            width,
            height,
            texels,
            rows: Distribution1D::new(&row_weights),
            columns,
            integral: Vec3::new(integral[0] as f32, integral[1] as f32, integral[2] as f32),
        })
    }

    /// Width and height in texels.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The texels, row-major from the top row.
    pub fn texels(&self) -> &[Vec3] {
        &self.texels
    }

    /// The integral of the radiance over the sphere of directions, per channel: sum of
    /// L_ij times the texel's solid angle (2 pi / W)(cos theta_i - cos theta_(i+1)).
    pub fn integral(&self) -> Vec3 {
        self.integral
    }

    /// The texel (row, column) a local direction falls in, and sin theta.
    #[inline]
    fn texel_of(&self, w: Vec3) -> (usize, usize, f32) {
        let (u, v) = direction_to_uv(w);
        let i = ((v * self.height as f32) as usize).min(self.height - 1);
        let j = ((u * self.width as f32) as usize).min(self.width - 1);
        let sin_theta = (w.x * w.x + w.z * w.z).sqrt();
        (i, j, sin_theta)
    }

    /// Radiance toward local direction `w` (unit; the direction the light comes from).
    #[inline]
    pub fn eval(&self, w: Vec3) -> Vec3 {
        let (i, j, _) = self.texel_of(w);
        self.texels[i * self.width + j]
    }

    /// Solid-angle density of sampling local direction `w`: P_ij W H / (2 pi^2 sin theta),
    /// 0 at the poles (where sampling never lands) and for texels of zero luminance.
    #[inline]
    pub fn pdf(&self, w: Vec3) -> f32 {
        if self.rows.is_empty() {
            return 0.0;
        }
        let (i, j, sin_theta) = self.texel_of(w);
        if sin_theta <= 0.0 {
            return 0.0;
        }
        let p = self.rows.pmf(i) * self.columns[i].pmf(j);
        p * (self.width * self.height) as f32 / (2.0 * PI * PI * sin_theta)
    }

    /// A local direction by the distribution (row, then column given the row, then uniform
    /// within the texel) and its solid-angle density; `None` for an all-black map or a
    /// direction on a pole.
    #[inline]
    pub fn sample(&self, u: Vec2) -> Option<(Vec3, f32)> {
        if self.rows.is_empty() {
            return None;
        }
        let (i, p_row, v_in) = self.rows.sample_continuous(u.y);
        let (j, p_col, u_in) = self.columns[i].sample_continuous(u.x);
        let uu = (j as f32 + u_in) / self.width as f32;
        let vv = (i as f32 + v_in) / self.height as f32;
        let w = uv_to_direction(uu, vv);
        let sin_theta = (w.x * w.x + w.z * w.z).sqrt();
        if sin_theta <= 0.0 {
            return None;
        }
        let pdf = p_row * p_col * (self.width * self.height) as f32 / (2.0 * PI * PI * sin_theta);
        Some((w, pdf))
    }
}

/// `Ok` if `texels` holds `width` x `height` (both non-zero) finite, non-negative radiances;
/// else what is wrong, and where (shared by the lat-long and equal-area maps).
pub(super) fn check_texels(width: usize, height: usize, texels: &[Vec3]) -> Result<(), MapError> {
    if width == 0 || height == 0 || texels.len() != width * height {
        return Err(MapError::Size {
            width,
            height,
            texels: texels.len(),
        });
    }
    match (texels.iter()).position(|t| !t.is_finite() || t.min_element() < 0.0) {
        Some(k) => Err(MapError::Texel {
            x: k % width,
            y: k / width,
            value: texels[k],
        }),
        None => Ok(()),
    }
}

/// (u, v) in [0, 1)^2 of a local unit direction: phi = atan2(x, -z) in [0, 2 pi), theta =
/// acos(y) (the module's frame).
#[inline]
pub fn direction_to_uv(w: Vec3) -> (f32, f32) {
    let mut phi = w.x.atan2(-w.z);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    let u = (phi * (0.5 / PI)).min(1.0);
    let v = (w.y.clamp(-1.0, 1.0).acos() * (1.0 / PI)).min(1.0);
    (if u >= 1.0 { 0.0 } else { u }, v)
}

/// The local unit direction of (u, v): (sin theta sin phi, cos theta, -sin theta cos phi),
/// theta = pi v, phi = 2 pi u.
#[inline]
pub fn uv_to_direction(u: f32, v: f32) -> Vec3 {
    let (sin_t, cos_t) = (PI * v).sin_cos();
    let (sin_p, cos_p) = (2.0 * PI * u).sin_cos();
    Vec3::new(sin_t * sin_p, cos_t, -sin_t * cos_p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uv_round_trips_through_directions() {
        for &(u, v) in &[(0.1, 0.2), (0.6, 0.9), (0.99, 0.5), (0.25, 0.5)] {
            let (u2, v2) = direction_to_uv(uv_to_direction(u, v));
            assert!((u - u2).abs() < 1e-5 && (v - v2).abs() < 1e-5, "{u} {v}");
        }
        // The frame: u = 0 looks along -z, u = 1/4 along +x, v = 0 is +y.
        assert!(uv_to_direction(0.0, 0.5).abs_diff_eq(Vec3::NEG_Z, 1e-6));
        assert!(uv_to_direction(0.25, 0.5).abs_diff_eq(Vec3::X, 1e-6));
        assert!(uv_to_direction(0.0, 0.0).abs_diff_eq(Vec3::Y, 1e-6));
    }

    #[test]
    fn constant_map_integrates_to_four_pi() {
        let m = LatLongMap::new(16, 8, vec![Vec3::ONE; 128]).unwrap();
        assert!((m.integral() - Vec3::splat(4.0 * PI)).abs().max_element() < 1e-4);
    }

    #[test]
    fn bad_maps_are_refused() {
        assert!(LatLongMap::new(2, 2, vec![Vec3::ONE; 3]).is_err());
        let mut t = vec![Vec3::ONE; 4];
        t[3] = Vec3::new(-1.0, 0.0, 0.0);
        assert_eq!(
            LatLongMap::new(2, 2, t).unwrap_err(),
            MapError::Texel {
                x: 1,
                y: 1,
                value: Vec3::new(-1.0, 0.0, 0.0)
            }
        );
    }
}
