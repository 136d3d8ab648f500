//! The path tracer: one sample per pixel per iteration, next-event estimation and MIS.
//!
//! Orchestration lives here (the iteration, parallel over image tiles, accumulation); the
//! per-path kernel is in [`tracer`].

mod tracer;

use super::camera_walk::RayCounters;
use super::runner::{reduce_until, Poll};
use super::task_order::interleaved;
use super::{
    image_bytes, Features, Integrator, IterationStats, MemoryEstimate, MemoryPart, PassTimes,
    RenderSettings, RenderStart, Stop, Stopwatch,
};
use crate::film::Film;
use crate::pixel_bounds::PixelBounds;
use crate::sampling::Rng;
use crate::scene::Scene;
use glam::{Vec2, Vec3};
use std::ops::Range;

/// Rows per parallel work item: small enough to balance two to many threads, large enough to
/// amortise scheduling.
const TILE_ROWS: usize = 4;

/// The render state of the path tracer.
pub struct PathTracer {
    settings: RenderSettings,
    film: Film,
    /// The pixels rendered (the whole image unless cropped).
    bounds: PixelBounds,
    /// One estimate per pixel for the current iteration, reused.
    estimates: Vec<Vec3>,
}

impl Integrator for PathTracer {
    fn features() -> Features {
        Features {
            aovs: &[],
            aov_refusal: "the path tracer gathers no photons",
            shard_refusal: None,
            sample_per_iteration: true,
            photon_map: false,
            delta_light_caustics: false,
            snapshot_channels: 0,
        }
    }

    /// The per-pixel buffers only.
    fn memory_estimate(width: u32, height: u32, _settings: &RenderSettings) -> MemoryEstimate {
        let mut estimate = MemoryEstimate::default();
        estimate.add(MemoryPart::Image, image_bytes(width, height));
        estimate
    }

    /// `seed 1, 16 samples per pixel`: every iteration in the image is one sample.
    fn settings_words(settings: &RenderSettings, image: Range<u64>) -> String {
        let samples = image.end - image.start;
        format!(
            "seed {}, {samples} sample{} per pixel",
            settings.seed,
            if samples == 1 { "" } else { "s" }
        )
    }

    /// A render from `start`: the path tracer carries nothing but the film between
    /// iterations (the default [`Integrator::from_snapshot`]), and iteration i's paths depend
    /// on (seed, i, pixel) alone.
    fn start(start: RenderStart) -> Self {
        PathTracer {
            settings: start.settings,
            film: start.film,
            bounds: start.bounds,
            estimates: vec![Vec3::ZERO; start.bounds.len()],
        }
    }

    /// Traces one path through every pixel and adds the result to the film.
    ///
    /// The pixel estimate is a box-filtered one: a uniformly jittered position in the pixel.
    /// Random streams are keyed by (seed, iteration, pixel), so the image does not depend on
    /// the number of threads.
    ///
    /// Abandoned (film untouched, `None`) if `stop` says yes before
    /// one of the iteration's tiles starts.
    fn iterate_until(&mut self, scene: &Scene, stop: Stop) -> Option<IterationStats> {
        let iteration = self.film.next_iteration();
        let width = scene.camera.width as usize;
        let settings = &self.settings;
        let bounds = self.bounds;
        let mut clock = Stopwatch::start();
        let tiles = self
            .estimates
            .chunks_mut(bounds.width() as usize * TILE_ROWS);
        let poll = Poll::new(stop);
        let counters = reduce_until(
            interleaved(tiles),
            &poll,
            |(tile, rows)| {
                let mut counters = RayCounters::default();
                for (i, out) in rows.iter_mut().enumerate() {
                    // A tile is rows of pixels, each up to max_depth bounces: ask between
                    // pixels.
                    if poll.stopped() {
                        break;
                    }
                    let pixel = bounds.full_index(tile * bounds.width() as usize * TILE_ROWS + i);
                    let mut rng = Rng::new(settings.seed, iteration, pixel as u64);
                    let film =
                        Vec2::new((pixel % width) as f32, (pixel / width) as f32) + rng.uniform2();
                    let ray = scene.camera.sample_ray(film, &mut rng);
                    *out = tracer::radiance(scene, settings, ray, &mut rng, &mut counters);
                }
                counters
            },
            RayCounters::merge,
        )?;
        let eye = clock.lap();
        let before = self.film.rejected();
        self.film.add_iteration(&self.estimates);
        let passes = PassTimes {
            eye,
            film: clock.lap(),
            ..Default::default()
        };
        Some(IterationStats {
            rays: counters.rays,
            shadow_rays: counters.shadow_rays,
            rejected: self.film.rejected() - before,
            passes,
            ..Default::default()
        })
    }

    /// The per-pixel estimates of the last iteration alone (row-major), for variance
    /// estimates in statistical tests.
    fn last_estimates(&self) -> &[Vec3] {
        &self.estimates
    }

    /// The accumulated image.
    fn film(&self) -> &Film {
        &self.film
    }

    /// Bytes held by the render state.
    fn memory_bytes(&self) -> usize {
        self.estimates.len() * std::mem::size_of::<Vec3>() + self.film.memory_bytes()
    }
}
