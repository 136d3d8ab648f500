//! Lights: every emissive triangle and sphere is an area light; point, spot and directional
//! lights have no geometry.
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
//! - A directional light ([`DirectionalLight`], a delta in direction) is found by
//!   [`Light::sample_direct`] alone too (pdf 1, radiance a delta of weight E, the
//!   irradiance); its emission leaves a disk covering the scene's bounding sphere along its
//!   one direction: [`Light::pdf_emission`] is (1/(pi R^2), 1) and Phi = E pi R^2. It needs
//!   the scene's bounds: [`Light::preprocess`], once, when the scene is built.
//! - An environment light ([`EnvironmentLight`], [`LightKind::Infinite`]) radiates L(w) from
//!   every direction at infinity: [`Light::le_infinite`] is what a ray escaping the scene
//!   along w sees and [`Light::pdf_infinite`] the density with which
//!   [`Light::sample_direct`] picks that direction; its emission leaves a disk over the
//!   scene's bounding sphere as the directional light's does, in a sampled direction:
//!   [`Light::pdf_emission`] is (1/(pi R^2), p(-w)) and Phi = pi R^2 (integral of L over the
//!   sphere). A scene has at most one.
//! - [`Light::pdf_direct`] is the solid-angle density with which [`Light::sample_direct`]
//!   produces a point, computed by the same expressions, so the two agree exactly.
//! - [`Light::sample_emission`] starts a light path; the mean of its `flux` is
//!   [`Light::power`].
//!
//! Every match on [`Light`] lists all variants: a new model does not compile until each
//! operation handles it. To add one, see ARCHITECTURE.md ("To add a light").

mod area;
mod directional;
mod environment;
mod envmap;
mod equal_area;
mod point;
mod sphere;
mod spot;
mod triangle;

pub use directional::DirectionalLight;
pub use environment::{EnvironmentLight, EnvironmentMap};
pub use envmap::{direction_to_uv, uv_to_direction, LatLongMap, MapError};
pub use equal_area::{sphere_to_square, square_to_sphere, EqualAreaMap};
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

/// The largest emitted radiance per channel (W/(m^2 sr)) a light may have, and likewise the
/// largest point or spot light intensity (W/sr) and directional irradiance (W/m^2): 2^40
/// (1.1e12), the film's range with room for the estimators' gain.
///
/// The film adds each sample exactly up to [`crate::film::MAX_ESTIMATE`] = 2^56 (7.2e16) and
/// drops larger ones. A camera path that sees an emitter adds its radiance L itself (times an
/// MIS weight and a throughput of at most 1 for energy-conserving surfaces), so L must be
/// below 2^56; a sample can exceed L by the estimator's gain: a density estimate weighs a
/// photon by 1 / (N pi r^2) (light area over N times the merge disc area, 10 to 1000 at usual
/// settings), a 1/pdf can exceed 1 where sampling is poor, and a point light's I/d^2 grows
/// near it. 2^40 leaves a gain of 2^16 = 65536 before the film's bound, and is still 5e4
/// times the sun's radiance (2e7 W/(m^2 sr)): no physically scaled scene comes near it.
pub const MAX_EMISSION: f32 = (1u64 << 40) as f32;

/// One light of the scene.
#[derive(Clone, Debug)]
pub enum Light {
    /// An emissive triangle.
    Triangle(TriangleLight),
    /// An emissive sphere; it emits inward when `sphere.inward` is set.
    Sphere(SphereLight),
    /// A point light (a delta light: found only by light sampling).
    Point(PointLight),
    /// A spot light (a delta light emitting into a cone).
    Spot(SpotLight),
    /// A directional light, the sun (a delta in direction, from infinitely far).
    Directional(DirectionalLight),
    /// An environment light, radiance from every direction at infinity (a constant colour
    /// or a lat-long image).
    Environment(EnvironmentLight),
}

/// What sort of light a model is, as pbrt-v4's `LightType` says it: what finds it and what
/// it needs. Checks, warnings and messages outside the light module ask this, not the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightKind {
    /// Emits from one point (point and spot lights): only light sampling finds it, a camera
    /// path never hits it, and its light through a specular surface is beyond a path tracer.
    DeltaPosition,
    /// Emits along one direction from infinitely far (a directional light): only light
    /// sampling finds it, and its light through a specular surface is beyond a path tracer.
    DeltaDirection,
    /// Emits from the surface of scene geometry (emissive triangles and spheres).
    Area,
    /// Emits from infinitely far in every direction (an environment light): camera paths
    /// that leave the scene find it, and light sampling does.
    Infinite,
}

