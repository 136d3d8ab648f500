//! Lights: every emissive triangle and sphere is an area light; point and spot lights have no
//! geometry.
//!
//! A closed set of models behind one enum, one file per model, as for the BSDFs. Each model
//! tells its [`LightKind`] (pbrt-v4's `LightType`); code outside this module asks the kind,
//! or a method of [`Light`], never the model.
//!
//! # The contract (every model follows it)
//! - Lights emit radiance; photons leave them carrying flux (`Importance` transport starts
//!   here, see [`crate::bsdf::TransportMode`]).
//! - Area lights ([`TriangleLight`], [`SphereLight`]) emit radiance `le` from one side, the
//!   side their geometric (emitting) normal points to, with a cosine (Lambertian)
//!   distribution: [`Light::le`] is `le` toward directions `w` with `n . w > 0` and zero
//!   otherwise. Their power is Phi = pi A Le.
//! - Delta lights ([`PointLight`], [`SpotLight`]) have no area: only [`Light::sample_direct`]
//!   finds them, with pdf 1 (a discrete choice) or not at all where they send no light, and
//!   [`Light::pdf_direct`] and [`Light::le`] are zero. Their emission leaves one point:
//!   [`Light::pdf_emission`] is (1, the direction's solid-angle density). A point light of
//!   intensity I (W/sr) has Phi = 4 pi I; a spot light's power is in `spot.rs`.
//! - [`Light::pdf_direct`] is the solid-angle density with which [`Light::sample_direct`]
//!   produces a point, computed by the same expressions, so the two agree exactly.
//! - [`Light::sample_emission`] starts a light path; the mean of its `flux` is
//!   [`Light::power`].
//!
//! Every match on [`Light`] lists all variants: a new model does not compile until each
//! operation handles it. To add one, see ARCHITECTURE.md ("To add a light").

mod area;
mod point;
mod sphere;
mod spot;
mod triangle;

pub use point::PointLight;
pub use sphere::SphereLight;
pub use spot::SpotLight;
pub use triangle::TriangleLight;

use crate::geometry::{Ray, Sphere, Triangle};
use glam::{Vec2, Vec3};

/// The largest power per channel (W) a light may emit. f32 holds up to 3.4e38, but a photon's
/// flux is divided by the light's selection probability and the density estimate multiplies
/// it by 1/(pi r^2) (1e6 and more for small radii) and sums many photons; 1e20 W leaves those
/// steps about 18 orders of magnitude of headroom, and no physically scaled scene comes near
/// it (a 100 W bulb is 1e2 W; the sun, 3.8e26 W, must be modelled by its irradiance).
pub const MAX_LIGHT_POWER: f32 = 1e20;

/// One light of the scene.
#[derive(Clone, Copy, Debug)]
pub enum Light {
    /// An emissive triangle.
    Triangle(TriangleLight),
    /// An emissive sphere; it emits inward when `sphere.inward` is set.
    Sphere(SphereLight),
    /// A point light (a delta light: found only by light sampling).
    Point(PointLight),
    /// A spot light (a delta light emitting into a cone).
    Spot(SpotLight),
}

/// What sort of light a model is, as pbrt-v4's `LightType` says it: what finds it and what
/// it needs. Checks, warnings and messages outside the light module ask this, not the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightKind {
    /// Emits from one point (point and spot lights): only light sampling finds it, a camera
    /// path never hits it, and its light through a specular surface is beyond a path tracer.
    DeltaPosition,
    /// Emits along one direction from infinitely far (a distant light). No model yet.
    DeltaDirection,
    /// Emits from the surface of scene geometry (emissive triangles and spheres).
    Area,
    /// Emits from infinitely far in every direction (an environment). No model yet.
    Infinite,
}

impl LightKind {
    /// True for the kinds that only light sampling finds (a delta distribution in position
    /// or direction).
    #[inline]
    pub fn is_delta(self) -> bool {
        match self {
            LightKind::DeltaPosition | LightKind::DeltaDirection => true,
            LightKind::Area | LightKind::Infinite => false,
        }
    }
}

/// A light sample for next-event estimation, seen from a shading point.
#[derive(Clone, Copy, Debug)]
pub struct DirectSample {
    /// Point on the light, and its geometric normal (zero for delta lights).
    pub p: Vec3,
    pub n: Vec3,
    /// Unit direction from the shading point toward the light, and the distance.
    pub wi: Vec3,
    pub dist: f32,
    /// Radiance arriving along -wi (for delta lights: the intensity toward the point / dist^2).
    pub li: Vec3,
    /// Solid-angle pdf of this sample, not counting the choice of the light (1 for delta lights).
    pub pdf: f32,
    pub is_delta: bool,
}

/// A sampled emission: the start of a light path.
#[derive(Clone, Copy, Debug)]
pub struct EmissionSample {
    pub ray_origin: Vec3,
    /// Geometric normal at the origin (zero for delta lights), for offsetting the ray.
    pub n: Vec3,
    pub dir: Vec3,
    /// Flux weight Le * cos / (p_area * p_dir), not counting the choice of the light.
    pub flux: Vec3,
    /// Area pdf of the origin (1 for delta lights) and solid-angle pdf of the direction.
    pub pdf_pos: f32,
    pub pdf_dir: f32,
}

