//! The scale-free initial radius of photon mapping (`auto`): a few pixel footprints at each
//! pixel's first diffuse visible point.
//!
//! A radius tied to the scene's extent fails on scenes with large ground planes or far walls,
//! and one in world units must be tuned per scene. A pixel's footprint, the camera's angular
//! pixel size times the distance travelled to its visible point, needs neither: scaling a
//! scene scales the distances and the radius with them, and a far-reaching floor changes only
//! the radius of the pixels that see it far away.

use super::camera_walk::{walk, Next, RayCounters, WalkParams};
use super::LightStrategy;
use crate::camera::Camera;
use crate::sampling::Rng;
use crate::scene::Scene;
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use std::f32::consts::FRAC_1_PI;

/// Pixel widths in an auto radius. Much less than a pixel would gather few photons (variance);
/// much more blurs shadows and caustics visibly (bias). Two was chosen by equal-time error
/// against path-traced references on the shipped boxes and a large ground plane
/// (`scripts/defaults_study.sh`, docs/performance.md): with two, `ppm` and `sppm` reached a
/// lower error than with three and than with the boxes' hand-tuned radii. The radius then
/// shrinks by Knaus and Zwicker's schedule (ppm) or by each pixel's photons (sppm).
pub const FOOTPRINT_PIXELS: f32 = 2.0;

/// Random streams of the pilot paths, apart from the eye and light paths'.
pub const PILOT_STREAM: u64 = 0x7069_6c6f_745f_7221;

/// The radius a pixel's gather should start with when its visible point lies at `length` along
/// the camera path (the sum of the segment lengths through any specular or glossy chain):
/// `FOOTPRINT_PIXELS * pixel_angle * length`, the footprint of that many pixels projected at
/// that distance. Through a flat mirror or a refracting slab the path length is the distance
/// to the virtual image, so the footprint is right; curved specular surfaces magnify or shrink
/// it, which the path length does not see (the radius is then only of the right order). The
/// footprint is measured perpendicular to the ray: on a surface seen at grazing angles the
/// pixel's footprint is longer along the slope, and the radius keeps its short side.
///
/// Reusable by every photon mapper (PPM's pilot, SPPM's visible points).
#[inline]
pub fn footprint_radius(camera: &Camera, length: f32) -> f32 {
    FOOTPRINT_PIXELS * camera.pixel_angle() * length
}

/// Where a pixel's pilot path (see [`pilot_points`]) first meets a surface with a diffuse part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PilotPoint {
    /// The path's length from the camera to the point (the sum of its segments).
    pub length: f32,
    /// The point, in world space.
    pub position: Vec3,
    /// Bounces before the point (the walk's depth there: 0 when the camera sees it directly).
    pub depth: u32,
    /// What a photon density estimate there is multiplied by to become the pixel's radiance:
    /// the path's throughput times the diffuse part's albedo / π (the mean of the channels).
    pub weight: f32,
}

/// One pilot path per pixel (row-major) through the pixel's centre: the path follows specular
/// and glossy lobes (sampled as the eye pass does, with its own random stream keyed by
/// (seed, pixel)) to its first vertex with a diffuse part, or `None` when it finds none (the
/// background, a path absorbed on the way). The same seed gives the same points.
pub fn pilot_points(
    scene: &Scene,
    seed: u64,
    max_depth: u32,
    rr_depth: u32,
    counters: &mut RayCounters,
) -> Vec<Option<PilotPoint>> {
    let camera = &scene.camera;
    let width = camera.width as usize;
    let pixels = width * camera.height as usize;
    let params = WalkParams {
        max_depth,
        rr_depth,
        emission: LightStrategy::Mis,
    };
    let mut points = vec![None; pixels];
    let total = points
        .par_chunks_mut(width)
        .enumerate()
        .map(|(y, row)| {
            let mut row_counters = RayCounters::default();
            for (x, out) in row.iter_mut().enumerate() {
                let pixel = (y * width + x) as u64;
                let mut rng = Rng::new(seed ^ PILOT_STREAM, 0, pixel);
                let ray = camera.generate_ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
                walk(
                    scene,
                    params,
                    ray,
                    &mut rng,
                    &mut row_counters,
                    |w, v, _| {
                        if let Some(diffuse) = v.bsdf.diffuse_part() {
                            let weight = w.path.throughput * diffuse.albedo * FRAC_1_PI;
                            *out = Some(PilotPoint {
                                length: w.length,
                                position: v.hit.p,
                                depth: v.depth,
                                weight: (weight.x + weight.y + weight.z) / 3.0,
                            });
                            return Next::Stop;
                        }
                        v.bsdf.non_diffuse_part().map_or(Next::Stop, Next::Scatter)
                    },
                );
            }
            row_counters
        })
        .reduce(RayCounters::default, RayCounters::merge);
    counters.rays += total.rays;
    counters.shadow_rays += total.shadow_rays;
    points
}

/// The initial radius of every pixel (row-major) for [`super::Radius::Auto`]:
/// [`footprint_radius`] at the path length of the pixel's [`pilot_points`]. Pixels whose
/// pilot finds no diffuse vertex take the median of the others' radii; if no pixel finds one
/// the scene has nothing to gather on and 0.5% of the scene's diagonal stands in (1 if the
/// scene has no extent).
///
/// The pilot's random numbers are its own, drawn before and independently of every
/// iteration's, so the radii are fixed, not random, for the iterations' estimates.
pub fn pilot_radii(
    scene: &Scene,
    seed: u64,
    max_depth: u32,
    rr_depth: u32,
    counters: &mut RayCounters,
) -> Vec<f32> {
    let points = pilot_points(scene, seed, max_depth, rr_depth, counters);
    footprint_radii(scene, &points)
}

/// [`pilot_radii`] of pilot points already traced (one per pixel, row-major).
pub(crate) fn footprint_radii(scene: &Scene, points: &[Option<PilotPoint>]) -> Vec<f32> {
    let mut radii: Vec<f32> = points
        .iter()
        .map(|p| p.map_or(f32::NAN, |p| footprint_radius(&scene.camera, p.length)))
        .collect();
    let mut found: Vec<f32> = radii
        .iter()
        .copied()
        .filter(|r| r.is_finite() && *r > 0.0)
        .collect();
    let fallback = if found.is_empty() {
        // A scene without geometry (only lights) has a diagonal of 0; nothing is ever
        // gathered there, but the grids need a positive radius.
        let r = 0.005 * scene.diagonal();
        if r.is_finite() && r > 0.0 {
            r
        } else {
            1.0
        }
    } else {
        let mid = found.len() / 2;
        *found.select_nth_unstable_by(mid, f32::total_cmp).1
    };
    for r in &mut radii {
        if !(r.is_finite() && *r > 0.0) {
            *r = fallback;
        }
    }
    radii
}

/// The `q`-quantile (0 <= q <= 1) of `values` (not empty), by selection: the value of rank
/// round(q (n - 1)).
pub(crate) fn quantile(values: &[f32], q: f32) -> f32 {
    let mut v = values.to_vec();
    let k = ((q.clamp(0.0, 1.0) * (v.len() - 1) as f32).round() as usize).min(v.len() - 1);
    *v.select_nth_unstable_by(k, f32::total_cmp).1
}
