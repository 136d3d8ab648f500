//! A spot light: a delta light at a point, emitting into a cone about its axis with a smooth
//! falloff toward the cone's edge.
//!
//! # Falloff
//! The radiant intensity toward a unit direction `w` at angle theta from the axis is
//!
//! I(w) = I0 * s(cos theta),  s(mu) = 1 for mu >= cos(theta_s), 0 for mu <= cos(theta_e),
//! and smoothstep(t) = 3 t^2 - 2 t^3, t = (mu - cos theta_e) / (cos theta_s - cos theta_e)
//! in between,
//!
//! with theta_e the cone angle (where the light ends) and theta_s the falloff start. This is
//! pbrt-v4's spot light (Pharr et al. 2023, sec. 12.1.1): its `coneangle` is theta_e and its
//! `conedelta` is theta_e - theta_s. Mitsuba 3's `spot` has the same two angles as
//! `cutoff_angle` (theta_e) and `beam_width` (theta_s), with a falloff linear in theta instead
//! of smooth in cos theta, so the two renderers agree inside theta_s and outside theta_e only.
//!
//! # Power
//! Phi = integral of I over the sphere = 2 pi I0 integral_{cos theta_e}^1 s(mu) dmu
//!     = 2 pi I0 ((1 - cos theta_s) + (cos theta_s - cos theta_e) / 2),
//! since the smoothstep integrates to 1/2 over [0, 1] (pbrt-v4, `SpotLight::Phi`).
//!
//! # Sampling
//! Emission: a direction uniform in the cone of half-angle theta_e (pdf 1 / (2 pi (1 -
//! cos theta_e)), the solid angle of the cone), weighted by the falloff: flux = I(w) / pdf.
//! Next-event estimation: the one point, pdf 1 (a discrete choice), radiance I(w) / d^2.

use super::{DirectSample, EmissionSample};
use crate::sampling::Frame;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// A spot light (see the module documentation for its falloff): radiant intensity
/// `intensity` (W/sr) along its axis, none outside its cone.
#[derive(Clone, Copy, Debug)]
pub struct SpotLight {
    /// Where the light is.
    pub position: Vec3,
    /// Unit direction of the axis.
    direction: Vec3,
    /// Radiant intensity on the axis (W/sr), per channel.
    pub intensity: Vec3,
    /// theta_e and theta_s, radians, 0 <= theta_s <= theta_e <= pi, theta_e > 0.
    cone_angle: f32,
    falloff_start: f32,
    /// cos theta_e, cos theta_s.
    cos_end: f32,
    cos_start: f32,
    /// 1 - cos theta_e, computed as 2 sin^2(theta_e / 2) to keep the digits of narrow cones.
    one_minus_cos_end: f32,
}

impl SpotLight {
    /// A spot light at `position` pointing along `direction` (any length but zero), with
    /// the cone angle theta_e and the falloff start theta_s in radians. `None` unless the
    /// direction is finite and non-zero and 0 <= theta_s <= theta_e <= pi with theta_e > 0.
    pub fn new(
        position: Vec3,
        direction: Vec3,
        intensity: Vec3,
        cone_angle: f32,
        falloff_start: f32,
    ) -> Option<Self> {
        let direction = direction.try_normalize()?;
        let angles_ok = cone_angle > 0.0
            && cone_angle <= PI
            && falloff_start >= 0.0
            && falloff_start <= cone_angle;
        angles_ok.then(|| {
            let half_sin = (0.5 * cone_angle).sin();
            SpotLight {
                position,
                direction,
                intensity,
                cone_angle,
                falloff_start,
                cos_end: cone_angle.cos(),
                cos_start: falloff_start.cos(),
                one_minus_cos_end: 2.0 * half_sin * half_sin,
            }
        })
    }

    /// The unit direction of the axis.
    pub fn direction(&self) -> Vec3 {
        self.direction
    }

    /// The cone angle theta_e (radians): no light beyond it.
    pub fn cone_angle(&self) -> f32 {
        self.cone_angle
    }

