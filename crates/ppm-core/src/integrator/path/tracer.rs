//! The per-path kernel of the path tracer.

use crate::geometry::Ray;
use crate::integrator::direct::estimate_direct;
use crate::integrator::shading::ShadingFrame;
use crate::integrator::{CameraPath, LightStrategy, RenderSettings};
use crate::sampling::Rng;
use crate::scene::Scene;
use glam::Vec3;

/// Rays traced by one worker.
#[derive(Clone, Copy, Debug, Default)]
pub struct PathCounters {
    pub rays: u64,
    pub shadow_rays: u64,
}

impl PathCounters {
    /// Sum of two counters.
    pub fn merge(a: Self, b: Self) -> Self {
        PathCounters {
            rays: a.rays + b.rays,
            shadow_rays: a.shadow_rays + b.shadow_rays,
        }
    }
}

/// Radiance arriving along `ray` (one-sample estimate).
///
/// At every vertex: emission seen directly or after a specular bounce counts fully; after a
/// non-specular bounce it is weighted by MIS against light sampling (power heuristic). At
/// every non-specular vertex one light sample (next-event estimation). The path continues by
/// BSDF sampling, throughput *= f |cos| / pdf, with Russian roulette after `rr_depth` bounces
/// (survival probability min(1, max channel of the throughput), the survivors divided by it).
pub fn radiance(
    scene: &Scene,
    settings: &RenderSettings,
    mut ray: Ray,
    rng: &mut Rng,
    counters: &mut PathCounters,
) -> Vec3 {
    let strategy = settings.light_strategy;
    let mut l = Vec3::ZERO;
    let mut path = CameraPath::new(ray.origin);
    for depth in 0..=settings.max_depth {
        counters.rays += 1;
        let Some(hit) = scene.intersect(&ray) else {
            break;
        };
        let material = scene.material(&hit);
        let wo = -ray.dir;

        l += path.throughput * path.emission(scene, &hit, wo, strategy);
        if depth == settings.max_depth {
            break;
        }

        let bsdf = &material.bsdf;
        let sf = ShadingFrame::new(&hit, wo);
        if !bsdf.is_delta() && strategy != LightStrategy::BsdfOnly {
            let mis = strategy == LightStrategy::Mis;
            let (ld, traced) = estimate_direct(scene, &hit, &sf, wo, bsdf, rng, mis);
            counters.shadow_rays += traced as u64;
            l += path.throughput * ld;
        }

        let Some(next) = path.scatter(bsdf, &sf, &hit, wo, rng, depth, settings.rr_depth) else {
            break;
        };
        ray = next;
    }
    l
}
