//! The pilot's measurements for the bias-variance scale of the `photons` radius
//! ([`super::radius_scale`], whose module comment has the formulas): each sampled pixel's
//! moments of the kernel estimate at d_k and 2 d_k ([`pixel_moments`]), its eye-only light
//! ([`EyeLight`]), and the scale m of a pilot ([`pilot_scale`]), which also estimates an
//! iteration's rays and photon visits for the scale's cost and nominal length.

use super::camera_walk::RayCounters;
use super::footprint::PilotPoint;
use super::ppm::trace_eye_path;
use super::radius_photons::PILOT_EYE_STREAM;
use super::radius_scale::{bias_variance_scale, gather_share, nominal_iterations, PixelMoments};
use super::{gather_limit, GatherContext, RenderSettings, PILOT_LIGHT_PATHS};
use crate::photon::{epanechnikov, HashGrid, Kernel, Photon};
use crate::scene::Scene;
use glam::Vec3;
use rayon::prelude::*;

/// Pixels whose moments are summed (a stride through those with a d_k): enough that the
/// pooled bias is well above the sum's own noise, few enough to cost little.
pub const SCALE_SAMPLE: usize = 16384;

/// Eye-only estimates per pixel in the pilot, for [`EyeLight`].
pub const EYE_SAMPLES: usize = 4;

/// The light a pixel gets besides the photons' estimate (emission, sampled direct light,
/// glossy chains to lights): the mean and the unbiased sample variance of
/// [`EYE_SAMPLES`] independent one-iteration estimates (radiance, mean of the channels).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EyeLight {
    /// Mean.
    pub mean: f64,
    /// Variance of one iteration's estimate.
    pub variance: f64,
}

impl EyeLight {
    /// The mean and unbiased variance of `samples` (at least 2).
    pub fn from_samples(samples: &[f64]) -> Self {
        let n = samples.len() as f64;
        let mean = samples.iter().sum::<f64>() / n;
        let variance = samples.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
        EyeLight { mean, variance }
    }
}
/// The scalar flux a relative error is measured in: the mean of the channels.
#[inline]
fn scalar(flux: Vec3) -> f64 {
    (flux.x as f64 + flux.y as f64 + flux.z as f64) / 3.0
}

/// The moments of the pixel whose pilot point is `p` with k-nearest distance `d_k` (> 0),
/// counting the photons of at most `max_bounce` bounces, a kernel sum of flux times `scale`
/// being radiance (the path's throughput times the diffuse albedo / π, over the pilot's light
/// paths), with eye-only light `eye`. `None` if the pixel's radiance L is not positive.
/// `grid` should have cells of about 4 d_k (the query's radius).
pub fn pixel_moments(
    grid: &HashGrid,
    p: Vec3,
    d_k: f32,
    max_bounce: u32,
    scale: f64,
    eye: EyeLight,
) -> Option<PixelMoments> {
    let r2 = [d_k * d_k, 4.0 * d_k * d_k, 16.0 * d_k * d_k];
    let (mut estimate, mut var) = (0.0f64, 0.0f64);
    let mut bias = [0.0f64; 2];
    let mut bias_var = [0.0f64; 2];
    grid.for_each_in_radius(p, 4.0 * d_k, |photon, d2| {
        if photon.bounce() > max_bounce {
            return;
        }
        let phi = scalar(photon.flux);
        let k = r2.map(|r2| epanechnikov(d2, r2) as f64);
        estimate += phi * k[1];
        var += phi * phi * k[1] * k[1];
        for (i, (b, bv)) in bias.iter_mut().zip(&mut bias_var).enumerate() {
            let g = (k[i + 1] - k[i]) / 3.0;
            *b += phi * g;
            *bv += phi * phi * g * g;
        }
    });
    let l = eye.mean + scale * estimate;
    if !(l > 0.0 && l.is_finite()) {
        return None;
    }
    let w = (scale / l).powi(2);
    Some(PixelMoments {
        bias2: (bias[0] * bias[0] - bias_var[0]) * w,
        bias2_double: (bias[1] * bias[1] - bias_var[1]) * w,
        // v(d_k) = 4 v(2 d_k).
        variance: 4.0 * var * w,
        eye: eye.variance / (l * l),
    })
}

