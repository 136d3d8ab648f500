//! The eye pass (assignment parts 6.2 and 6.4): camera paths through specular chains to a
//! diffuse point, where the photon map gives the reflected radiance.

use crate::bsdf::{Bsdf, Phong};
use crate::geometry::Hit;
use crate::integrator::direct::estimate_direct;
use crate::integrator::shading::ShadingFrame;
use crate::integrator::{CameraPath, DirectMode, LightStrategy, RenderSettings};
use crate::photon::{HashGrid, Kernel};
use crate::sampling::Rng;
use crate::scene::Scene;
use glam::{Vec2, Vec3};

/// Random streams of eye paths are kept apart from the light paths' by this salt.
pub const EYE_STREAM: u64 = 0x6579_6570_6174_6821;

/// What the eye pass needs from the current iteration.
pub struct GatherContext<'a> {
    pub grid: &'a HashGrid,
    pub kernel: Kernel,
    pub radius: f32,
    /// 1 / (number of light paths of this iteration).
    pub inv_paths: f32,
}

/// Rays traced by one worker.
#[derive(Clone, Copy, Debug, Default)]
pub struct EyeCounters {
    pub rays: u64,
    pub shadow_rays: u64,
}

/// The photon density estimate of the radiance reflected toward `wo` at `hit` by a diffuse
/// lobe of albedo `albedo` (a diffuse surface, or the diffuse lobe of a phong surface):
///
/// L(x, wo) = sum over photons p within r of f k(d_p^2) Phi_p / N,   f = albedo / pi,
/// k(d^2) = 2 (1 - d^2 / r^2) / (pi r^2)  (Epanechnikov, normalised over the disc),
///
/// where Phi_p is the flux of the photon's light path and N the number of light paths.
/// f does not depend on the directions, so it leaves the sum. Photons that arrived from the
/// other side of the surface (wi_p . n <= 0, n the geometric normal turned toward the viewer)
/// are rejected: they lit the back of a thin wall. The flux per unit geometric area is taken
/// as the irradiance, which is exact on flat-shaded surfaces (ns = ng).
#[inline]
pub fn density_estimate(ctx: &GatherContext<'_>, hit: &Hit, wo: Vec3, albedo: Vec3) -> Vec3 {
    let n_view = if wo.dot(hit.ng) >= 0.0 {
        hit.ng
    } else {
        -hit.ng
    };
    let sum = ctx.grid.kernel_flux(hit.p, ctx.radius, n_view, &ctx.kernel);
    sum * (albedo * (std::f32::consts::FRAC_1_PI * ctx.inv_paths))
}

/// The eye path through pixel `pixel` of iteration `iteration`; returns its radiance estimate.
///
/// - Mirror and glass: the path follows the sampled delta lobe (radiance mode).
/// - Diffuse: the density estimate of the photon map, and with `--direct sampled` one light
///   sample (no MIS: this vertex never samples its BSDF, so light sampling is the only
///   strategy for direct light); the path ends.
/// - Phong (6.4): the glossy lobe is never density-estimated. Its direct light comes from one
///   light sample, and the path continues by sampling the glossy lobe alone; emission that
///   this bounce finds is weighted by MIS (power heuristic) against the light sample, so
///   nothing is counted twice. The diffuse lobe, if any, is estimated like a diffuse surface
///   (photons, plus a light sample with `--direct sampled`).
/// - Emission seen directly or through specular chains counts fully.
/// - Russian roulette on the throughput after `rr_depth` bounces.
#[allow(clippy::too_many_arguments)]
pub fn trace_eye_path(
    scene: &Scene,
    settings: &RenderSettings,
    ctx: &GatherContext<'_>,
    iteration: u64,
    pixel: usize,
    width: usize,
    counters: &mut EyeCounters,
) -> Vec3 {
    let mut rng = Rng::new(settings.seed ^ EYE_STREAM, iteration, pixel as u64);
    let film = Vec2::new((pixel % width) as f32, (pixel / width) as f32) + rng.uniform2();
    let mut ray = scene.camera.generate_ray(film);
    let sampled_direct = settings.direct == DirectMode::Sampled;
    let mut l = Vec3::ZERO;
    let mut path = CameraPath::new(ray.origin);
    for depth in 0..=settings.max_depth {
        counters.rays += 1;
        let Some(hit) = scene.intersect(&ray) else {
            break;
        };
        let material = scene.material(&hit);
        let wo = -ray.dir;
        l += path.throughput * path.emission(scene, &hit, wo, LightStrategy::Mis);
        if depth == settings.max_depth {
            break;
        }
        let sf = ShadingFrame::new(&hit, wo);
        // The lobe the path continues with, if any.
        let continue_with = match &material.bsdf {
            Bsdf::Diffuse(d) => {
                l += path.throughput * density_estimate(ctx, &hit, wo, d.albedo);
                if sampled_direct {
                    let (ld, traced) =
                        estimate_direct(scene, &hit, &sf, wo, &material.bsdf, &mut rng, false);
                    counters.shadow_rays += traced as u64;
                    l += path.throughput * ld;
                }
                break;
            }
            Bsdf::Phong(p) => {
                if p.diffuse.max_element() > 0.0 {
                    let diffuse = Bsdf::diffuse(p.diffuse);
                    l += path.throughput * density_estimate(ctx, &hit, wo, p.diffuse);
                    if sampled_direct {
                        let (ld, traced) =
                            estimate_direct(scene, &hit, &sf, wo, &diffuse, &mut rng, false);
                        counters.shadow_rays += traced as u64;
                        l += path.throughput * ld;
                    }
                }
                if p.specular.max_element() <= 0.0 {
                    break;
                }
                let glossy = Bsdf::Phong(Phong {
                    diffuse: Vec3::ZERO,
                    ..*p
                });
                let (ld, traced) = estimate_direct(scene, &hit, &sf, wo, &glossy, &mut rng, true);
                counters.shadow_rays += traced as u64;
                l += path.throughput * ld;
                glossy
            }
            delta @ (Bsdf::Mirror(_) | Bsdf::Glass(_)) => *delta,
        };
        let Some(next) = path.scatter(
            &continue_with,
            &sf,
            &hit,
            wo,
            &mut rng,
            depth,
            settings.rr_depth,
        ) else {
            break;
        };
        ray = next;
    }
    l
}
