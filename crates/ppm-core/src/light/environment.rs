//! An environment light: radiance arriving from infinitely far in every direction, a constant
//! colour, a lat-long image or an equal-area octahedral one (pbrt-v4's), L(w) = scale *
//! map(R^-1 w) with R a rotation or a reflection (the light's `to_world`; a reflection
//! mirrors the sky, as an imported world mirror does) and w the unit direction toward the light (the direction a ray escaping the
//! scene travels). pbrt-v4's `UniformInfiniteLight` and `ImageInfiniteLight` (Pharr et al.
//! 2023, sec. 12.5), Mitsuba 3's `constant` and `envmap`, SmallVCM's `BackgroundLight`.
//! Its kind is [`super::LightKind::Infinite`]: camera paths that leave the scene find it, and
//! so does light sampling.
//!
//! # Next-event estimation
//! A direction wi by the map's distribution ([`LatLongMap::sample`]: luminance * sin theta per
//! texel, p(w) = p(u, v) / (2 pi^2 sin theta); [`EqualAreaMap::sample`]: luminance per texel,
//! p(w) = P_ij N^2 / (4 pi)); a constant map uniformly over the sphere, p(w) = 1 / (4 pi). The incident radiance is L(wi); the shadow ray ends beyond the scene's
//! bounding sphere. [`EnvironmentLight::pdf_dir`] is the same density, for the MIS weight of
//! an escaping camera path.
//!
//! # Emission
//! As for the directional light (`directional.rs`), but over every direction: a direction wi
//! toward the light with density p(wi), a point uniform on the disk of radius R (the scene's
//! bounding sphere) perpendicular to it, upstream of the sphere (area pdf 1 / (pi R^2)); the
//! path travels along d = -wi. Flux weight L(wi) / (p(wi) / (pi R^2)) (the disk is
//! perpendicular to d: no cosine). Its mean is the power,
//!
//! Phi = pi R^2 * integral over the sphere of L(w) dw
//!
//! (pbrt-v4 `ImageInfiniteLight::Phi`): the flux through the disk from every direction, so
//! the photon density on a surface is its irradiance, integral of L cos.
//!
//! # Densities for bidirectional MIS
//! Georgiev 2012 (TR sec. 5.1, eqs. 48-50 for lights at infinity) and SmallVCM's
//! `BackgroundLight`: next-event's pdf is p(wi) (solid angle; no distance), the emission pdf
//! is p(wi) / (pi R^2) (both times the light's choice), the cosine at the light is 1. A light
//! subpath reaches its first vertex (cosine cos_1) with area density p(wi) cos_1 / (pi R^2):
//! parallel rays, no distance term. Relative to next-event's density of the same direction
//! that is cos_1 / (pi R^2) ([`super::Light::pdf_emission_at`]), as for the directional light.

use super::directional::bounding_sphere;
use super::envmap::LatLongMap;
use super::equal_area::EqualAreaMap;
use super::{DirectSample, EmissionSample};
use crate::sampling::{concentric_disc, uniform_sphere, Frame};
use glam::{Mat3, Vec2, Vec3};
use std::f32::consts::PI;
use std::sync::Arc;

/// What the environment radiates before the scale: one colour, or an image shared by every
/// copy of the light (built once, with its sampling distribution).
#[derive(Clone, Debug)]
pub enum EnvironmentMap {
    /// The same radiance from every direction (W/(m^2 sr)).
    Constant(Vec3),
    /// A lat-long image (see `envmap.rs` for the frame).
    Image(Arc<LatLongMap>),
    /// An equal-area octahedral image, pbrt-v4's (see `equal_area.rs` for the frame).
    EqualArea(Arc<EqualAreaMap>),
}

impl EnvironmentMap {
    /// Radiance toward the local direction `w` (the map's frame).
    #[inline]
    fn eval(&self, w: Vec3) -> Vec3 {
        match self {
            EnvironmentMap::Constant(c) => *c,
            EnvironmentMap::Image(m) => m.eval(w),
            EnvironmentMap::EqualArea(m) => m.eval(w),
        }
    }