    /// The falloff start theta_s (radians): full intensity within it.
    pub fn falloff_start(&self) -> f32 {
        self.falloff_start
    }

    /// Phi = 2 pi I0 ((1 - cos theta_s) + (cos theta_s - cos theta_e) / 2).
    pub fn power(&self) -> Vec3 {
        let half_sin = (0.5 * self.falloff_start).sin();
        let one_minus_cos_start = 2.0 * half_sin * half_sin;
        let falloff_band = self.one_minus_cos_end - one_minus_cos_start;
        2.0 * PI * self.intensity * (one_minus_cos_start + 0.5 * falloff_band)
    }

    /// The falloff s(mu) at mu = cos theta, the cosine between the axis and the direction
    /// of emission.
    #[inline]
    pub fn falloff(&self, mu: f32) -> f32 {
        if mu >= self.cos_start {
            1.0
        } else if mu <= self.cos_end || mu.is_nan() {
            0.0
        } else {
            // cos_end < mu < cos_start here, so the denominator is positive.
            let t = (mu - self.cos_end) / (self.cos_start - self.cos_end);
            t * t * (3.0 - 2.0 * t)
        }
    }

    /// The light seen from `p`: the only point, with pdf 1 (a discrete choice) and incident
    /// radiance as a delta of weight I(w) / d^2, w the direction from the light to `p`.
    /// `None` when `p` is at the light or outside the cone (no light reaches it).
    #[inline]
    pub(super) fn sample_direct(&self, p: Vec3) -> Option<DirectSample> {
        let d = self.position - p;
        let dist2 = d.length_squared();
        if !dist2.is_finite() || dist2 <= 0.0 {
            return None;
        }
        let dist = dist2.sqrt();
        let wi = d / dist;
        let falloff = self.falloff(self.direction.dot(-wi));
        (falloff > 0.0).then(|| DirectSample {
            p: self.position,
            n: Vec3::ZERO,
            wi,
            dist,
            li: self.intensity * (falloff / dist2),
            pdf: 1.0,
            is_delta: true,
        })
    }

    /// A light path leaving the light: a direction uniform in the cone (cos theta uniform
    /// in [cos theta_e, 1], phi uniform; pdf [`SpotLight::pdf_emission_dir`]), flux weight
    /// I(w) / p_w = I0 s(cos theta) 2 pi (1 - cos theta_e).
    #[inline]
    pub(super) fn sample_emission(&self, u_dir: Vec2) -> EmissionSample {
        // 1 - cos theta directly, so that narrow cones keep their resolution.
        let one_minus_cos = u_dir.x * self.one_minus_cos_end;
        let cos_theta = 1.0 - one_minus_cos;
        let sin_theta = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
        let phi = 2.0 * PI * u_dir.y;
        let local = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
        let dir = Frame::new(self.direction).to_world(local).normalize();
        // The density and the falloff of the direction as rounded, by the expressions that
        // `pdf_emission` uses, so the two agree exactly.
        let pdf_dir = self.pdf_emission_dir(dir);
        let flux = if pdf_dir > 0.0 {
            self.intensity * (self.falloff(self.direction.dot(dir)) / pdf_dir)
        } else {
            Vec3::ZERO
        };
        EmissionSample {
            ray_origin: self.position,
            n: Vec3::ZERO,
            dir,
            flux,
            pdf_pos: 1.0,
            pdf_dir,
        }
    }

    /// The solid-angle density with which [`SpotLight::sample_emission`] leaves along unit
    /// `w`: 1 / (2 pi (1 - cos theta_e)) inside the cone (cos theta >= cos theta_e), else 0.
    #[inline]
    pub(super) fn pdf_emission_dir(&self, w: Vec3) -> f32 {
        if self.direction.dot(w) >= self.cos_end {
            1.0 / (2.0 * PI * self.one_minus_cos_end)
        } else {
            0.0
        }
    }
}
