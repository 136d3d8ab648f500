//! The eye pass: camera paths through specular chains to a
//! diffuse point, where the photon map gives the reflected radiance.

use crate::bsdf::Bsdf;
use crate::integrator::camera_path::start_pixel_path;
use crate::integrator::camera_walk::{walk, RayCounters, WalkParams};
use crate::integrator::{DirectMode, LightStrategy, RenderSettings};
use crate::photon::{GatherNormals, HashGrid, Kernel};
use crate::scene::Scene;
use glam::Vec3;

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

/// The photon density estimate of the radiance reflected at `p`, a point with `normals`
/// (turned toward the viewer, [`crate::integrator::ShadingFrame::gather_normals`]), by a
/// diffuse lobe of albedo `albedo` (a diffuse surface, or the diffuse lobe of a phong
/// surface):
///
/// L(x, wo) = sum over photons p within r of f k(d_p^2) Phi_p w(wi_p) / N,   f = albedo / pi,
/// k(d^2) = 2 (1 - d^2 / r^2) / (pi r^2)  (Epanechnikov, normalised over the disc),
///
/// where Phi_p is the flux of the photon's light path and N the number of light paths.
/// f does not depend on the directions, so it leaves the sum. Photons that arrived from the
/// other side of the surface (wi_p . n <= 0, n the geometric normal turned toward the viewer)
/// are rejected: they lit the back of a thin wall. On a surface shaded with an interpolated
/// normal ns each photon is also weighted by (wi_p . ns) / (wi_p . n): the photons' density
/// per unit of geometric area is the irradiance with the geometric cosine, while the
/// reflected radiance takes the shading one (w = 1 when flat; [`crate::photon::GatherNormals`]).
///
/// Only photons of at most `max_bounce` bounces count. A photon left at its light path's hit
/// number b + 1 (bounce b) and gathered at camera vertex d + 1 (walk depth d: d bounces
/// before it) closes a path of b + 1 + d + 1 edges, that is b + d + 1 bounces, which
/// `max_depth` bounds as it bounds the path tracer's paths: b <= max_depth - 1 - d
/// ([`gather_limit`]). At the first vertex (d = 0) every photon qualifies, since the photon
/// pass stops at bounce max_depth - 1; behind a specular chain the limit removes the photons
/// that would make the path too long.
#[inline]
pub fn density_estimate(
    ctx: &GatherContext<'_>,
    p: Vec3,
    normals: GatherNormals,
    albedo: Vec3,
    max_bounce: u32,
) -> Vec3 {
    let sum = ctx
        .grid
        .kernel_flux_up_to(p, ctx.radius, normals, &ctx.kernel, max_bounce);
    sum * (albedo * (std::f32::consts::FRAC_1_PI * ctx.inv_paths))
}

/// The most bounces a photon gathered at walk depth `depth` (`depth < max_depth`) may have
/// so that the whole path has at most `max_depth` bounces (see [`density_estimate`]).
#[inline]
pub fn gather_limit(max_depth: u32, depth: u32) -> u32 {
    debug_assert!(
        depth < max_depth,
        "no gather at depth {depth} of {max_depth}"
    );
    max_depth - 1 - depth
}

/// The eye path through pixel `pixel` of iteration `iteration`; returns its radiance estimate.
///
/// The walk ([`walk`]) follows delta lobes, picks up emission seen directly or through
/// specular chains fully (MIS-weighted after a glossy bounce) and applies Russian roulette
/// after `rr_depth` bounces. At each vertex the BSDF is split ([`Bsdf::diffuse_part`],
/// [`Bsdf::non_diffuse_part`]):
/// - the diffuse part gets the photon density estimate, and with `--direct sampled` one light
///   sample (no MIS: this part is never sampled by the path, so light sampling is the only
///   strategy for its direct light);
/// - the non-diffuse part is traced (6.4, [`crate::integrator::Walk::trace_non_diffuse`]): a glossy part gets a
///   light sample MIS-weighted against the BSDF sample that continues the path; a delta part
///   only continues. Without a non-diffuse part the path ends.
///
/// Always inlined into the pass's loop over pixels: as a call it loaded and spilled about 80
/// instructions' worth of loop invariants (scene and gather fields) for every pixel.
#[inline(always)]
pub fn trace_eye_path(
    scene: &Scene,
    settings: &RenderSettings,
    ctx: &GatherContext<'_>,
    iteration: u64,
    pixel: usize,
    width: usize,
    counters: &mut RayCounters,
) -> Vec3 {
    let (mut rng, ray) =
        start_pixel_path(scene, settings.seed ^ EYE_STREAM, iteration, pixel, width);
    let params = WalkParams::new(settings, LightStrategy::Mis);
    let sampled_direct = settings.direct == DirectMode::Sampled;
    walk(scene, params, ray, &mut rng, counters, |w, v, rng| {
        if let Some(diffuse) = v.bsdf.diffuse_part() {
            let normals = v.sf.gather_normals(v.hit, v.wo);
            let max_bounce = gather_limit(settings.max_depth, v.depth);
            w.add(density_estimate(
                ctx,
                v.hit.p,
                normals,
                diffuse.albedo,
                max_bounce,
            ));
            if sampled_direct {
                w.add_direct(scene, v, &Bsdf::Diffuse(diffuse), rng, false);
            }
        }
        w.trace_non_diffuse(scene, v, rng)
    })
}
