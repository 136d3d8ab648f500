//! The camera pass of SPPM: one jittered camera path per pixel, through specular and glossy
//! bounces, to the visible point where the photons of the iteration will be gathered.

use crate::bsdf::Bsdf;
use crate::integrator::camera_path::start_pixel_path;
use crate::integrator::camera_walk::{walk, Next, RayCounters, WalkParams};
use crate::integrator::{gather_limit, DirectMode, LightStrategy, RenderSettings};
use crate::photon::GatherNormals;
use crate::scene::Scene;
use glam::Vec3;

/// Random streams of SPPM camera paths are kept apart from every other stream by this salt.
pub const SPPM_EYE_STREAM: u64 = 0x7370_706d_5f65_7965;

/// A pixel's visible point of this iteration as the photon pass sees it: where its camera
/// path stopped (see [`crate::integrator::VisiblePoint`]) and what a photon arriving there is
/// worth to the pixel: what its gather reads ([`super::gather`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct SplatPoint {
    /// Position (world space, camera-relative like the scene).
    pub p: Vec3,
    /// The geometric and shading normals on the camera's side: a photon counts with the
    /// weight [`GatherNormals::weight`] (photons from the other side are ignored).
    pub normals: GatherNormals,
    /// beta f / p_lobe: the camera path's throughput (an importance, radiance mode) times the
    /// diffuse lobe's f = albedo / pi, over the probability of having chosen that lobe. A
    /// photon of flux Phi_p inside the disc adds `weight * Phi_p` to the pixel's Phi.
    pub weight: Vec3,
    /// The pixel's squared gather radius R_i^2 this iteration; 0 with no visible point.
    pub r2: f32,
    /// Photons of more bounces do not count here: the point is at walk depth d, and a
    /// photon of bounce b closes a path of b + d + 1 bounces, at most max_depth
    /// ([`crate::integrator::gather_limit`]).
    pub max_bounce: u16,
    /// False when the path escaped, was absorbed or ended on a purely specular chain.
    pub found: bool,
}

impl SplatPoint {
    /// The disc the grid indexes, if any.
    #[inline]
    pub fn disc(&self) -> Option<(Vec3, f32)> {
        self.found.then_some((self.p, self.r2))
    }
}

/// Traces the camera path of `pixel` in `iteration` on the shared camera-path walk
/// ([`walk`]). Returns the radiance it found on the way (emission, sampled direct light) and
/// its visible point, whose `r2` the caller sets.
///
/// The walk follows delta lobes, picks up emission (fully at the camera and after a delta
/// bounce, MIS-weighted after a glossy one) and applies Russian roulette. At each vertex:
/// - no diffuse part (mirror, glass, a purely glossy phong): the non-diffuse part is traced
///   ([`crate::integrator::Walk::trace_non_diffuse`]: a glossy part gets one light sample with
///   MIS);
/// - a diffuse part only: the visible point, weight beta albedo / pi; with `--direct sampled`
///   one light sample of the diffuse part (photons then start at their second bounce);
/// - both parts (phong): one is chosen, the diffuse part with the probability q the BSDF's
///   own sampling gives it ([`Bsdf::diffuse_probability`], its share of the albedos), and
///   the throughput divided by the choice's probability (q or 1 - q), which keeps the
///   estimator unbiased: one visible point per path, yet the glossy part is traced as in
///   `ppm`, never density-estimated. A fixed q = 1/2 multiplied a path's second moment by
///   about 2 specular^2 per glossy bounce, which grows once specular exceeds 0.71 (a glossy
///   furnace of specular 0.9 had pixels 150 times its mean); with q proportional to the
///   albedos both choices weigh about the total albedo.
pub fn trace_camera_path(
    scene: &Scene,
    settings: &RenderSettings,
    iteration: u64,
    pixel: usize,
    width: usize,
    counters: &mut RayCounters,
) -> (Vec3, SplatPoint) {
    let (mut rng, ray) = start_pixel_path(
        scene,
        settings.seed ^ SPPM_EYE_STREAM,
        iteration,
        pixel,
        width,
    );
    let params = WalkParams::new(settings, LightStrategy::Mis);
    let sampled_direct = settings.direct == DirectMode::Sampled;
    let mut point = SplatPoint::default();
    let l = walk(scene, params, ray, &mut rng, counters, |w, v, rng| {
        let Some(diffuse) = v.bsdf.diffuse_part() else {
            return w.trace_non_diffuse(scene, v, rng);
        };
        let q = if v.bsdf.non_diffuse_part().is_some() {
            v.bsdf.diffuse_probability()
        } else {
            1.0
        };
        if q < 1.0 && rng.uniform() >= q {
            w.path.throughput /= 1.0 - q;
            return w.trace_non_diffuse(scene, v, rng);
        }
        w.path.throughput /= q;
        if sampled_direct {
            w.add_direct(scene, v, &Bsdf::Diffuse(diffuse), rng, false);
        }
        point = SplatPoint {
            p: v.hit.p,
            normals: v.sf.gather_normals(v.hit, v.wo),
            weight: w.path.throughput * diffuse.albedo * std::f32::consts::FRAC_1_PI,
            r2: 0.0,
            max_bounce: u16::try_from(gather_limit(settings.max_depth, v.depth))
                .unwrap_or(u16::MAX),
            found: true,
        };
        Next::Stop
    });
    (l, point)
}