impl LightKind {
    /// True for the kinds at infinity (directional and environment lights): their light
    /// paths reach the first vertex with a density that does not fall off with distance.
    #[inline]
    pub fn is_infinite(self) -> bool {
        match self {
            LightKind::DeltaDirection | LightKind::Infinite => true,
            LightKind::DeltaPosition | LightKind::Area => false,
        }
    }

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

    /// A directional light travelling along `direction` with irradiance `irradiance`
    /// (W/m^2); `None` for a zero or non-finite direction (see [`DirectionalLight::new`]).
    pub fn directional(direction: Vec3, irradiance: Vec3) -> Option<Self> {
        DirectionalLight::new(direction, irradiance).map(Light::Directional)
    }

    /// The model's kind. One exhaustive match: a new model says here what it is.
    #[inline]
    pub fn kind(&self) -> LightKind {
        match self {
            Light::Triangle(_) | Light::Sphere(_) => LightKind::Area,
            Light::Point(_) | Light::Spot(_) => LightKind::DeltaPosition,
            Light::Directional(_) => LightKind::DeltaDirection,
            Light::Environment(_) => LightKind::Infinite,
        }
    }

    /// Total emitted power per channel: pi * A * Le for an area light, 4 pi I for a point light,
    /// the integral of the falloff for a spot light, E pi R^2 for a directional light (after
    /// [`Light::preprocess`]).
    pub fn power(&self) -> Vec3 {
        match self {
            Light::Triangle(light) => light.power(),
            Light::Sphere(light) => light.power(),
            Light::Point(light) => light.power(),
            Light::Spot(light) => light.power(),
            Light::Directional(light) => light.power(),
            Light::Environment(light) => light.power(),
        }
    }

    /// The build-time step, once the scene's geometry is known: a directional light takes
    /// the scene's bounds (min, max) to place its disk of origins (see `directional.rs`);
    /// the other models need nothing. [`crate::SceneBuilder::build`] calls it.
    pub fn preprocess(&mut self, bounds: (Vec3, Vec3)) {
        match self {
            Light::Directional(light) => light.preprocess(bounds),
            Light::Environment(light) => light.preprocess(bounds),
            Light::Triangle(_) | Light::Sphere(_) | Light::Point(_) | Light::Spot(_) => {}
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
            Light::Directional(light) => light.translate(offset),
            Light::Environment(light) => light.translate(offset),
        }
    }