impl Light {
    /// An area light on an emissive triangle; `None` for a degenerate one.
    pub fn triangle(tri: Triangle, le: Vec3, prim: u32) -> Option<Self> {
        TriangleLight::new(tri, le, prim).map(Light::Triangle)
    }

    /// An area light on an emissive sphere (global primitive id `prim`).
    pub fn sphere(sphere: Sphere, le: Vec3, prim: u32) -> Self {
        Light::Sphere(SphereLight { sphere, le, prim })
    }

    /// A spot light; `None` for a zero direction or angles out of range (see
    /// [`SpotLight::new`]).
    pub fn spot(
        position: Vec3,
        direction: Vec3,
        intensity: Vec3,
        cone_angle: f32,
        falloff_start: f32,
    ) -> Option<Self> {
        SpotLight::new(position, direction, intensity, cone_angle, falloff_start).map(Light::Spot)
    }

    /// The model's kind. One exhaustive match: a new model says here what it is.
    #[inline]
    pub fn kind(&self) -> LightKind {
        match self {
            Light::Triangle(_) | Light::Sphere(_) => LightKind::Area,
            Light::Point(_) | Light::Spot(_) => LightKind::DeltaPosition,
        }
    }

    /// Total emitted power per channel: pi * A * Le for an area light, 4 pi I for a point light,
    /// the integral of the falloff for a spot light.
    pub fn power(&self) -> Vec3 {
        match self {
            Light::Triangle(light) => light.power(),
            Light::Sphere(light) => light.power(),
            Light::Point(light) => light.power(),
            Light::Spot(light) => light.power(),
        }
    }

    /// Moves the light by `offset` (its geometry for an area light).
    pub fn translate(&mut self, offset: Vec3) {
        match self {
            Light::Triangle(light) => {
                for v in &mut light.tri.v {
                    *v += offset;
                }
            }
            Light::Sphere(light) => light.sphere.center += offset,
            Light::Point(light) => light.position += offset,
            Light::Spot(light) => light.position += offset,
        }
    }

    /// The light as part of a scene scaled by `scale` > 0 about the origin and then moved by
    /// `offset` (every point p to p scale + offset), lighting the scaled scene as it lit the
    /// original: an area light keeps its radiance (its power grows by scale^2 with its area),
    /// a delta light's intensity grows by scale^2 so its irradiance at the scaled distances is
    /// kept. Directions and angles do not change.
    pub fn transform(&mut self, scale: f32, offset: Vec3) {
        let scale2 = scale * scale;
        match self {
            Light::Triangle(light) => {
                for v in &mut light.tri.v {
                    *v = *v * scale + offset;
                }
                light.area *= scale2;
            }
            Light::Sphere(light) => {
                light.sphere.center = light.sphere.center * scale + offset;
                light.sphere.radius *= scale;
            }
            Light::Point(light) => {
                light.position = light.position * scale + offset;
                light.intensity *= scale2;
            }
            Light::Spot(light) => {
                light.position = light.position * scale + offset;
                light.intensity *= scale2;
            }
        }
    }

