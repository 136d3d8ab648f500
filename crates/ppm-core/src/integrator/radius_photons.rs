//! The default initial radius of photon mapping (`photons`): each pixel's distance to its
//! [`NEAREST_PHOTONS`]-th nearest photon in a pilot photon map of a fixed size, for `ppm`
//! times one scale for the whole image that balances bias against variance
//! ([`super::radius_scale`]).
//!
//! The radius should be free of the scene's units, its extent and the image's resolution.
//! A pixel footprint (`auto`, [`super::footprint`]) is free of the first two but not of the
//! third: at 4 times the pixels it is half the radius in the scene, so at an equal photon
//! count each pixel's estimate rests on a quarter of the photons. The photons themselves say
//! how large a disc must be to hold enough of them: the k-nearest-neighbour radius of the
//! classic photon map (Jensen 2001, sec. 7.2), here measured once, before the first
//! iteration, in a pilot photon map, and then shrunk by the usual schedule.
//!
//! The rule, for pixel p with pilot point x_p (the first diffuse vertex of the path through
//! its centre, [`pilot_points`]):
//!
//!   r_1(p) = m min(d_k(x_p), CAP * median_q d_k(x_q)),
//!
//! where d_k(x) is the distance from x to the k-th nearest photon (k = [`NEAREST_PHOTONS`])
//! among those a gather at x would count (bounce limit of [`gather_limit`]), in a pilot map of
//! [`PILOT_LIGHT_PATHS`] light paths traced with the render's depth and direct-light mode
//! (every bounce for `vcm`, which merges them all) on a random stream of their own. Pixels whose pilot finds no diffuse surface, or fewer than k
//! photons within the cap, take the median (no surface) or the cap (too few photons). The
//! scale m (`ppm`; 1 for the others) comes from the same pilot: the squared bias and the variance of the estimate at
//! d_k pooled over a sample of pixels, the eye pass's own noise there, and the cost of a
//! larger disc, so that the error at equal time is least ([`super::radius_scale`]).
//!
//! - Units and extent: scaling the scene scales every distance, photon positions with it,
//!   so d_k scales and the image does not change; a far-reaching floor changes the photon
//!   density only where the floor is.
//! - Resolution: the pilot map's size is fixed, not the render's photons per iteration
//!   (`sppm` and `vcm` trace one light path per pixel), and d_k is measured at points, not
//!   over pixels, so d_k of a surface point does not depend on the image's size. The scale
//!   m does, through time alone: at equal time more pixels mean fewer iterations of a
//!   render of the nominal length, and make the gathers a larger share of each.
//! - For a uniform photon density rho (photons per unit area) on a plane, pi d_k^2 rho is
//!   Gamma(k, 1) distributed (the k-th point of a Poisson process), so
//!   E[d_k^2] = k / (pi rho): the first iteration's disc holds about k photons per
//!   [`PILOT_LIGHT_PATHS`] light paths.
//!
//! Like the footprint's, the pilot's random numbers are its own (seed ^ [`PILOT_PHOTON_STREAM`]
//! for the light paths, [`super::PILOT_STREAM`] for the points, seed ^ [`PILOT_EYE_STREAM`]
//! for the eye-only estimates), so the radii are a pure
//! function of the scene and the settings, fixed, not random, for every iteration's estimate,
//! and the same at any thread count (each pixel's d_k is the k-th smallest of a set of
//! distances, whatever order the grid hands them out in; m sums its pixels in order).

use super::camera_walk::RayCounters;
use super::footprint::{footprint_radii, pilot_points, PilotPoint};
use super::radius_moments::{pilot_scale, Pilot};
use super::radius_scale::scales;
use super::runner::Poll;
use super::{
    gather_limit, trace_light_path, DirectMode, MemoryEstimate, MemoryPart, PhotonCounters, Radius,
    RenderSettings, Setting, Stop, BYTES_PER_PHOTON, DEFAULT_PHOTONS, PHOTONS_PER_PATH,
};
use crate::photon::{HashGrid, Photon, PhotonBuffer};
use crate::scene::Scene;
use glam::Vec3;
use rayon::prelude::*;