    /// The light as part of a scene scaled by `scale` > 0 about the origin and then moved by
    /// `offset` (every point p to p scale + offset), lighting the scaled scene as it lit the
    /// original: an area light keeps its radiance (its power grows by scale^2 with its area),
    /// a delta light's intensity grows by scale^2 so its irradiance at the scaled distances is
    /// kept, a directional light keeps its irradiance (its disk of origins follows the scene).
    /// Directions and angles do not change.
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
            Light::Directional(light) => light.transform(scale, offset),
            Light::Environment(light) => light.transform(scale, offset),
        }
    }

    /// The model's name for messages: `emissive triangle`, `point light`...
    pub fn name(&self) -> &'static str {
        match self {
            Light::Triangle(_) => "emissive triangle",
            Light::Sphere(_) => "emissive sphere",
            Light::Point(_) => "point light",
            Light::Spot(_) => "spot light",
            Light::Directional(_) => "directional light",
            Light::Environment(_) => "environment light",
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
            Light::Directional(light) => format!("irradiance {}", light.irradiance),
            Light::Environment(light) => match light.parts() {
                (EnvironmentMap::Constant(c), scale, _) => format!("radiance {c}, scale {scale}"),
                (EnvironmentMap::Image(m), scale, _) => {
                    let (w, h) = m.size();
                    format!("{w}x{h} radiance map, scale {scale}")
                }
                (EnvironmentMap::EqualArea(m), scale, _) => {
                    let n = m.size();
                    format!("{n}x{n} equal-area radiance map, scale {scale}")
                }
            },
        }
    }

    /// The global primitive id of an area light's surface; `None` for lights without one.
    pub fn prim(&self) -> Option<u32> {
        match self {
            Light::Triangle(light) => Some(light.prim),
            Light::Sphere(light) => Some(light.prim),
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) | Light::Environment(_) => {
                None
            }
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
            Light::Directional(light) => (
                std::f64::consts::PI * (light.radius() as f64).powi(2),
                light.irradiance.max_element(),
            ),
            Light::Environment(light) => (
                std::f64::consts::PI * (light.radius() as f64).powi(2),
                light.radiance_integral().max_element(),
            ),
        };
        Err(scale * value as f64)
    }

    /// `Ok` if every channel of what the light emits (an area light's radiance, a point or
    /// spot light's intensity, a directional light's irradiance, an environment's radiance
    /// times its scale, its brightest texel for a map) is at most [`MAX_EMISSION`]; else the
    /// field that sets it, as the scene format names it, and its largest channel.
    pub fn check_emission(&self) -> Result<(), (&'static str, f64)> {
        let (field, value) = match self {
            Light::Triangle(light) => ("emission", light.le.max_element()),
            Light::Sphere(light) => ("emission", light.le.max_element()),
            Light::Point(light) => ("intensity", light.intensity.max_element()),
            Light::Spot(light) => ("intensity", light.intensity.max_element()),
            Light::Directional(light) => ("irradiance", light.irradiance.max_element()),
            Light::Environment(light) => {
                let (map, scale, _) = light.parts();
                let brightest = (map.texels().iter()).fold(0.0f32, |a, t| a.max(t.max_element()));
                (
                    "radiance (`color` or `file` times `scale`)",
                    brightest * scale,
                )
            }
        };
        let value = value as f64;
        if value <= MAX_EMISSION as f64 {
            Ok(())
        } else {
            Err((field, value))
        }
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
            Light::Directional(light) => light.sample_direct(p),
            Light::Environment(light) => light.sample_direct(p, u),
        }
    }

    /// The solid-angle pdf with which [`Light::sample_direct`] from `p` would produce the point
    /// `q` with emitting normal `n` (not counting the choice of the light); 0 for delta lights.
    #[inline]
    pub fn pdf_direct(&self, p: Vec3, q: Vec3, n: Vec3) -> f32 {
        match self {
            Light::Triangle(light) => area::pdf_direct(light.area, p, q, n),
            Light::Sphere(light) => area::pdf_direct(light.sphere.area(), p, q, n),
            Light::Environment(light) => light.pdf_dir((q - p).normalize_or_zero()),
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) => 0.0,
        }
    }

    /// What a ray leaving the scene along unit direction `w` sees of a light at infinity:
    /// L(w) for an environment light, zero for every other light (a directional light is a
    /// delta no ray hits).
    #[inline]
    pub fn le_infinite(&self, w: Vec3) -> Vec3 {
        match self {
            Light::Environment(light) => light.radiance(w),
            Light::Triangle(_)
            | Light::Sphere(_)
            | Light::Point(_)
            | Light::Spot(_)
            | Light::Directional(_) => Vec3::ZERO,
        }
    }

    /// The solid-angle density with which [`Light::sample_direct`] picks direction `w` (unit,
    /// toward the light) of a light at infinity, not counting the choice of the light: the
    /// MIS weight of a camera path that leaves the scene along `w`. Zero for the others.
    #[inline]
    pub fn pdf_infinite(&self, w: Vec3) -> f32 {
        match self {
            Light::Environment(light) => light.pdf_dir(w),
            Light::Triangle(_)
            | Light::Sphere(_)
            | Light::Point(_)
            | Light::Spot(_)
            | Light::Directional(_) => 0.0,
        }
    }

    /// Radiance emitted from a point with geometric normal `n` toward direction `w` (unit):
    /// one-sided for area lights, zero for delta lights; an environment light sends L(-w)
    /// toward w from infinitely far (`n` ignored).
    #[inline]
    pub fn le(&self, n: Vec3, w: Vec3) -> Vec3 {
        match self {
            Light::Triangle(light) => area::le(light.le, n, w),
            Light::Sphere(light) => area::le(light.le, n, w),
            Light::Environment(light) => light.radiance(-w),
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) => Vec3::ZERO,
        }
    }

    /// Samples the start of a light path: for area lights a point uniform by area (pdf 1/A)
    /// and a cosine-weighted direction (pdf cos/pi) about the emitting normal, so the flux
    /// weight Le cos / (p_area p_dir) = pi A Le is the same for every sample. Point lights: a
    /// uniform direction (pdf 1/(4 pi)), weight 4 pi I. Spot lights: a direction uniform in
    /// the cone, weighted by the falloff (`spot.rs`). Directional lights: a point uniform on
    /// the disk covering the scene (pdf 1/(pi R^2)) and the light's direction, weight E pi R^2.
    /// Environment lights: a direction by the map's distribution, then a point on the disk
    /// perpendicular to it, weight L pi R^2 / p(w) (`environment.rs`).
    /// Always inlined (once per light path), with the emitter's sampling inside it
    /// (docs/performance.md, "Inlining").
    #[inline(always)]
    pub fn sample_emission(&self, u_pos: Vec2, u_dir: Vec2) -> EmissionSample {
        match self {
            Light::Triangle(light) => light.emitter(u_pos).sample_emission(u_dir),
            Light::Sphere(light) => light.emitter(u_pos).sample_emission(u_dir),
            Light::Point(light) => light.sample_emission(u_dir),
            Light::Spot(light) => light.sample_emission(u_dir),
            Light::Directional(light) => light.sample_emission(u_pos),
            Light::Environment(light) => light.sample_emission(u_pos, u_dir),
        }
    }

    /// The densities with which [`Light::sample_emission`] produces a light path leaving
    /// the point with emitting normal `n` in unit direction `w`: (area pdf of the point, solid-
    /// angle pdf of the direction), not counting the choice of the light. Area lights:
    /// (1/A, max(0, n . w)/pi); point lights: (1, 1/(4 pi)); spot lights: (1, 1/(2 pi (1 -
    /// cos theta_e))) inside the cone, (1, 0) outside (`n` is ignored for both); directional
    /// lights: (1/(pi R^2), 1), the disk's area density and the delta direction's discrete
    /// weight (`w` is taken to be the light's direction, the only one it emits). Bidirectional
    /// estimators need them for the paths that other strategies found (the reverse pdfs of
    /// vertex connection and merging, Georgiev et al. 2012).
    #[inline]
    pub fn pdf_emission(&self, n: Vec3, w: Vec3) -> (f32, f32) {
        match self {
            Light::Triangle(light) => (1.0 / light.area, area::pdf_emission_dir(n, w)),
            Light::Sphere(light) => (1.0 / light.sphere.area(), area::pdf_emission_dir(n, w)),
            Light::Point(_) => (1.0, point::PDF_EMISSION_DIR),
            Light::Spot(light) => (1.0, light.pdf_emission_dir(w)),
            Light::Directional(light) => (light.pdf_pos(), 1.0),
            Light::Environment(light) => (light.pdf_pos(), light.pdf_dir(-w)),
        }
    }

    /// The area density, at a point that next-event estimation connected to this light by
    /// `ls` (with |cos| `cos` between the point's normal and `ls.wi`), with which the light's
    /// emission reaches that point, relative to the density with which next-event estimation
    /// chose the light's point (SmallVCM's emissionPdfW cosToLight / (directPdfW cosAtLight);
    /// Georgiev 2012, TR eqs. 44-45). Lights at a point (area, point, spot lights): the
    /// emission direction's pdf toward the point, turned into area measure there, p_W(-wi)
    /// |cos| / d^2 (for area lights the origin's 1/A cancels against next-event's). A
    /// directional light: next-event's direction has probability 1 and its parallel rays
    /// leave the disk with area density 1/(pi R^2), projected onto the point's surface:
    /// |cos| / (pi R^2), with no distance (the light is at infinity).
    #[inline]
    pub fn pdf_emission_at(&self, ls: &DirectSample, cos: f32) -> f32 {
        match self {
            Light::Directional(light) => light.pdf_pos() * cos,
            // SmallVCM's BackgroundLight: emission pdf p(wi) / (pi R^2) over next-event's
            // p(wi), the cosine at the light 1, no distance: |cos| / (pi R^2).
            Light::Environment(light) => light.pdf_pos() * cos,
            Light::Triangle(_) | Light::Sphere(_) | Light::Point(_) | Light::Spot(_) => {
                let (_, pdf_dir) = self.pdf_emission(ls.n, -ls.wi);
                pdf_dir * cos / (ls.dist * ls.dist)
            }
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
