//! The per-path kernel of the path tracer.

use crate::geometry::Ray;
use crate::integrator::camera_walk::{walk, Next, RayCounters, WalkParams};
use crate::integrator::{LightStrategy, RenderSettings};
use crate::sampling::Rng;
use crate::scene::Scene;
use glam::Vec3;

/// Radiance arriving along `ray` (one-sample estimate).
///
/// The walk ([`walk`]): emission seen directly or after a specular bounce counts fully; after a
/// non-specular bounce it is weighted by MIS against light sampling (power heuristic), and the
/// path continues by BSDF sampling, throughput *= f |cos| / pdf, with Russian roulette after
/// `rr_depth` bounces (survival probability min(1, max channel of the throughput), the
/// survivors divided by it). At every vertex with a non-delta lobe, one light sample of the
/// whole BSDF (next-event estimation); the path then continues with the whole BSDF.
pub fn radiance(
    scene: &Scene,
    settings: &RenderSettings,
    ray: Ray,
    rng: &mut Rng,
    counters: &mut RayCounters,
) -> Vec3 {
    let strategy = settings.light_strategy;
    let params = WalkParams {
        max_depth: settings.max_depth,
        rr_depth: settings.rr_depth,
        emission: strategy,
    };
    walk(scene, params, ray, rng, counters, |w, v, rng| {
        if !v.bsdf.is_delta() && strategy != LightStrategy::BsdfOnly {
            w.add_direct(scene, v, v.bsdf, rng, strategy == LightStrategy::Mis);
        }
        Next::Scatter(*v.bsdf)
    })
}