    /// Solid-angle density of sampling the local direction `w`: 1 / (4 pi) for a constant
    /// map, the image's density for the others.
    #[inline]
    fn pdf(&self, w: Vec3) -> f32 {
        match self {
            EnvironmentMap::Constant(_) => 1.0 / (4.0 * PI),
            EnvironmentMap::Image(m) => m.pdf(w),
            EnvironmentMap::EqualArea(m) => m.pdf(w),
        }
    }

    /// The integral of the radiance over the sphere of directions, per channel (W/m^2).
    fn integral(&self) -> Vec3 {
        match self {
            EnvironmentMap::Constant(c) => *c * (4.0 * PI),
            EnvironmentMap::Image(m) => m.integral(),
            EnvironmentMap::EqualArea(m) => m.integral(),
        }
    }

    /// Every radiance the map holds (one for a constant map).
    pub fn texels(&self) -> &[Vec3] {
        match self {
            EnvironmentMap::Constant(c) => std::slice::from_ref(c),
            EnvironmentMap::Image(m) => m.texels(),
            EnvironmentMap::EqualArea(m) => m.texels(),
        }
    }
}

/// An environment light (see the module documentation).
#[derive(Clone, Debug)]
pub struct EnvironmentLight {
    map: EnvironmentMap,
    /// Multiplies the map's radiance.
    scale: f32,
    /// Rotation (or reflection) from the map's frame to the world (orthonormal).
    to_world: Mat3,
    /// Centre and radius of the scene's bounding sphere (radius 0 before `preprocess`).
    center: Vec3,
    radius: f32,
}

impl EnvironmentLight {
    /// A light radiating `scale` * `map`, rotated by `to_world` (the map's frame to the
    /// world). `None` unless the scale is finite and non-negative and `to_world` is
    /// orthonormal to 1e-3 (a rotation, or a rotation and a mirror: directions and solid
    /// angles are kept either way).
    pub fn new(map: EnvironmentMap, scale: f32, to_world: Mat3) -> Option<Self> {
        let orthonormal = (to_world.transpose() * to_world).abs_diff_eq(Mat3::IDENTITY, 1e-3)
            && (to_world.determinant().abs() - 1.0).abs() < 1e-3;
        if !(scale.is_finite() && scale >= 0.0 && orthonormal) {
            return None;
        }
        if let EnvironmentMap::Constant(c) = map {
            if !(c.is_finite() && c.min_element() >= 0.0) {
                return None;
            }
        }
        Some(EnvironmentLight {
            map,
            scale,
            to_world,
            center: Vec3::ZERO,
            radius: 0.0,
        })
    }

    /// The map, its scale and its rotation (what the light is made of, for fingerprints).
    pub fn parts(&self) -> (&EnvironmentMap, f32, Mat3) {
        (&self.map, self.scale, self.to_world)
    }

    /// The radius of the disk of origins (the scene's bounding sphere, slightly enlarged).
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// Sets the bounding sphere from the scene's bounds, as the directional light does.
    pub fn preprocess(&mut self, bounds: (Vec3, Vec3)) {
        (self.center, self.radius) = bounding_sphere(bounds);
    }

    /// Moves the bounding sphere with the scene (directions do not change).
    pub(super) fn transform(&mut self, scale: f32, offset: Vec3) {
        self.center = self.center * scale + offset;
        self.radius *= scale;
    }

    /// Moves the bounding sphere by `offset`.
    pub(super) fn translate(&mut self, offset: Vec3) {
        self.center += offset;
    }

    /// Integral of L over the sphere of directions, per channel (W/m^2).
    pub fn radiance_integral(&self) -> Vec3 {
        self.scale * self.map.integral()
    }

    /// pi R^2, the area of the disk of origins.
    #[inline]
    fn disk_area(&self) -> f32 {
        PI * self.radius * self.radius
    }

    /// Phi = pi R^2 * integral of L over the sphere (see the module documentation).
    pub fn power(&self) -> Vec3 {
        self.radiance_integral() * self.disk_area()
    }

