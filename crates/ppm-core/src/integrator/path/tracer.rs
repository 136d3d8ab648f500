//! The per-path kernel of the path tracer.

use crate::bsdf::{Lobe, TransportMode};
use crate::geometry::Ray;
use crate::integrator::direct::{emission_mis_weight, estimate_direct};
use crate::integrator::shading::ShadingFrame;
use crate::integrator::{LightStrategy, RenderSettings};
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
    let mut throughput = Vec3::ONE;
    // State of the previous vertex, for MIS on emission found by BSDF sampling.
    let mut prev_specular = true;
    let mut prev_pdf = 0.0f32;
    let mut prev_p = ray.origin;
    for depth in 0..=settings.max_depth {
        counters.rays += 1;
        let Some(hit) = scene.intersect(&ray) else {
            break;
        };
        let material = scene.material(&hit);
        let wo = -ray.dir;

        if material.is_emissive() && wo.dot(hit.ng) > 0.0 {
            let weight = if prev_specular {
                1.0
            } else {
                match strategy {
                    LightStrategy::Mis => emission_mis_weight(scene, prev_p, prev_pdf, &hit),
                    LightStrategy::LightOnly => 0.0,
                    LightStrategy::BsdfOnly => 1.0,
                }
            };
            l += throughput * material.emission * weight;
        }
        if depth == settings.max_depth {
            break;
        }

        let bsdf = &material.bsdf;
        let sf = ShadingFrame::new(&hit, wo);
        if !bsdf.is_delta() && strategy != LightStrategy::BsdfOnly {
            let mis = strategy == LightStrategy::Mis;
            let (ld, traced) = estimate_direct(scene, &hit, &sf, wo, bsdf, rng, mis);
            counters.shadow_rays += traced as u64;
            l += throughput * ld;
        }

        let u_lobe = rng.uniform();
        let u = rng.uniform2();
        let Some(s) = bsdf.sample(sf.wo, u_lobe, u, TransportMode::Radiance) else {
            break;
        };
        let wi = sf.frame.to_world(s.wi);
        if !sf.consistent(&hit, wo, wi, s.wi) {
            break;
        }
        throughput *= s.weight;
        prev_specular = s.lobe == Lobe::Specular;
        prev_pdf = s.pdf;
        prev_p = hit.p;

        if depth + 1 >= settings.rr_depth {
            let survive = throughput.max_element().min(1.0);
            if survive.is_nan() || rng.uniform() >= survive {
                break;
            }
            throughput /= survive;
        }
        ray = Ray::spawn(hit.p, hit.ng, wi);
    }
    l
}
