//! Lights: every emissive triangle and sphere is an area light; point lights have no geometry.
//!
//! Area lights emit radiance `le` from one side, the side their geometric normal points to,
//! with a cosine (Lambertian) distribution. Their power is Phi = pi * A * Le; a point light of
//! intensity I (W/sr) has Phi = 4 pi I.

use crate::geometry::{Ray, Sphere, Triangle};
use crate::sampling::{cosine_hemisphere, uniform_sphere, uniform_triangle, Frame};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// The largest power per channel (W) a light may emit. f32 holds up to 3.4e38, but a photon's
/// flux is divided by the light's selection probability and the density estimate multiplies
/// it by 1/(pi r^2) (1e6 and more for small radii) and sums many photons; 1e20 W leaves those
/// steps about 18 orders of magnitude of headroom, and no physically scaled scene comes near
/// it (a 100 W bulb is 1e2 W; the sun, 3.8e26 W, must be modelled by its irradiance).
pub const MAX_LIGHT_POWER: f32 = 1e20;

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

/// A point light without geometry: radiant intensity `intensity` (W/sr) in every direction.
#[derive(Clone, Copy, Debug)]
pub struct PointLight {
    pub position: Vec3,
    pub intensity: Vec3,
}

/// One light of the scene.
#[derive(Clone, Copy, Debug)]
pub enum Light {
    /// An emissive triangle (global primitive id `prim`).
    Triangle {
        tri: Triangle,
        normal: Vec3,
        area: f32,
        le: Vec3,
        prim: u32,
    },
    /// An emissive sphere; it emits inward when `sphere.inward` is set.
    Sphere { sphere: Sphere, le: Vec3, prim: u32 },
    /// A point light (a delta light: found only by light sampling).
    Point(PointLight),
}

/// A light sample for next-event estimation, seen from a shading point.
#[derive(Clone, Copy, Debug)]
pub struct DirectSample {
    /// Point on the light, and its geometric normal (zero for point lights).
    pub p: Vec3,
    pub n: Vec3,
    /// Unit direction from the shading point toward the light, and the distance.
    pub wi: Vec3,
    pub dist: f32,
    /// Radiance arriving along -wi (for point lights: intensity / dist^2).
    pub li: Vec3,
    /// Solid-angle pdf of this sample, not counting the choice of the light (1 for delta lights).
    pub pdf: f32,
    pub is_delta: bool,
}

/// A sampled emission: the start of a light path.
#[derive(Clone, Copy, Debug)]
pub struct EmissionSample {
    pub ray_origin: Vec3,
    /// Geometric normal at the origin (zero for point lights), for offsetting the ray.
    pub n: Vec3,
    pub dir: Vec3,
    /// Flux weight Le * cos / (p_area * p_dir), not counting the choice of the light.
    pub flux: Vec3,
    /// Area pdf of the origin (1 for point lights) and solid-angle pdf of the direction.
    pub pdf_pos: f32,
    pub pdf_dir: f32,
}

impl Light {
    /// An area light on an emissive triangle; `None` for a degenerate one.
    pub fn triangle(tri: Triangle, le: Vec3, prim: u32) -> Option<Self> {
        let c = (tri.v[1] - tri.v[0]).cross(tri.v[2] - tri.v[0]);
        let area = 0.5 * c.length();
        (area > 0.0 && area.is_finite()).then(|| Light::Triangle {
            tri,
            normal: c.normalize(),
            area,
            le,
            prim,
        })
    }

    /// Total emitted power per channel: pi * A * Le for an area light, 4 pi I for a point light.
    pub fn power(&self) -> Vec3 {
        match self {
            Light::Triangle { area, le, .. } => PI * *area * *le,
            Light::Sphere { sphere, le, .. } => PI * sphere.area() * *le,
            Light::Point(p) => 4.0 * PI * p.intensity,
        }
    }

    /// `Ok` if every channel of [`Light::power`] is finite and at most [`MAX_LIGHT_POWER`];
    /// else the power (computed again in f64, so an overflowing one is reported by value).
    pub fn check_power(&self) -> Result<(), f64> {
        let power = self.power();
        if power.is_finite() && power.max_element() <= MAX_LIGHT_POWER {
            return Ok(());
        }
        let pi = std::f64::consts::PI;
        let (scale, value) = match self {
            Light::Triangle { area, le, .. } => (pi * *area as f64, le.max_element()),
            Light::Sphere { sphere, le, .. } => (pi * sphere.area() as f64, le.max_element()),
            Light::Point(p) => (4.0 * pi, p.intensity.max_element()),
        };
        Err(scale * value as f64)
    }

    /// Surface area of an area light (0 for a point light).
    #[inline]
    fn area(&self) -> f32 {
        match self {
            Light::Triangle { area, .. } => *area,
            Light::Sphere { sphere, .. } => sphere.area(),
            Light::Point(_) => 0.0,
        }
    }

    /// True for lights that only light sampling can find.
    pub fn is_delta(&self) -> bool {
        matches!(self, Light::Point(_))
    }

