//! Where a camera path starts, what it carries from vertex to vertex, and its BSDF-sampled
//! continuation.

use super::direct::emission_mis_weight;
use super::shading::ShadingFrame;
use super::LightStrategy;
use crate::bsdf::{Bsdf, Lobe, TransportMode};
use crate::geometry::{Hit, Ray};
use crate::sampling::{power_heuristic, Rng};
use crate::scene::Scene;
use glam::{Vec2, Vec3};

/// The start of pixel `pixel`'s camera path in `iteration` (pixels row-major, `width` to a
/// row): the path's random stream and its first ray.
///
/// The stream is keyed by (`seed`, `iteration`, `pixel`), never by thread, so the image is
/// the same at any thread count; each camera pass passes its own salted `seed`, which keeps
/// its stream apart from the others'. The ray goes through a film position drawn uniformly in
/// the pixel's square [x, x+1) x [y, y+1), pdf 1 per unit pixel area: the pixel estimates the
/// mean radiance over its area (a box filter), and the sample weight is 1. A thin lens then
/// draws the ray's lens point from the same stream ([`crate::camera::Camera::sample_ray`]);
/// the lens's importance over its density is 1 too (the lens module's docs).
/// Always inlined: it opens the per-pixel loop of every camera pass.
#[inline(always)]
pub fn start_pixel_path(
    scene: &Scene,
    seed: u64,
    iteration: u64,
    pixel: usize,
    width: usize,
) -> (Rng, Ray) {
    let mut rng = Rng::new(seed, iteration, pixel as u64);
    let film = Vec2::new((pixel % width) as f32, (pixel / width) as f32) + rng.uniform2();
    let ray = scene.camera.sample_ray(film, &mut rng);
    (rng, ray)
}

/// The throughput of a camera path and what MIS needs to know of its previous vertex.
#[derive(Clone, Copy, Debug)]
pub struct CameraPath {
    /// Product of f |cos| / pdf (and Russian-roulette survival) along the path.
    pub throughput: Vec3,
    /// True at the camera and after a delta bounce: emission found next counts fully.
    pub prev_specular: bool,
    /// Solid-angle pdf of the last BSDF sample, for the MIS weight of emission it finds.
    pub prev_pdf: f32,
    /// The last vertex.
    pub prev_p: Vec3,
}

impl CameraPath {
    /// A path leaving the camera at `origin`.
    pub fn new(origin: Vec3) -> Self {
        CameraPath {
            throughput: Vec3::ONE,
            prev_specular: true,
            prev_pdf: 0.0,
            prev_p: origin,
        }
    }

    /// The emitted radiance the path picks up at `hit` (seen along `wo`), before the
    /// throughput: emission is one-sided (toward the geometric normal) and counts fully at the
    /// camera and after a delta bounce; after a non-specular bounce it is weighted against
    /// light sampling by `strategy` (the power heuristic for MIS, 0 when only light sampling
    /// finds emitters, 1 when only BSDF sampling does).
    /// Always inlined into the walk, as `scatter` is (docs/performance.md, "Inlining").
    #[inline(always)]
    pub fn emission(&self, scene: &Scene, hit: &Hit, wo: Vec3, strategy: LightStrategy) -> Vec3 {
        let material = scene.material(hit);
        if !material.is_emissive() || wo.dot(hit.ng) <= 0.0 {
            return Vec3::ZERO;
        }
        let weight = if self.prev_specular {
            1.0
        } else {
            match strategy {
                LightStrategy::Mis => emission_mis_weight(scene, self.prev_p, self.prev_pdf, hit),
                LightStrategy::LightOnly => 0.0,
                LightStrategy::BsdfOnly => 1.0,
            }
        };
        material.emission * weight
    }

    /// The radiance the path picks up when it leaves the scene along `dir` (unit), before the
    /// throughput: the environment's L(dir) (zero without one), counted fully at the camera
    /// and after a delta bounce; after a non-specular bounce weighted as emission is, the
    /// power heuristic between the BSDF's pdf and the light's p_light p(dir) (Veach 1997,
    /// sec. 9.2; pbrt-v4's `PathIntegrator` on an escaped ray).
    #[inline(always)]
    pub fn escaped(&self, scene: &Scene, dir: Vec3, strategy: LightStrategy) -> Vec3 {
        let Some((light, p_light)) = scene.environment() else {
            return Vec3::ZERO;
        };
        let weight = if self.prev_specular {
            1.0
        } else {
            match strategy {
                LightStrategy::Mis => {
                    power_heuristic(self.prev_pdf, p_light * light.pdf_infinite(dir))
                }
                LightStrategy::LightOnly => 0.0,
                LightStrategy::BsdfOnly => 1.0,
            }
        };
        light.le_infinite(dir) * weight
    }

    /// Continues the path at `hit` by sampling `bsdf` (radiance mode): throughput *= f |cos| /
    /// pdf. Returns the next ray, or `None` when the path ends: no sample, a direction whose
    /// geometric side contradicts its lobe (it would leak through the surface), or Russian
    /// roulette after `rr_depth` bounces, which survives with probability min(1, max channel
    /// of the throughput) and divides the survivors by it.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub fn scatter(
        &mut self,
        bsdf: &Bsdf,
        sf: &ShadingFrame,
        hit: &Hit,
        wo: Vec3,
        rng: &mut Rng,
        depth: u32,
        rr_depth: u32,
    ) -> Option<Ray> {
        let (u_lobe, u) = (rng.uniform(), rng.uniform2());
        let s = bsdf.sample(sf.wo, u_lobe, u, TransportMode::Radiance)?;
        let wi = sf.frame.to_world(s.wi);
        if !sf.consistent(hit, wo, wi, s.wi) {
            return None;
        }
        self.throughput *= s.weight;
        self.prev_specular = s.lobe == Lobe::Specular;
        self.prev_pdf = s.pdf;
        self.prev_p = hit.p;
        if depth + 1 >= rr_depth {
            let survive = self.throughput.max_element().min(1.0);
            if survive.is_nan() || rng.uniform() >= survive {
                return None;
            }
            self.throughput /= survive;
        }
        Some(Ray::spawn(hit.p, hit.ng, wi))
    }
}
