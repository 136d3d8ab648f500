//! A point light: a delta light with no geometry, isotropic radiant intensity.

use super::{DirectSample, EmissionSample};
use crate::sampling::uniform_sphere;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// The solid-angle pdf of a point light's emission direction (uniform on the sphere).
pub(super) const PDF_EMISSION_DIR: f32 = 1.0 / (4.0 * PI);

/// A point light without geometry: radiant intensity `intensity` (W/sr) in every direction.
#[derive(Clone, Copy, Debug)]
pub struct PointLight {
    pub position: Vec3,
    pub intensity: Vec3,
}

impl PointLight {
    /// Phi = 4 pi I.
    pub fn power(&self) -> Vec3 {
        4.0 * PI * self.intensity
    }

    /// The light seen from `p`: the only point, with pdf 1 (a discrete choice) and incident
    /// radiance as a delta of weight I / d^2. `None` when `p` is at the light.
    #[inline]
    pub(super) fn sample_direct(&self, p: Vec3) -> Option<DirectSample> {
        let d = self.position - p;
        let dist2 = d.length_squared();
        if !dist2.is_finite() || dist2 <= 0.0 {
            return None;
        }
        let dist = dist2.sqrt();
        Some(DirectSample {
            p: self.position,
            n: Vec3::ZERO,
            wi: d / dist,
            dist,
            li: self.intensity / dist2,
            pdf: 1.0,
            is_delta: true,
        })
    }

    /// A light path leaving the light: a uniform direction (pdf 1/(4 pi)), so the flux weight
    /// I / p_w = 4 pi I for every sample.
    #[inline]
    pub(super) fn sample_emission(&self, u_dir: Vec2) -> EmissionSample {
        let dir = uniform_sphere(u_dir);
        let pdf_dir = PDF_EMISSION_DIR;
        EmissionSample {
            ray_origin: self.position,
            n: Vec3::ZERO,
            dir,
            flux: self.intensity / pdf_dir,
            pdf_pos: 1.0,
            pdf_dir,
        }
    }
}
