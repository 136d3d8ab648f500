//! The camera-path walk, written once for every integrator that traces paths from the eye.
//!
//! [`walk`] owns what all of them share: intersecting, emission pickup (fully at the camera and
//! after a delta bounce, MIS-weighted after a non-specular one, [`CameraPath::emission`]), the
//! BSDF-sampled continuation with Russian roulette ([`CameraPath::scatter`]) and the depth limit.
//! What to do at a vertex is the integrator's: a closure that sees the [`Vertex`], may add
//! radiance through [`Walk`], and answers with [`Next`]. It is a generic parameter, so the loop
//! is monomorphised per integrator: static dispatch, nothing allocated.
//!
//! The three integrators' vertex rules:
//! - path tracer: a light sample with the whole BSDF, then continue with the whole BSDF;
//! - photon mapping eye pass: the diffuse part is density-estimated, the non-diffuse part is
//!   traced ([`Walk::trace_non_diffuse`]: a light sample at a glossy lobe);
//! - stochastic PPM's visible-point pass: stop at the first vertex with a diffuse part and keep
//!   it as a [`VisiblePoint`] ([`walk_to_visible_point`]).

use super::direct::estimate_direct;
use super::shading::ShadingFrame;
use super::{CameraPath, LightStrategy, RenderSettings};
use crate::bsdf::{Bsdf, Diffuse};
use crate::geometry::{Hit, Ray};
use crate::sampling::Rng;
use crate::scene::Scene;
use glam::Vec3;

/// Rays traced by one worker.
#[derive(Clone, Copy, Debug, Default)]
pub struct RayCounters {
    /// Closest-hit rays.
    pub rays: u64,
    /// Shadow (any-hit) rays.
    pub shadow_rays: u64,
}

impl RayCounters {
    /// Sum of two counters.
    pub fn merge(a: Self, b: Self) -> Self {
        RayCounters {
            rays: a.rays + b.rays,
            shadow_rays: a.shadow_rays + b.shadow_rays,
        }
    }
}

/// The limits and the emission rule of a walk.
#[derive(Clone, Copy, Debug)]
pub struct WalkParams {
    /// Most bounces; emission is still picked up at the vertex after the last one.
    pub max_depth: u32,
    /// Russian roulette starts after this many bounces.
    pub rr_depth: u32,
    /// How emission found by BSDF sampling is weighted (see [`CameraPath::emission`]).
    pub emission: LightStrategy,
}

impl WalkParams {
    /// The depth limits of `settings` (`max_depth`, `rr_depth`), with emission found by BSDF
    /// sampling weighted by `emission`.
    #[inline(always)]
    pub fn new(settings: &RenderSettings, emission: LightStrategy) -> Self {
        WalkParams {
            max_depth: settings.max_depth,
            rr_depth: settings.rr_depth,
            emission,
        }
    }
}

/// A vertex of the walk, as the integrator's closure sees it.
pub struct Vertex<'a> {
    pub hit: &'a Hit,
    /// Direction toward the previous vertex (world space, unit).
    pub wo: Vec3,
    pub sf: ShadingFrame,
    /// The BSDF of the hit's material.
    pub bsdf: &'a Bsdf,
    /// Bounces before this vertex (0 at the first hit seen from the camera).
    pub depth: u32,
}

/// What the walk does after a vertex.
#[derive(Clone, Copy, Debug)]
pub enum Next {
    /// Continue by sampling this BSDF (the vertex's whole BSDF or one of its parts).
    Scatter(Bsdf),
    /// End the path here.
    Stop,
}

/// The state of a walk that the closure may read and add to.
pub struct Walk<'c> {
    /// Throughput and what MIS needs of the previous vertex.
    pub path: CameraPath,
    /// Radiance gathered so far (already multiplied by the throughput).
    pub radiance: Vec3,
    /// Length of the path from the camera to the current vertex (sum of segment lengths,
    /// through specular chains): the distance at which a pixel's footprint is measured.
    pub length: f32,
    pub counters: &'c mut RayCounters,
}

impl Walk<'_> {
    /// Adds `contribution` (radiance leaving the current vertex toward `wo`) times the
    /// path throughput.
    #[inline]
    pub fn add(&mut self, contribution: Vec3) {
        self.radiance += self.path.throughput * contribution;
    }

    /// One light sample of the light `bsdf` reflects toward the camera at `v`
    /// ([`estimate_direct`]), weighted by MIS against BSDF sampling when `mis` is set (only
    /// if the walk continues with a BSDF sample of the same `bsdf`).
    #[inline]
    pub fn add_direct(
        &mut self,
        scene: &Scene,
        v: &Vertex<'_>,
        bsdf: &Bsdf,
        rng: &mut Rng,
        mis: bool,
    ) {
        let (ld, traced) = estimate_direct(scene, v.hit, &v.sf, v.wo, bsdf, rng, mis);
        self.counters.shadow_rays += traced as u64;
        self.add(ld);
    }

    /// The traced lobes of a photon-mapping vertex: the non-diffuse part of
    /// the BSDF is never density-estimated. A glossy part gets one light sample, MIS-weighted
    /// (power heuristic) against the BSDF sample that continues the path, so the emission that
    /// sample finds is not counted twice; a delta part only continues. `Stop` when there is
    /// no non-diffuse part.
    #[inline]
    pub fn trace_non_diffuse(&mut self, scene: &Scene, v: &Vertex<'_>, rng: &mut Rng) -> Next {
        match v.bsdf.non_diffuse_part() {
            None => Next::Stop,
            Some(part) => {
                if !part.is_delta() {
                    self.add_direct(scene, v, &part, rng, true);
                }
                Next::Scatter(part)
            }
        }
    }
}

