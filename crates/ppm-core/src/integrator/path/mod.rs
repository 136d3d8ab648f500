//! The path tracer: one sample per pixel per iteration, next-event estimation and MIS.
//!
//! Orchestration lives here (the iteration, parallel over image tiles, accumulation); the
//! per-path kernel is in [`tracer`].

mod tracer;

use super::camera_walk::RayCounters;
use super::task_order::interleaved;
use super::{
    image_bytes, IterationStats, MemoryEstimate, MemoryPart, PassTimes, RenderSettings, Snapshot,
    Stopwatch, MAX_DEPTH,
};
use crate::film::Film;
use crate::pixel_bounds::PixelBounds;
use crate::sampling::Rng;
use crate::scene::Scene;
use crate::StateError;
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

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

impl PathTracer {
    /// A fresh render; `max_depth` is clamped to [`MAX_DEPTH`].
    pub fn new(scene: &Scene, settings: RenderSettings) -> Self {
        let (w, h) = (scene.camera.width, scene.camera.height);
        Self::with_bounds(settings, PixelBounds::full(w, h))
    }

    /// A fresh render of the pixels in `bounds` only (see [`PixelBounds`]).
    pub fn with_bounds(settings: RenderSettings, bounds: PixelBounds) -> Self {
        let mut settings = settings;
        settings.max_depth = settings.max_depth.min(MAX_DEPTH);
        PathTracer {
            settings,
            film: Film::new(bounds.width(), bounds.height()),
            bounds,
            estimates: vec![Vec3::ZERO; bounds.len()],
        }
    }

    /// What [`PathTracer::new`] allocates for a `width` x `height` image: the per-pixel
    /// buffers only.
    pub fn memory_estimate(width: u32, height: u32, _settings: &RenderSettings) -> MemoryEstimate {
        let mut estimate = MemoryEstimate::default();
        estimate.add(MemoryPart::Image, image_bytes(width, height));
        estimate
    }

    /// A render continuing from `snapshot`: the path tracer carries nothing but the film
    /// between iterations, and iteration i's paths depend on (seed, i, pixel) alone.
    pub fn from_snapshot(
        scene: &Scene,
        settings: RenderSettings,
        snapshot: Snapshot,
    ) -> Result<Self, StateError> {
        let (w, h) = (scene.camera.width, scene.camera.height);
        let film = snapshot.into_film(w, h)?;
        let mut settings = settings;
        settings.max_depth = settings.max_depth.min(MAX_DEPTH);
        Ok(PathTracer {
            settings,
            film,
            bounds: PixelBounds::full(w, h),
            estimates: vec![Vec3::ZERO; (w * h) as usize],
        })
    }

    /// What [`PathTracer::from_snapshot`] needs to continue: the film.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot::of_film(&self.film)
    }

    /// Traces one path through every pixel and adds the result to the film.
    ///
    /// The pixel estimate is a box-filtered one: a uniformly jittered position in the pixel.
    /// Random streams are keyed by (seed, iteration, pixel), so the image does not depend on
    /// the number of threads.
    ///
    /// Abandoned (film untouched, `None`) if `stop` says yes before
    /// one of the iteration's tiles starts.
    pub fn iterate_until<F: Fn() -> bool + Sync>(
        &mut self,
        scene: &Scene,
        stop: &F,
    ) -> Option<IterationStats> {
        let iteration = self.film.next_iteration();
        let width = scene.camera.width as usize;
        let settings = &self.settings;
        let abandoned = AtomicBool::new(false);
        let bounds = self.bounds;
        let mut clock = Stopwatch::start();
        let tiles = self
            .estimates
            .chunks_mut(bounds.width() as usize * TILE_ROWS);
        let counters = interleaved(tiles)
            .into_par_iter()
            .map(|(tile, rows)| {
                let mut counters = RayCounters::default();
                if stop() {
                    abandoned.store(true, Ordering::Relaxed);
                    return counters;
                }
                for (i, out) in rows.iter_mut().enumerate() {
                    let pixel = bounds.full_index(tile * bounds.width() as usize * TILE_ROWS + i);
                    let mut rng = Rng::new(settings.seed, iteration, pixel as u64);
                    let film =
                        Vec2::new((pixel % width) as f32, (pixel / width) as f32) + rng.uniform2();
                    let ray = scene.camera.generate_ray(film);
                    *out = tracer::radiance(scene, settings, ray, &mut rng, &mut counters);
                }
                counters
            })
            .reduce(RayCounters::default, RayCounters::merge);
        // The parallel iterator has joined: every store above is visible here.
        if abandoned.load(Ordering::Relaxed) {
            return None;
        }
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
    pub fn last_estimates(&self) -> &[Vec3] {
        &self.estimates
    }

    /// The accumulated image.
    pub fn film(&self) -> &Film {
        &self.film
    }

    /// Bytes held by the render state.
    pub fn memory_bytes(&self) -> usize {
        self.estimates.len() * std::mem::size_of::<Vec3>() + self.film.memory_bytes()
    }
}