    /// The model's name for messages: `emissive triangle`, `point light`...
    pub fn name(&self) -> &'static str {
        match self {
            Light::Triangle(_) => "emissive triangle",
            Light::Sphere(_) => "emissive sphere",
            Light::Point(_) => "point light",
            Light::Spot(_) => "spot light",
        }
    }

    /// What sets the light's power, for messages: `intensity [1, 1, 1]`, `emission [17, 12,
    /// 4]`, with a spot light's cone angle.
    pub fn describe(&self) -> String {
        match self {
            Light::Triangle(light) => format!("emission {}", light.le),
            Light::Sphere(light) => format!("emission {}", light.le),
            Light::Point(light) => format!("intensity {}", light.intensity),
            Light::Spot(light) => format!(
                "intensity {}, cone angle {} degrees",
                light.intensity,
                light.cone_angle().to_degrees()
            ),
        }
    }

    /// The global primitive id of an area light's surface; `None` for lights without one.
    pub fn prim(&self) -> Option<u32> {
        match self {
            Light::Triangle(light) => Some(light.prim),
            Light::Sphere(light) => Some(light.prim),
            Light::Point(_) | Light::Spot(_) => None,
        }
    }

    /// `Ok` if every channel of [`Light::power`] is finite and at most [`MAX_LIGHT_POWER`];
    /// else the power, computed again in f64 so that an overflowing one is reported by value.
    pub fn check_power(&self) -> Result<(), f64> {
        let power = self.power();
        if power.is_finite() && power.max_element() <= MAX_LIGHT_POWER {
            return Ok(());
        }
        let pi = std::f64::consts::PI;
        let (scale, value) = match self {
            Light::Triangle(light) => (pi * light.area as f64, light.le.max_element()),
            Light::Sphere(light) => (pi * light.sphere.area() as f64, light.le.max_element()),
            Light::Point(light) => (4.0 * pi, light.intensity.max_element()),
            Light::Spot(light) => {
                // 2 pi ((1 - cos theta_s) + (cos theta_s - cos theta_e) / 2), in f64.
                let one_minus_cos = |angle: f32| 1.0 - (angle as f64).cos();
                let start = one_minus_cos(light.falloff_start());
                let end = one_minus_cos(light.cone_angle());
                (
                    2.0 * pi * (start + 0.5 * (end - start)),
                    light.intensity.max_element(),
                )
            }
        };
        Err(scale * value as f64)
    }

    /// True for lights that only light sampling can find (see [`LightKind::is_delta`]).
    #[inline]
    pub fn is_delta(&self) -> bool {
        self.kind().is_delta()
    }

    /// Samples a point on the light as seen from `p` for next-event estimation.
    /// Area lights: uniform by area, converted to solid angle: pdf = d^2 / (A cos_l).
    /// `None` if the sampled point faces away (one-sided emission) or is degenerate.
    #[inline]
    pub fn sample_direct(&self, p: Vec3, u: Vec2) -> Option<DirectSample> {
        match self {
            Light::Triangle(light) => light.emitter(u).sample_direct(p),
            Light::Sphere(light) => light.emitter(u).sample_direct(p),
            Light::Point(light) => light.sample_direct(p),
            Light::Spot(light) => light.sample_direct(p),
        }
    }

    /// The solid-angle pdf with which [`Light::sample_direct`] from `p` would produce the point
    /// `q` with emitting normal `n` (not counting the choice of the light); 0 for delta lights.
    #[inline]
    pub fn pdf_direct(&self, p: Vec3, q: Vec3, n: Vec3) -> f32 {
        match self {
            Light::Triangle(light) => area::pdf_direct(light.area, p, q, n),
            Light::Sphere(light) => area::pdf_direct(light.sphere.area(), p, q, n),
            Light::Point(_) | Light::Spot(_) => 0.0,
        }
    }

    /// Radiance emitted from a point with geometric normal `n` toward direction `w` (unit):
    /// one-sided for area lights, zero for delta lights.
    #[inline]
    pub fn le(&self, n: Vec3, w: Vec3) -> Vec3 {
        match self {
            Light::Triangle(light) => area::le(light.le, n, w),
            Light::Sphere(light) => area::le(light.le, n, w),
            Light::Point(_) | Light::Spot(_) => Vec3::ZERO,
        }
    }

    /// Samples the start of a light path: for area lights a point uniform by area (pdf 1/A)
    /// and a cosine-weighted direction (pdf cos/pi) about the emitting normal, so the flux
    /// weight Le cos / (p_area p_dir) = pi A Le is the same for every sample. Point lights: a
    /// uniform direction (pdf 1/(4 pi)), weight 4 pi I. Spot lights: a direction uniform in
    /// the cone, weighted by the falloff (`spot.rs`).
    /// Always inlined (once per light path): left to LLVM it stayed a call, and so did the
    /// emitter's sampling inside it.
    #[inline(always)]
    pub fn sample_emission(&self, u_pos: Vec2, u_dir: Vec2) -> EmissionSample {
        match self {
            Light::Triangle(light) => light.emitter(u_pos).sample_emission(u_dir),
            Light::Sphere(light) => light.emitter(u_pos).sample_emission(u_dir),
            Light::Point(light) => light.sample_emission(u_dir),
            Light::Spot(light) => light.sample_emission(u_dir),
        }
    }

    /// The densities with which [`Light::sample_emission`] produces a light path leaving
    /// the point with emitting normal `n` in unit direction `w`: (area pdf of the point, solid-
    /// angle pdf of the direction), not counting the choice of the light. Area lights:
    /// (1/A, max(0, n . w)/pi); point lights: (1, 1/(4 pi)); spot lights: (1, 1/(2 pi (1 -
    /// cos theta_e))) inside the cone, (1, 0) outside (`n` is ignored for both). Bidirectional
    /// estimators need them for the paths that other strategies found (the reverse pdfs of
    /// vertex connection and merging, Georgiev et al. 2012).
    #[inline]
    pub fn pdf_emission(&self, n: Vec3, w: Vec3) -> (f32, f32) {
        match self {
            Light::Triangle(light) => (1.0 / light.area, area::pdf_emission_dir(n, w)),
            Light::Sphere(light) => (1.0 / light.sphere.area(), area::pdf_emission_dir(n, w)),
            Light::Point(_) => (1.0, point::PDF_EMISSION_DIR),
            Light::Spot(light) => (1.0, light.pdf_emission_dir(w)),
        }
    }

    /// The ray that leaves an emission sample.
    pub(crate) fn emission_ray(s: &EmissionSample) -> Ray {
        if s.n == Vec3::ZERO {
            Ray::new(s.ray_origin, s.dir)
        } else {
            Ray::spawn(s.ray_origin, s.n, s.dir)
        }
    }
}
