//! The camera pass of SPPM: one jittered camera path per pixel, through specular and glossy
//! bounces, to the visible point where the photons of the iteration will be gathered.

use crate::bsdf::{Bsdf, Phong};
use crate::integrator::direct::estimate_direct;
use crate::integrator::shading::ShadingFrame;
use crate::integrator::{CameraPath, DirectMode, LightStrategy, RenderSettings};
use crate::sampling::Rng;
use crate::scene::Scene;
use glam::{Vec2, Vec3};

/// Random streams of SPPM camera paths are kept apart from every other stream by this salt.
pub const SPPM_EYE_STREAM: u64 = 0x7370_706d_5f65_7965;

/// Where a pixel's camera path stopped in this iteration, and what a photon arriving there
/// is worth to the pixel.
#[derive(Clone, Copy, Debug, Default)]
pub struct VisiblePoint {
    /// Position (world space, camera-relative like the scene).
    pub p: Vec3,
    /// The geometric normal on the camera's side: photons from the other side are ignored.
    pub n_view: Vec3,
    /// beta f / p_lobe: the camera path's throughput (an importance, radiance mode) times the
    /// diffuse lobe's f = albedo / pi, over the probability of having chosen that lobe. A
    /// photon of flux Phi_p inside the disc adds `weight * Phi_p` to the pixel's Phi.
    pub weight: Vec3,
    /// The pixel's squared gather radius R_i^2 this iteration; 0 with no visible point.
    pub r2: f32,
    /// False when the path escaped, was absorbed or ended on a purely specular chain.
    pub found: bool,
}

impl VisiblePoint {
    /// The disc the grid indexes, if any.
    #[inline]
    pub fn disc(&self) -> Option<(Vec3, f32)> {
        self.found.then_some((self.p, self.r2))
    }
}

/// Rays traced by one worker of the camera pass.
#[derive(Clone, Copy, Debug, Default)]
pub struct CameraCounters {
    pub rays: u64,
    pub shadow_rays: u64,
}

/// Probability of stopping at the diffuse lobe of a phong surface (continuing with the glossy
/// lobe otherwise): in proportion to the lobes' largest albedo channels.
#[inline]
fn diffuse_lobe_probability(p: &Phong) -> f32 {
    let d = p.diffuse.max_element().max(0.0);
    let s = p.specular.max_element().max(0.0);
    if d + s > 0.0 {
        d / (d + s)
    } else {
        0.0
    }
}

/// Traces the camera path of `pixel` in `iteration`. Returns the radiance it found on the way
/// (emission, sampled direct light) and its visible point, whose `r2` the caller sets.
///
/// - Mirror and glass: the path follows the sampled delta lobe (radiance mode).
/// - Diffuse: the visible point, with weight beta albedo / pi; with `--direct sampled` one
///   light sample there (photons then start at their second bounce). The path ends.
/// - Phong: one lobe is chosen, the diffuse one with probability q (see
///   [`diffuse_lobe_probability`]), and the throughput divided by the choice's probability.
///   Diffuse: as above. Glossy: direct light by one light sample weighted by MIS against the
///   continuation, then the path continues by sampling the glossy lobe alone (the glossy
///   lobe is never density-estimated, as in the `ppm` eye pass, assignment part 6.4).
/// - Emission seen directly or through delta chains counts fully, after a glossy bounce with
///   its MIS weight.
/// - Russian roulette on the throughput after `rr_depth` bounces.
pub fn trace_camera_path(
    scene: &Scene,
    settings: &RenderSettings,
    iteration: u64,
    pixel: usize,
    width: usize,
    counters: &mut CameraCounters,
) -> (Vec3, VisiblePoint) {
    let mut rng = Rng::new(settings.seed ^ SPPM_EYE_STREAM, iteration, pixel as u64);
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
        // The diffuse albedo to stop at (with the lobe choice's probability), or the lobe
        // to continue with.
        let (stop, continue_with) = match &material.bsdf {
            Bsdf::Diffuse(d) => (Some((d.albedo, 1.0)), None),
            Bsdf::Phong(p) => {
                let q = diffuse_lobe_probability(p);
                if q > 0.0 && rng.uniform() < q {
                    (Some((p.diffuse, q)), None)
                } else if q < 1.0 {
                    path.throughput /= 1.0 - q;
                    let glossy = Bsdf::Phong(Phong {
                        diffuse: Vec3::ZERO,
                        ..*p
                    });
                    let (ld, traced) =
                        estimate_direct(scene, &hit, &sf, wo, &glossy, &mut rng, true);
                    counters.shadow_rays += traced as u64;
                    l += path.throughput * ld;
                    (None, Some(glossy))
                } else {
                    (None, None)
                }
            }
            delta @ (Bsdf::Mirror(_) | Bsdf::Glass(_)) => (None, Some(*delta)),
        };
        if let Some((albedo, q)) = stop {
            let beta = path.throughput / q;
            if sampled_direct {
                let diffuse = Bsdf::diffuse(albedo);
                let (ld, traced) = estimate_direct(scene, &hit, &sf, wo, &diffuse, &mut rng, false);
                counters.shadow_rays += traced as u64;
                l += beta * ld;
            }
            let n_view = if wo.dot(hit.ng) >= 0.0 {
                hit.ng
            } else {
                -hit.ng
            };
            let vp = VisiblePoint {
                p: hit.p,
                n_view,
                weight: beta * albedo * std::f32::consts::FRAC_1_PI,
                r2: 0.0,
                found: true,
            };
            return (l, vp);
        }
        let Some(bsdf) = continue_with else {
            break;
        };
        let Some(next) = path.scatter(&bsdf, &sf, &hit, wo, &mut rng, depth, settings.rr_depth)
        else {
            break;
        };
        ray = next;
    }
    (l, VisiblePoint::default())
}