/// k: the photons a pixel's first disc holds in the pilot map. A round value within the 16
/// to 128 usual for k-nearest photon maps, checked by equal-time error against fixed world
/// radii on a glass scene and a Cornell box at 128 and 512 pixels (docs/performance.md, "A
/// radius from the photons"); the density estimate's relative noise in the first iterations is
/// about 1 / sqrt(k) times [`PILOT_LIGHT_PATHS`] over the photons per iteration.
pub const NEAREST_PHOTONS: usize = 32;

/// Light paths of the pilot photon map: `ppm`'s default photons per iteration, so that with
/// the defaults the first iteration's disc holds about [`NEAREST_PHOTONS`] photons. Fixed,
/// whatever `--photons` and the image size, so that the radius depends on neither.
pub const PILOT_LIGHT_PATHS: u32 = DEFAULT_PHOTONS;

/// No pixel's radius exceeds this many times the median pixel's: in a dark corner the k-th
/// photon may lie across the room, and a disc that large would average light from there.
pub const CAP: f32 = 4.0;

/// Random streams of the pilot light paths, apart from the iterations' and the pilot points'.
pub const PILOT_PHOTON_STREAM: u64 = 0x6b6e_6e5f_7068_6f74;

/// Random streams of the pilot's eye-only estimates ([`super::radius_moments::EyeLight`]).
pub const PILOT_EYE_STREAM: u64 = 0x6579_655f_6e6f_6973;

/// Pilot points used to choose the grid's cell size (a stride through the found ones).
const GRID_SAMPLE: usize = 256;

/// Light paths per parallel work item of the pilot photon pass.
const PATHS_PER_TASK: u32 = 512;

/// The distance from `p` to the `k`-th nearest photon of `grid` with at most `max_bounce`
/// bounces (k >= 1), if it is at most `limit`; `None` if fewer than `k` such photons lie
/// within `limit`. The search starts at radius `start` (> 0) and doubles: once a disc holds
/// k photons, every photon nearer than the k-th is in it, so the answer is exact.
/// `scratch` is reused between calls.
pub fn nearest_photon_distance(
    grid: &HashGrid,
    p: Vec3,
    k: usize,
    max_bounce: u32,
    start: f32,
    limit: f32,
    scratch: &mut Vec<f32>,
) -> Option<f32> {
    debug_assert!(k >= 1 && start > 0.0);
    let mut r = start.min(limit);
    loop {
        scratch.clear();
        grid.for_each_in_radius(p, r, |photon, d2| {
            if photon.bounce() <= max_bounce {
                scratch.push(d2);
            }
        });
        if scratch.len() >= k {
            let (_, kth, _) = scratch.select_nth_unstable_by(k - 1, f32::total_cmp);
            return Some(kth.sqrt());
        }
        if r >= limit {
            return None;
        }
        r = (2.0 * r).min(limit);
    }
}

/// The pilot photon map: [`PILOT_LIGHT_PATHS`] light paths of `settings` (their depth, and
/// their direct-light mode where the algorithm reads it) on the pilot's own stream; `None` if
/// `poll` says stop (asked between light paths: in a deep closed scene the pilot pass is long).
fn pilot_photons(
    scene: &Scene,
    settings: &RenderSettings,
    counters: &mut RayCounters,
    poll: &Poll,
) -> Option<Vec<Photon>> {
    // The photons the render's estimate counts: with `--direct sampled` ppm and sppm store
    // none of the first bounce; vcm merges light vertices of every bounce (and does not read
    // the direct-light mode, so its radius must not depend on it).
    let direct = if settings.algorithm.reads(Setting::Direct) {
        settings.direct
    } else {
        DirectMode::Photons
    };
    let pilot = RenderSettings {
        seed: settings.seed ^ PILOT_PHOTON_STREAM,
        photons: PILOT_LIGHT_PATHS,
        direct,
        ..settings.clone()
    };
    let mut buffer = PhotonBuffer::with_capacity(PILOT_LIGHT_PATHS as usize * PHOTONS_PER_PATH);
    loop {
        buffer.clear();
        let rays = (0..PILOT_LIGHT_PATHS.div_ceil(PATHS_PER_TASK))
            .into_par_iter()
            .map(|task| {
                let mut light = PhotonCounters::default();
                let mut writer = buffer.writer();
                let end = ((task + 1) * PATHS_PER_TASK).min(PILOT_LIGHT_PATHS);
                for path in task * PATHS_PER_TASK..end {
                    if poll.stopped() {
                        break;
                    }
                    trace_light_path(scene, &pilot, 0, path, &mut writer, &mut light);
                }
                light.rays
            })
            .sum::<u64>();
        if poll.stopped() {
            return None;
        }
        if !buffer.overflowed() {
            counters.rays += rays;
            return Some(buffer.as_slice().to_vec());
        }
        let needed = buffer.pushed();
        buffer.grow(needed + needed / 4);
    }
}