/// What the pilot found: per pixel its point, d_k and capped radius, the photon map, the
/// rays of its light paths ([`PILOT_LIGHT_PATHS`]), and k.
pub(super) struct Pilot<'a> {
    pub points: &'a [Option<PilotPoint>],
    pub distances: &'a [Option<f32>],
    pub radii: &'a [f32],
    pub photons: &'a [Photon],
    pub light_rays: u64,
    pub k: usize,
}

/// The eye-only light of `pixel`: [`EYE_SAMPLES`] estimates of the eye pass with no photons
/// (what the render adds to the photons' estimate there: emission, sampled direct light,
/// glossy chains), on the pilot's own stream.
fn eye_light(
    scene: &Scene,
    settings: &RenderSettings,
    empty: &GatherContext<'_>,
    pixel: usize,
    counters: &mut RayCounters,
) -> EyeLight {
    let width = scene.camera.width as usize;
    let mut samples = [0.0f64; EYE_SAMPLES];
    for (i, sample) in samples.iter_mut().enumerate() {
        let l = trace_eye_path(scene, settings, empty, i as u64 + 1, pixel, width, counters);
        *sample = scalar(l);
    }
    EyeLight::from_samples(&samples)
}

/// The bias-variance scale m ([`super::radius_scale`]) from a stride through the pixels with
/// a distance, each at its capped d_k (`typical` sizes the grid's cells), for the render's
/// light paths per iteration (`--photons`). An iteration's cost is estimated from the pilot as its rays (the light paths',
/// scaled to the render's count, and the eye paths') and its photon visits (k per pixel,
/// scaled likewise).
pub(super) fn pilot_scale(
    scene: &Scene,
    settings: &RenderSettings,
    pilot: &Pilot<'_>,
    typical: f32,
    counters: &mut RayCounters,
) -> f32 {
    let found: Vec<(usize, PilotPoint)> = (pilot.points.iter().zip(pilot.distances))
        .enumerate()
        .filter_map(|(i, (point, d))| point.filter(|_| d.is_some()).map(|point| (i, point)))
        .collect();
    let stride = found.len().div_ceil(SCALE_SAMPLE).max(1);
    let mut grid = HashGrid::new();
    grid.build(pilot.photons, 4.0 * typical);
    let mut empty_grid = HashGrid::new();
    empty_grid.build(&[], typical);
    let empty = GatherContext {
        grid: &empty_grid,
        kernel: Kernel::new(typical),
        radius: typical,
        inv_paths: 1.0,
    };
    let eye_settings = RenderSettings {
        seed: settings.seed ^ PILOT_EYE_STREAM,
        ..settings.clone()
    };
    let per_path_weight = 1.0 / PILOT_LIGHT_PATHS as f64;
    let (moments, eye_counters): (Vec<Option<PixelMoments>>, Vec<RayCounters>) = found
        .par_iter()
        .step_by(stride)
        .map(|&(i, point)| {
            let mut eye_counters = RayCounters::default();
            let eye = eye_light(scene, &eye_settings, &empty, i, &mut eye_counters);
            let max_bounce = gather_limit(settings.max_depth, point.depth);
            let scale = point.weight as f64 * per_path_weight;
            let moments = pixel_moments(
                &grid,
                point.position,
                pilot.radii[i],
                max_bounce,
                scale,
                eye,
            );
            (moments, eye_counters)
        })
        .unzip();
    let sampled = eye_counters.len();
    let total = eye_counters
        .into_iter()
        .fold(RayCounters::default(), RayCounters::merge);
    counters.rays += total.rays;
    counters.shadow_rays += total.shadow_rays;
    let moments: Vec<PixelMoments> = moments.into_iter().flatten().collect();
    // ppm's light paths per iteration (`--photons`).
    let paths = settings.photons;
    let per_path = paths as f64 / PILOT_LIGHT_PATHS as f64;
    // The eye pass's rays: the eye-only paths' per sampled pixel (the render's own eye paths,
    // with their shadow rays and glossy chains) for each pixel with a point, one camera ray
    // for each without.
    let eye_rays = (total.rays + total.shadow_rays) as f64 / (EYE_SAMPLES * sampled.max(1)) as f64;
    let rays = pilot.light_rays as f64 * per_path
        + eye_rays * found.len() as f64
        + (pilot.points.len() - found.len()) as f64;
    let visits = found.len() as f64 * pilot.k as f64 * per_path;
    let share = gather_share(rays, visits);
    let iterations = nominal_iterations(rays, share);
    bias_variance_scale(&moments, settings.alpha, paths, share, iterations).1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;
    use glam::Vec2;

    /// The iterations the order's check is evaluated over.
    const N: u32 = 64;

    /// `n` photons of flux 1 on the plane z = 0 over [-1, 1]², with density proportional to
    /// 1 + a (x² + y²) (rejection sampling), bounce 1.
    fn quadratic_photons(n: usize, a: f32, seed: u64) -> Vec<Photon> {
        let mut rng = Rng::new(seed, 0, 0);
        let top = 1.0 + 2.0 * a.max(0.0);
        let mut photons = Vec::with_capacity(n);
        while photons.len() < n {
            let u = rng.uniform2() * 2.0 - Vec2::ONE;
            if rng.uniform() * top <= 1.0 + a * u.length_squared() {
                let key = Photon::key(photons.len() as u32, 1);
                photons.push(Photon::new(u.extend(0.0), Vec3::Z, Vec3::ONE, key));
            }
        }
        photons
    }

    /// For a density f = c (1 + a |x|²) the disc-average expansion is exact (Δf = 4ac
    /// everywhere, no higher derivatives), so at x the bias at radius r relative to the
    /// weight T = E[Ê(2 d_k)] = f(x) + Δf (2 d_k)²/12 is (4a r²/12) / (T / c), and the relative
    /// variance at d_k is 4/(3π d_k² f(x)) (∫K² of the Epanechnikov kernel is 4/(3π r²)). The
    /// pooled moments over queries spread across the plane recover both radii's squared bias
    /// (so an order of 4) and the variance, and no bias for a uniform density.
    #[test]
    fn the_pooled_moments_are_the_laplacian_bias_and_the_poisson_variance() {
        let n = 1_000_000;
        let d_k = 0.1f64;
        for (a, seed) in [(0.0f64, 1u64), (3.0, 2)] {
            let photons = quadratic_photons(n, a as f32, seed);
            let mut grid = HashGrid::new();
            grid.build(&photons, 4.0 * d_k as f32);
            let c = n as f64 / (4.0 * (1.0 + 2.0 * a / 3.0));
            let mut rng = Rng::new(seed + 10, 0, 0);
            let queries = 200;
            let mut sum = PixelMoments::default();
            let mut expected = PixelMoments::default();
            for _ in 0..queries {
                // Within [-0.5, 0.5]², so that the discs (radius 4 d_k) stay on the square.
                let q = rng.uniform2() - Vec2::splat(0.5);
                let m = pixel_moments(
                    &grid,
                    q.extend(0.0),
                    d_k as f32,
                    1,
                    1.0,
                    EyeLight::default(),
                )
                .unwrap();
                let r2 = q.length_squared() as f64;
                let t = 1.0 + a * r2 + 4.0 * a * (2.0 * d_k).powi(2) / 12.0;
                let f = c * (1.0 + a * r2);
                let weight = 1.0 / queries as f64;
                sum.bias2 += m.bias2 * weight;
                sum.bias2_double += m.bias2_double * weight;
                sum.variance += m.variance * weight;
                expected.bias2 += (4.0 * a * d_k * d_k / 12.0 / t).powi(2) * weight;
                expected.bias2_double += (16.0 * a * d_k * d_k / 12.0 / t).powi(2) * weight;
                expected.variance += 4.0 / (3.0 * std::f64::consts::PI * d_k * d_k * f) * weight;
            }
            assert!(
                (sum.variance / expected.variance - 1.0).abs() < 0.05,
                "a {a}: variance {:e} vs {:e}",
                sum.variance,
                expected.variance
            );
            // The noise of one query's b̂(d_k)² is about 2e-6 here (var(b̂) at d_k over T²),
            // 16 times less at 2 d_k per unit of b²; a missing factor (the 1/3, a radius
            // off by its square root of 2) is far outside these bounds.
            for (got, want, floor) in [
                (sum.bias2, expected.bias2, 2e-6),
                (sum.bias2_double, expected.bias2_double, 2e-6),
            ] {
                let tolerance = 0.15 * want + floor;
                assert!(
                    (got - want).abs() < tolerance,
                    "a {a}: bias² {got:e} vs {want:e} (tolerance {tolerance:e})"
                );
            }
            if a > 0.0 {
                let (p, _) = bias_variance_scale(&[sum], 2.0 / 3.0, 1000, 0.0, N);
                assert!((p - 4.0).abs() < 0.3, "order {p}");
            }
        }
    }
}