    /// The area pdf of an emission origin on the disk: 1 / (pi R^2).
    #[inline]
    pub(super) fn pdf_pos(&self) -> f32 {
        1.0 / self.disk_area()
    }

    /// L(w) = scale * map(R^-1 w): the radiance arriving from direction `wi` (unit, toward
    /// the light).
    #[inline]
    pub fn radiance(&self, wi: Vec3) -> Vec3 {
        match &self.map {
            EnvironmentMap::Constant(c) => *c * self.scale,
            map => map.eval(self.to_world.transpose() * wi) * self.scale,
        }
    }

    /// The solid-angle density with which [`EnvironmentLight::sample_dir`] produces `wi`:
    /// 1 / (4 pi) for a constant map, p(u, v) / (2 pi^2 sin theta) for a lat-long image,
    /// P_ij N^2 / (4 pi) for an equal-area one (the rotation preserves solid angle).
    #[inline]
    pub fn pdf_dir(&self, wi: Vec3) -> f32 {
        match &self.map {
            EnvironmentMap::Constant(_) => 1.0 / (4.0 * PI),
            map => map.pdf(self.to_world.transpose() * wi),
        }
    }

    /// A direction toward the light and its solid-angle density ([`EnvironmentLight::pdf_dir`]).
    #[inline]
    fn sample_dir(&self, u: Vec2) -> Option<(Vec3, f32)> {
        match &self.map {
            EnvironmentMap::Constant(_) => Some((uniform_sphere(u), 1.0 / (4.0 * PI))),
            EnvironmentMap::Image(m) => self.image_direction(m.sample(u)?.0),
            EnvironmentMap::EqualArea(m) => self.image_direction(m.sample(u)?.0),
        }
    }

    /// The world direction of an image's local sample `w`, and its density evaluated again
    /// from that direction, so that a sample's pdf is `pdf_dir` of its direction bit for bit
    /// (MIS weights compare them).
    #[inline]
    fn image_direction(&self, w: Vec3) -> Option<(Vec3, f32)> {
        let wi = (self.to_world * w).normalize();
        Some((wi, self.pdf_dir(wi)))
    }

    /// Next-event estimation from `p`: wi by the map's distribution, radiance L(wi), at a
    /// distance beyond the bounding sphere (|p - c| + 2 R).
    #[inline]
    pub(super) fn sample_direct(&self, p: Vec3, u: Vec2) -> Option<DirectSample> {
        let (wi, pdf) = self.sample_dir(u)?;
        let dist = (p - self.center).length() + 2.0 * self.radius;
        if !(dist.is_finite() && pdf > 0.0) {
            return None;
        }
        Some(DirectSample {
            p: p + wi * dist,
            n: Vec3::ZERO,
            wi,
            dist,
            li: self.radiance(wi),
            pdf,
            is_delta: false,
        })
    }

    /// A light path: wi with density p(wi), an origin uniform on the disk of radius R centred
    /// at c + R wi perpendicular to wi, direction d = -wi; flux weight L(wi) pi R^2 / p(wi).
    /// A failed direction sample (an all-black map) carries no flux.
    #[inline]
    pub(super) fn sample_emission(&self, u_pos: Vec2, u_dir: Vec2) -> EmissionSample {
        let Some((wi, pdf_dir)) = self.sample_dir(u_dir) else {
            return EmissionSample {
                ray_origin: self.center,
                n: Vec3::ZERO,
                dir: Vec3::Y,
                flux: Vec3::ZERO,
                pdf_pos: self.pdf_pos(),
                pdf_dir: 0.0,
            };
        };
        let disk = concentric_disc(u_pos) * self.radius;
        let frame = Frame::new(wi);
        let origin =
            self.center + wi * self.radius + frame.to_world(Vec3::new(disk.x, disk.y, 0.0));
        let pdf_pos = self.pdf_pos();
        EmissionSample {
            ray_origin: origin,
            n: Vec3::ZERO,
            dir: -wi,
            flux: self.radiance(wi) / (pdf_pos * pdf_dir),
            pdf_pos,
            pdf_dir,
        }
    }
}