/// The median of `values` (not empty), by selection.
fn median(values: &[f32]) -> f32 {
    let mut v = values.to_vec();
    let mid = v.len() / 2;
    *v.select_nth_unstable_by(mid, f32::total_cmp).1
}

/// Each pixel's d_k (row-major; `None` where the pilot found no diffuse surface or fewer than
/// `k` photons within `limit(typical)`), and the typical d_k of a sample of pixels, with
/// `grid` built over `photons` for it.
fn pixel_distances(
    scene: &Scene,
    settings: &RenderSettings,
    points: &[Option<PilotPoint>],
    photons: &[Photon],
    k: usize,
) -> Vec<Option<f32>> {
    let found: Vec<&PilotPoint> = points.iter().flatten().collect();
    if found.is_empty() || photons.is_empty() {
        return vec![None; points.len()];
    }
    let max_bounce = |p: &PilotPoint| gather_limit(settings.max_depth, p.depth);
    // A first grid whose cells are a 1/1024 of the scene's diagonal (scale-free), for a
    // sample of the points; the median of their d_k then sizes the cells of the grid every
    // pixel queries, so that a typical query visits 2 x 2 x 2 cells.
    let diagonal = scene.diagonal();
    let coarse = if diagonal.is_finite() && diagonal > 0.0 {
        diagonal / 1024.0
    } else {
        1.0
    };
    let far = if diagonal.is_finite() && diagonal > 0.0 {
        2.0 * diagonal
    } else {
        f32::MAX
    };
    let mut grid = HashGrid::new();
    grid.build(photons, coarse);
    let stride = found.len().div_ceil(GRID_SAMPLE);
    let sample: Vec<f32> = found
        .par_iter()
        .step_by(stride)
        .map_init(Vec::new, |scratch, p| {
            nearest_photon_distance(&grid, p.position, k, max_bounce(p), coarse, far, scratch)
        })
        .flatten()
        .filter(|d| *d > 0.0)
        .collect();
    if sample.is_empty() {
        return vec![None; points.len()];
    }
    let typical = median(&sample);
    grid.build(photons, typical);
    let limit = CAP * typical.max(f32::MIN_POSITIVE);
    points
        .par_iter()
        .map_init(Vec::new, |scratch, p| {
            p.as_ref().and_then(|p| {
                nearest_photon_distance(
                    &grid,
                    p.position,
                    k,
                    max_bounce(p),
                    typical,
                    limit,
                    scratch,
                )
            })
        })
        .collect()
}

/// Adds the pilot's memory to `estimate` under the `photons` rule (nothing under the others:
/// the footprint pilot's points are a few bytes per pixel): the pilot photon map, as a photon
/// pass of [`PILOT_LIGHT_PATHS`] paths, and per pixel its pilot point and distance. They live
/// beside the render's own buffers during the first iteration's pilot, so the two add.
pub fn add_pilot_memory(
    estimate: &mut MemoryEstimate,
    width: u32,
    height: u32,
    settings: &RenderSettings,
) {
    if settings.radius != Radius::Photons {
        return;
    }
    let pixels = width as u64 * height as u64;
    let per_pixel = (std::mem::size_of::<Option<PilotPoint>>()
        + std::mem::size_of::<Option<f32>>()
        + std::mem::size_of::<f32>()) as u64;
    let photons = PILOT_LIGHT_PATHS as u64 * PHOTONS_PER_PATH as u64 * BYTES_PER_PHOTON;
    estimate.add(
        MemoryPart::Pilot,
        photons.saturating_add(pixels.saturating_mul(per_pixel)),
    );
}