/// Walks the camera path that starts with `ray`, calling `at_vertex` at every vertex before the
/// depth limit; returns the radiance gathered (emission picked up, plus what `at_vertex`
/// added).
///
/// Per vertex: one closest-hit ray (a ray that leaves the scene picks up the environment,
/// [`CameraPath::escaped`], and ends the walk), the throughput times the transmittance of the
/// medium the segment crossed ([`Scene::transmittance`]); emission weighted by `params.emission`; at the depth limit
/// the walk ends; otherwise `at_vertex` decides, and on [`Next::Scatter`] the path continues by
/// sampling that BSDF in radiance mode, throughput *= f |cos| / pdf, with Russian roulette
/// after `params.rr_depth` bounces ([`CameraPath::scatter`]).
#[inline(always)]
pub fn walk<F>(
    scene: &Scene,
    params: WalkParams,
    mut ray: Ray,
    rng: &mut Rng,
    counters: &mut RayCounters,
    mut at_vertex: F,
) -> Vec3
where
    F: FnMut(&mut Walk<'_>, &Vertex<'_>, &mut Rng) -> Next,
{
    let mut w = Walk {
        path: CameraPath::new(ray.origin),
        radiance: Vec3::ZERO,
        length: 0.0,
        counters,
    };
    for depth in 0..=params.max_depth {
        w.counters.rays += 1;
        let Some(hit) = scene.intersect(&ray) else {
            // Added only when there is something to add, so that scenes without an
            // environment keep their sums bit for bit.
            let escaped = w.path.escaped(scene, ray.dir, params.emission);
            if escaped != Vec3::ZERO {
                w.add(escaped);
            }
            break;
        };
        w.length += hit.t;
        // Beer-Lambert along the segment just travelled (1 without absorbing media).
        w.path.throughput *= scene.transmittance(&hit, -ray.dir, hit.t);
        let wo = -ray.dir;
        let emitted = w.path.emission(scene, &hit, wo, params.emission);
        w.add(emitted);
        if depth == params.max_depth {
            break;
        }
        let bsdf = scene.bsdf(&hit);
        let v = Vertex {
            hit: &hit,
            wo,
            sf: ShadingFrame::new(&hit, wo),
            bsdf: &bsdf,
            depth,
        };
        let Next::Scatter(bsdf) = at_vertex(&mut w, &v, rng) else {
            break;
        };
        let Some(next) = w
            .path
            .scatter(&bsdf, &v.sf, &hit, wo, rng, depth, params.rr_depth)
        else {
            break;
        };
        ray = next;
    }
    w.radiance
}

/// The first vertex of a camera path with a diffuse part: where stochastic PPM gathers
/// photons for the pixel (Hachisuka and Jensen 2009, the "hit point" of their eye pass), and
/// where the auto radius measures the pixel's footprint.
#[derive(Clone, Copy, Debug)]
pub struct VisiblePoint {
    pub hit: Hit,
    /// Direction toward the previous vertex (world space).
    pub wo: Vec3,
    /// Path throughput from the camera to the point (radiance weight of its estimate).
    pub throughput: Vec3,
    /// The diffuse part of the BSDF there: its density estimate is the photons' contribution.
    pub diffuse: Diffuse,
    /// Length of the path from the camera (through any specular or glossy chain).
    pub length: f32,
}

/// Walks the camera path from `ray` to its first vertex with a diffuse part and returns the
/// radiance picked up on the way and that [`VisiblePoint`] (`None` if the path ends first).
/// Non-diffuse vertices are traced as in photon mapping ([`Walk::trace_non_diffuse`]). At
/// the visible point `at_visible` runs first (e.g. a light sample of the diffuse part with
/// `--direct sampled`), then the walk stops.
#[inline(always)]
pub fn walk_to_visible_point<F>(
    scene: &Scene,
    params: WalkParams,
    ray: Ray,
    rng: &mut Rng,
    counters: &mut RayCounters,
    mut at_visible: F,
) -> (Vec3, Option<VisiblePoint>)
where
    F: FnMut(&mut Walk<'_>, &Vertex<'_>, &Diffuse, &mut Rng),
{
    let mut visible = None;
    let radiance = walk(scene, params, ray, rng, counters, |w, v, rng| {
        if let Some(diffuse) = v.bsdf.diffuse_part() {
            at_visible(w, v, &diffuse, rng);
            visible = Some(VisiblePoint {
                hit: *v.hit,
                wo: v.wo,
                throughput: w.path.throughput,
                diffuse,
                length: w.length,
            });
            return Next::Stop;
        }
        w.trace_non_diffuse(scene, v, rng)
    });
    (radiance, visible)
}