    /// A uniformly distributed point on the light's surface and its emitting normal; pdf = 1/area.
    #[inline]
    fn sample_area(&self, u: Vec2) -> (Vec3, Vec3, f32) {
        match self {
            Light::Triangle {
                tri, normal, area, ..
            } => {
                let b = uniform_triangle(u);
                let p = tri.v[0] * (1.0 - b.x - b.y) + tri.v[1] * b.x + tri.v[2] * b.y;
                (p, *normal, 1.0 / *area)
            }
            Light::Sphere { sphere, .. } => {
                let d = uniform_sphere(u);
                let n = if sphere.inward { -d } else { d };
                (
                    sphere.center + d * sphere.radius.abs(),
                    n,
                    1.0 / sphere.area(),
                )
            }
            Light::Point(p) => (p.position, Vec3::ZERO, 1.0),
        }
    }

    /// Samples a point on the light as seen from `p` for next-event estimation.
    /// Area lights: uniform by area, converted to solid angle: pdf = d^2 / (A cos_l).
    /// `None` if the sampled point faces away (one-sided emission) or is degenerate.
    #[inline]
    pub fn sample_direct(&self, p: Vec3, u: Vec2) -> Option<DirectSample> {
        let (q, n, _) = self.sample_area(u);
        let d = q - p;
        let dist2 = d.length_squared();
        if !dist2.is_finite() || dist2 <= 0.0 {
            return None;
        }
        let dist = dist2.sqrt();
        let wi = d / dist;
        match self {
            Light::Point(light) => Some(DirectSample {
                p: q,
                n,
                wi,
                dist,
                li: light.intensity / dist2,
                pdf: 1.0,
                is_delta: true,
            }),
            Light::Triangle { le, .. } | Light::Sphere { le, .. } => {
                let pdf = solid_angle_pdf(self.area(), dist2, -wi.dot(n));
                (pdf > 0.0).then_some(DirectSample {
                    p: q,
                    n,
                    wi,
                    dist,
                    li: *le,
                    pdf,
                    is_delta: false,
                })
            }
        }
    }

    /// The largest power per channel (W) a light may emit. f32 holds up to 3.4e38, but a photon's
    /// flux is divided by the light's selection probability and the density estimate multiplies
    /// it by 1/(pi r^2) (1e6 and more for small radii) and sums many photons; 1e20 W leaves those
    /// steps about 18 orders of magnitude of headroom, and no physically scaled scene comes near
    /// it (a 100 W bulb is 1e2 W; the sun, 3.8e26 W, must be modelled by its irradiance).
    pub const MAX_LIGHT_POWER: f32 = 1e20;

    /// The solid-angle pdf with which [`Light::sample_direct`] from `p` would produce the point
    /// `q` with emitting normal `n` (not counting the choice of the light); 0 for point lights.
    #[inline]
    pub fn pdf_direct(&self, p: Vec3, q: Vec3, n: Vec3) -> f32 {
        if self.is_delta() {
            return 0.0;
        }
        let d = q - p;
        let dist2 = d.length_squared();
        if dist2.is_nan() || dist2 <= 0.0 {
            return 0.0;
        }
        // The same expressions as in `sample_direct`, so both give the same value.
        let wi = d / dist2.sqrt();
        solid_angle_pdf(self.area(), dist2, -wi.dot(n))
    }

    /// Radiance emitted from a point with geometric normal `n` toward direction `w` (unit).
    #[inline]
    pub fn le(&self, n: Vec3, w: Vec3) -> Vec3 {
        match self {
            Light::Triangle { le, .. } | Light::Sphere { le, .. } if n.dot(w) > 0.0 => *le,
            _ => Vec3::ZERO,
        }
    }

    /// Samples the start of a light path: a point uniform by area (pdf 1/A) and a
    /// cosine-weighted direction (pdf cos/pi) about the emitting normal, so the flux weight
    /// Le cos / (p_area p_dir) = pi A Le is the same for every sample. Point lights: a uniform
    /// direction (pdf 1/(4 pi)), weight 4 pi I.
    #[inline]
    pub fn sample_emission(&self, u_pos: Vec2, u_dir: Vec2) -> EmissionSample {
        let (p, n, pdf_pos) = self.sample_area(u_pos);
        match self {
            Light::Point(light) => {
                let dir = uniform_sphere(u_dir);
                let pdf_dir = 1.0 / (4.0 * PI);
                EmissionSample {
                    ray_origin: p,
                    n,
                    dir,
                    flux: light.intensity / pdf_dir,
                    pdf_pos,
                    pdf_dir,
                }
            }
            Light::Triangle { le, .. } | Light::Sphere { le, .. } => {
                let local = cosine_hemisphere(u_dir);
                let dir = Frame::new(n).to_world(local);
                let cos = local.z;
                let pdf_dir = cos / PI;
                // Le cos / (p_area p_dir) = Le cos / ((1/A) (cos/pi)) = pi A Le, for cos > 0.
                let flux = if pdf_dir > 0.0 {
                    *le * (cos / (pdf_pos * pdf_dir))
                } else {
                    Vec3::ZERO
                };
                EmissionSample {
                    ray_origin: p,
                    n,
                    dir,
                    flux,
                    pdf_pos,
                    pdf_dir,
                }
            }
        }
    }

    /// The ray that leaves an emission sample.
    pub fn emission_ray(s: &EmissionSample) -> Ray {
        if s.n == Vec3::ZERO {
            Ray::new(s.ray_origin, s.dir)
        } else {
            Ray::spawn(s.ray_origin, s.n, s.dir)
        }
    }
}