/// The initial radius r_1(p) of every pixel (row-major) for [`super::Radius::Photons`]: the
/// rule of this module, with k = [`NEAREST_PHOTONS`]. Pixels without a pilot point take the
/// median of the found radii, pixels with fewer than k photons within the cap the cap; if no
/// pixel finds k photons (a scene that stores none), the footprint rule at the same pilot
/// points stands in ([`super::pilot_radii`], without tracing them again).
pub fn photon_radii(
    scene: &Scene,
    settings: &RenderSettings,
    counters: &mut RayCounters,
) -> Vec<f32> {
    photon_radii_with(scene, settings, NEAREST_PHOTONS, counters)
}

/// [`photon_radii`] with `k` nearest photons (k >= 1), for tests and measurement.
pub fn photon_radii_with(
    scene: &Scene,
    settings: &RenderSettings,
    k: usize,
    counters: &mut RayCounters,
) -> Vec<f32> {
    unstopped(scene, settings, k, Scaled::Yes, counters)
}

/// [`photon_radii_with`] without the bias-variance scale (m = 1): each pixel's capped d_k
/// alone, for tests and measurement.
pub fn nearest_photon_radii(
    scene: &Scene,
    settings: &RenderSettings,
    k: usize,
    counters: &mut RayCounters,
) -> Vec<f32> {
    unstopped(scene, settings, k, Scaled::No, counters)
}

/// [`photon_radii_until`] with nothing to stop it.
fn unstopped(
    scene: &Scene,
    settings: &RenderSettings,
    k: usize,
    scaled: Scaled,
    counters: &mut RayCounters,
) -> Vec<f32> {
    let never = || false;
    photon_radii_until(scene, settings, k, scaled, counters, &Poll::new(&never))
        .expect("a pass that is never stopped finishes")
}

/// Whether the radii are multiplied by the bias-variance scale where the algorithm takes it
/// ([`scales`]: `Yes`), or never (`No`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scaled {
    Yes,
    No,
}

/// [`photon_radii_with`], abandoned (`None`) if `poll` says stop during the pilot photon pass.
fn photon_radii_until(
    scene: &Scene,
    settings: &RenderSettings,
    k: usize,
    scaled: Scaled,
    counters: &mut RayCounters,
    poll: &Poll,
) -> Option<Vec<f32>> {
    let k = k.max(1);
    let s = settings;
    let points = pilot_points(scene, s.seed, s.max_depth, s.rr_depth, counters);
    let before_photons = counters.rays;
    let photons = pilot_photons(scene, settings, counters, poll)?;
    let light_rays = counters.rays - before_photons;
    let distances = pixel_distances(scene, settings, &points, &photons, k);
    let found: Vec<f32> = distances
        .iter()
        .flatten()
        .copied()
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    if found.is_empty() {
        return Some(footprint_radii(scene, &points));
    }
    let mid = median(&found);
    let cap = CAP * mid;
    let radii: Vec<f32> = points
        .iter()
        .zip(&distances)
        .map(|(point, d)| match (point, d) {
            (_, Some(d)) if d.is_finite() && *d > 0.0 => d.min(cap),
            (Some(_), _) => cap,
            (None, _) => mid,
        })
        .collect();
    if scaled == Scaled::No || !scales(settings.algorithm) {
        return Some(radii);
    }
    let pilot = Pilot {
        points: &points,
        distances: &distances,
        radii: &radii,
        photons: &photons,
        light_rays,
        k,
    };
    let m = pilot_scale(scene, settings, &pilot, mid, counters);
    Some(radii.iter().map(|r| m * r).collect())
}

