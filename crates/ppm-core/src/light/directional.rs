//! A directional (distant) light: the sun. Parallel light of irradiance E (W/m^2, measured on
//! a surface facing it) arriving from infinitely far along one direction; pbrt-v4's
//! `DistantLight` (Pharr et al. 2023, sec. 12.4), Mitsuba 3's `directional`, SmallVCM's
//! `DirectionalLight`. A delta in direction ([`super::LightKind::DeltaDirection`]): no camera
//! path can hit it.
//!
//! # Next-event estimation
//! The only direction toward the light is wi = -d (d the direction light travels), chosen with
//! probability 1 (a discrete choice, pdf 1); the incident radiance is a delta of weight E
//! about -d, so a surface at p receives E max(0, n . wi): no 1/r^2. The shadow ray must reach
//! "infinity": it ends on a point beyond the scene's bounding sphere.
//!
//! # Emission
//! The light's power in a bounded scene is the flux that crosses the scene's bounding sphere
//! (centre c, radius R): the flux through the disk of radius R perpendicular to d, Phi = E pi
//! R^2 (pbrt-v4 `DistantLight::Phi`). A light path starts at a point uniform on that disk
//! (area pdf p_pos = 1/(pi R^2)), placed upstream of the sphere (its centre at c - R d, so
//! every origin is outside the sphere), and leaves along d (a delta in direction: pdf_dir = 1,
//! a discrete choice). Flux weight = E / p_pos = E pi R^2 for every sample: the irradiance
//! on the disk divided by the density of the origin. The photon density on a surface facing
//! the light then is Phi / (pi R^2) = E, and on a tilted one E cos theta.
//!
//! # Densities for bidirectional MIS
//! Georgiev 2012 ("Implementing vertex connection and merging", sec. 5.1 on lights at
//! infinity) and SmallVCM: the emission pdf of a directional light is the area density of
//! the disk, p_pos (SmallVCM's `emissionPdfW` = concentric disk pdf / R^2), the next-event pdf
//! is 1 and the cosine at the light is 1. A light subpath reaches its first vertex x_1 (cosine
//! cos_1 to the light's direction) with area density p_pos cos_1: parallel rays, so the
//! distance to the disk does not enter (no 1/d^2; the light is "at infinity" even though our
//! origins are on a finite disk).

use super::{DirectSample, EmissionSample};
use crate::sampling::{concentric_disc, Frame};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// A directional light of irradiance `irradiance` (W/m^2 per channel, on a surface facing
/// it) travelling along a unit direction. Its disk of origins is set from the scene's bounds
/// by [`DirectionalLight::preprocess`], which the scene builder calls once.
#[derive(Clone, Copy, Debug)]
pub struct DirectionalLight {
    /// Unit direction the light travels (from the light into the scene).
    direction: Vec3,
    /// Irradiance on a surface perpendicular to `direction` (W/m^2), per channel.
    pub irradiance: Vec3,
    /// Centre and radius of the scene's bounding sphere (radius 0 before `preprocess`).
    center: Vec3,
    radius: f32,
}

impl DirectionalLight {
    /// A light travelling along `direction` (any length but zero). `None` unless the
    /// direction is finite and non-zero.
    pub fn new(direction: Vec3, irradiance: Vec3) -> Option<Self> {
        Some(DirectionalLight {
            direction: direction.try_normalize()?,
            irradiance,
            center: Vec3::ZERO,
            radius: 0.0,
        })
    }

    /// The unit direction the light travels.
    pub fn direction(&self) -> Vec3 {
        self.direction
    }

    /// The radius of the disk of origins (the scene's bounding sphere, slightly enlarged).
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// Sets the bounding sphere from the scene's bounds (min, max): the sphere around the box,
    /// enlarged by 0.1% so that no geometry touches the disk of origins; a scene without
    /// extent (no geometry) gets a unit sphere, so the power stays finite and positive.
    pub fn preprocess(&mut self, bounds: (Vec3, Vec3)) {
        (self.center, self.radius) = bounding_sphere(bounds);
    }

    /// Moves the light's bounding sphere with the scene (the direction does not change).
    pub(super) fn transform(&mut self, scale: f32, offset: Vec3) {
        self.center = self.center * scale + offset;
        self.radius *= scale;
    }

    /// Moves the light's bounding sphere by `offset`.
    pub(super) fn translate(&mut self, offset: Vec3) {
        self.center += offset;
    }

    /// pi R^2, the area of the disk of origins.
    #[inline]
    fn disk_area(&self) -> f32 {
        PI * self.radius * self.radius
    }

    /// Phi = E pi R^2: the flux through the disk that covers the scene's bounding sphere.
    pub fn power(&self) -> Vec3 {
        self.irradiance * self.disk_area()
    }

    /// The area pdf of an emission origin on the disk: 1 / (pi R^2).
    #[inline]
    pub(super) fn pdf_pos(&self) -> f32 {
        1.0 / self.disk_area()
    }

    /// The light seen from `p`: the direction -d with pdf 1 (a discrete choice), incident
    /// radiance a delta of weight E, at a distance that leaves the bounding sphere (|p - c| +
    /// 2 R: beyond the sphere from any point inside it, and from points outside too).
    #[inline]
    pub(super) fn sample_direct(&self, p: Vec3) -> Option<DirectSample> {
        let wi = -self.direction;
        let dist = (p - self.center).length() + 2.0 * self.radius;
        if !dist.is_finite() {
            return None;
        }
        Some(DirectSample {
            p: p + wi * dist,
            n: Vec3::ZERO,
            wi,
            dist,
            li: self.irradiance,
            pdf: 1.0,
            is_delta: true,
        })
    }

    /// A light path: an origin uniform on the disk of radius R centred at c - R d,
    /// perpendicular to d (concentric mapping, area pdf 1/(pi R^2)), direction d (pdf 1, a
    /// delta), flux weight E / p_pos = E pi R^2.
    #[inline]
    pub(super) fn sample_emission(&self, u_pos: Vec2) -> EmissionSample {
        let disk = concentric_disc(u_pos) * self.radius;
        let frame = Frame::new(self.direction);
        let origin = self.center - self.direction * self.radius
            + frame.to_world(Vec3::new(disk.x, disk.y, 0.0));
        let pdf_pos = self.pdf_pos();
        EmissionSample {
            ray_origin: origin,
            n: Vec3::ZERO,
            dir: self.direction,
            flux: self.irradiance / pdf_pos,
            pdf_pos,
            pdf_dir: 1.0,
        }
    }
}

/// The sphere (centre, radius) around the scene's bounds (min, max), enlarged by 0.1% so that
/// no geometry touches a disk of origins on it; a scene without extent (no geometry) gets a
/// unit sphere, so the power of a light at infinity stays finite and positive.
pub(super) fn bounding_sphere(bounds: (Vec3, Vec3)) -> (Vec3, f32) {
    let (lo, hi) = bounds;
    let radius = 0.5 * (hi - lo).length() * 1.001;
    if radius.is_finite() && radius > 0.0 {
        (0.5 * (lo + hi), radius)
    } else if (lo + hi).is_finite() {
        (0.5 * (lo + hi), 1.0)
    } else {
        (Vec3::ZERO, 1.0)
    }
}
