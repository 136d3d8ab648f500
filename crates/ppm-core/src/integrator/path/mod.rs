//! The path tracer: one sample per pixel per iteration, next-event estimation and MIS.
//!
//! Orchestration lives here (the iteration, parallel over image tiles, accumulation); the
//! per-path kernel is in [`tracer`].

mod tracer;

use super::{IterationStats, PassTimes, RenderSettings, Snapshot, Stopwatch};
use crate::film::Film;
use crate::sampling::Rng;
use crate::scene::Scene;
use crate::StateError;
use glam::{Vec2, Vec3};
use rayon::prelude::*;

pub use tracer::PathCounters;

/// Rows per parallel work item: small enough to balance two to many threads, large enough to
/// amortise scheduling.
const TILE_ROWS: usize = 4;

/// The render state of the path tracer.
pub struct PathTracer {
    settings: RenderSettings,
    film: Film,
    /// One estimate per pixel for the current iteration, reused.
    estimates: Vec<Vec3>,
}

impl PathTracer {
    /// A fresh render.
    pub fn new(scene: &Scene, settings: RenderSettings) -> Self {
        let (w, h) = (scene.camera.width, scene.camera.height);
        PathTracer {
            settings,
            film: Film::new(w, h),
            estimates: vec![Vec3::ZERO; (w * h) as usize],
        }
    }

    /// A render continuing from `snapshot`: the path tracer carries nothing but the film
    /// between iterations, and iteration i's paths depend on (seed, i, pixel) alone.
    pub fn from_snapshot(
        scene: &Scene,
        settings: RenderSettings,
        snapshot: Snapshot,
    ) -> Result<Self, StateError> {
        let (w, h) = (scene.camera.width, scene.camera.height);
        snapshot.check_film_only(w, h)?;
        Ok(PathTracer {
            settings,
            film: snapshot.film,
            estimates: vec![Vec3::ZERO; (w * h) as usize],
        })
    }

    /// What [`PathTracer::from_snapshot`] needs to continue: the film.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            film: self.film.clone(),
            pixels: Vec::new(),
        }
    }

    /// Traces one path through every pixel and adds the result to the film.
    ///
    /// The pixel estimate is a box-filtered one: a uniformly jittered position in the pixel.
    /// Random streams are keyed by (seed, iteration, pixel), so the image does not depend on
    /// the number of threads.
    pub fn iterate(&mut self, scene: &Scene) -> IterationStats {
        let iteration = self.film.next_iteration();
        let width = scene.camera.width as usize;
        let settings = &self.settings;
        let mut clock = Stopwatch::start();
        let counters = self
            .estimates
            .par_chunks_mut(width * TILE_ROWS)
            .enumerate()
            .map(|(tile, rows)| {
                let mut counters = PathCounters::default();
                for (i, out) in rows.iter_mut().enumerate() {
                    let pixel = tile * width * TILE_ROWS + i;
                    let mut rng = Rng::new(settings.seed, iteration, pixel as u64);
                    let film =
                        Vec2::new((pixel % width) as f32, (pixel / width) as f32) + rng.uniform2();
                    let ray = scene.camera.generate_ray(film);
                    *out = tracer::radiance(scene, settings, ray, &mut rng, &mut counters);
                }
                counters
            })
            .reduce(PathCounters::default, PathCounters::merge);
        let eye = clock.lap();
        let before = self.film.rejected();
        self.film.add_iteration(&self.estimates);
        let passes = PassTimes {
            eye,
            film: clock.lap(),
            ..Default::default()
        };
        IterationStats {
            rays: counters.rays,
            shadow_rays: counters.shadow_rays,
            rejected: self.film.rejected() - before,
            passes,
            ..Default::default()
        }
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