/// Every pixel's initial radius (row-major) under a per-pixel rule (`auto`: the footprint,
/// [`super::pilot_radii`]; `photons`: [`photon_radii`]); `Some(None)` for a world radius, and
/// `None` if `stop` said yes during the pilot pass (the caller abandons its iteration). The one
/// place ppm, sppm and vcm choose between the rules.
pub fn initial_pixel_radii(
    scene: &Scene,
    settings: &RenderSettings,
    counters: &mut RayCounters,
    stop: Stop,
) -> Option<Option<Vec<f32>>> {
    let s = settings;
    match s.radius {
        Radius::World(_) => Some(None),
        Radius::Auto => Some(Some(super::pilot_radii(
            scene,
            s.seed,
            s.max_depth,
            s.rr_depth,
            counters,
        ))),
        Radius::Photons => {
            let poll = Poll::new(stop);
            photon_radii_until(
                scene,
                settings,
                NEAREST_PHOTONS,
                Scaled::Yes,
                counters,
                &poll,
            )
            .map(Some)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// Photons uniform on the unit square of the plane z = 0 (a binomial process of density
    /// n per unit area): E[pi d_k^2 rho] = k, so the mean of d_k^2 over query points far from
    /// the edges is k / (pi rho) within sampling error.
    #[test]
    fn the_nearest_photon_radius_of_a_uniform_density_is_sqrt_k_over_pi_rho() {
        let n = 200_000u32;
        let mut rng = Rng::new(5, 0, 0);
        let photons: Vec<Photon> = (0..n)
            .map(|i| {
                let u = rng.uniform2();
                Photon::new(
                    Vec3::new(u.x, u.y, 0.0),
                    Vec3::Z,
                    Vec3::ONE,
                    Photon::key(i, 1),
                )
            })
            .collect();
        let mut grid = HashGrid::new();
        grid.build(&photons, 0.01);
        let mut scratch = Vec::new();
        for k in [8usize, 32, 128] {
            let expected = k as f64 / (std::f64::consts::PI * n as f64);
            let mut sum = 0.0;
            let queries = 400;
            for q in 0..queries {
                let u = rng.uniform2();
                let p = Vec3::new(0.2 + 0.6 * u.x, 0.2 + 0.6 * u.y, 0.0);
                let d = nearest_photon_distance(&grid, p, k, 1, 1e-4, 1.0, &mut scratch)
                    .unwrap_or_else(|| panic!("query {q}: fewer than {k} photons"));
                sum += (d as f64).powi(2);
            }
            // pi rho d_k^2 ~ Gamma(k, 1): the mean of 400 has a relative deviation of
            // 1 / sqrt(400 k) (at most 2.5%); 4 of them.
            let mean = sum / queries as f64;
            let rel = (mean / expected - 1.0).abs();
            assert!(
                rel < 4.0 / (400.0 * k as f64).sqrt(),
                "k {k}: {mean:e} vs {expected:e}"
            );
        }
        // Photons of more bounces than allowed are not counted: none with bounce 0.
        assert_eq!(
            nearest_photon_distance(&grid, Vec3::splat(0.5), 8, 0, 1e-3, 2.0, &mut scratch),
            None
        );
    }

    /// The k-th distance is exact whatever radius the search starts at.
    #[test]
    fn the_search_start_does_not_change_the_distance() {
        let mut rng = Rng::new(9, 0, 0);
        let photons: Vec<Photon> = (0..5000u32)
            .map(|i| {
                let u = rng.uniform2();
                let v = rng.uniform();
                Photon::new(
                    Vec3::new(u.x, u.y, v),
                    Vec3::Z,
                    Vec3::ONE,
                    Photon::key(i, 1),
                )
            })
            .collect();
        let p = Vec3::new(0.4, 0.6, 0.5);
        let mut all: Vec<f32> = photons
            .iter()
            .map(|q| q.position.distance_squared(p))
            .collect();
        all.sort_by(f32::total_cmp);
        let mut grid = HashGrid::new();
        grid.build(&photons, 0.05);
        let mut scratch = Vec::new();
        for start in [1e-5f32, 0.01, 0.3, 3.0] {
            let d = nearest_photon_distance(&grid, p, 20, 1, start, 10.0, &mut scratch);
            assert_eq!(d, Some(all[19].sqrt()), "start {start}");
        }
    }
}
