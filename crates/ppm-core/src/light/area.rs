//! What every area light shares: a point sampled uniformly on its surface, converted to a
//! solid-angle pdf for next-event estimation, and Lambertian (cosine) one-sided emission.

use super::{DirectSample, EmissionSample};
use crate::sampling::{cosine_hemisphere, Frame};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// A point chosen uniformly on an area light (area pdf 1/A): position, emitting normal, the
/// light's area A and radiance.
#[derive(Clone, Copy, Debug)]
pub(super) struct Emitter {
    pub(super) q: Vec3,
    pub(super) n: Vec3,
    pub(super) area: f32,
    pub(super) le: Vec3,
}

impl Emitter {
    /// The point seen from `p` for next-event estimation. Changing measure from area to solid
    /// angle (Veach 1997, eq. 8.10): p_w = p_A d^2 / cos_l = d^2 / (A cos_l). `None` when the
    /// point faces away from `p` (one-sided emission) or coincides with it.
    #[inline]
    pub(super) fn sample_direct(&self, p: Vec3) -> Option<DirectSample> {
        let d = self.q - p;
        let dist2 = d.length_squared();
        if !dist2.is_finite() || dist2 <= 0.0 {
            return None;
        }
        let dist = dist2.sqrt();
        let wi = d / dist;
        let pdf = solid_angle_pdf(self.area, dist2, -wi.dot(self.n));
        (pdf > 0.0).then_some(DirectSample {
            p: self.q,
            n: self.n,
            wi,
            dist,
            li: self.le,
            pdf,
            is_delta: false,
        })
    }

    /// A light path leaving the point: a cosine-weighted direction about the emitting normal
    /// (pdf cos/pi), so the flux weight Le cos / (p_A p_w) = pi A Le for every sample.
    #[inline(always)]
    pub(super) fn sample_emission(&self, u_dir: Vec2) -> EmissionSample {
        let pdf_area = 1.0 / self.area;
        let local = cosine_hemisphere(u_dir);
        let dir = Frame::new(self.n).to_world(local);
        let cos = local.z;
        let pdf_dir = cos / PI;
        // Le cos / (p_area p_dir) = Le cos / ((1/A) (cos/pi)) = pi A Le, for cos > 0.
        let flux = if pdf_dir > 0.0 {
            self.le * (cos / (pdf_area * pdf_dir))
        } else {
            Vec3::ZERO
        };
        EmissionSample {
            ray_origin: self.q,
            n: self.n,
            dir,
            flux,
            pdf_pos: pdf_area,
            pdf_dir,
        }
    }
}

/// The solid-angle pdf with which [`Emitter::sample_direct`] from `p` produces the point `q`
/// with emitting normal `n` on a light of area `area`; the same expressions, so the same value.
#[inline]
pub(super) fn pdf_direct(area: f32, p: Vec3, q: Vec3, n: Vec3) -> f32 {
    let d = q - p;
    let dist2 = d.length_squared();
    if dist2.is_nan() || dist2 <= 0.0 {
        return 0.0;
    }
    let wi = d / dist2.sqrt();
    solid_angle_pdf(area, dist2, -wi.dot(n))
}

/// The solid-angle pdf cos/pi with which [`Emitter::sample_emission`] leaves along `w` from a
/// point with emitting normal `n`; 0 behind the light.
#[inline]
pub(super) fn pdf_emission_dir(n: Vec3, w: Vec3) -> f32 {
    n.dot(w).max(0.0) / PI
}

/// Lambertian one-sided emission: `le` toward `w` when `n . w > 0`, else zero.
#[inline]
pub(super) fn le(le: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    if n.dot(w) > 0.0 {
        le
    } else {
        Vec3::ZERO
    }
}

/// The solid-angle pdf d^2 / (A cos_l) of a point chosen uniformly on an area-A light, seen
/// from distance d at cosine cos_l to its normal; 0 when the point faces away or the pdf is
/// not finite (`sample_direct` produces no such samples).
#[inline]
fn solid_angle_pdf(area: f32, dist2: f32, cos_l: f32) -> f32 {
    if cos_l.is_nan() || cos_l <= 0.0 {
        return 0.0;
    }
    let pdf = dist2 / (area * cos_l);
    if pdf.is_finite() {
        pdf
    } else {
        0.0
    }
}
