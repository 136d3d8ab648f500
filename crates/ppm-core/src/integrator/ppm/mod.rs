//! Progressive photon mapping (Hachisuka et al. 2008), in the probabilistic formulation of
//! Knaus and Zwicker 2011: every iteration is an independent photon-mapping estimate with
//! the iteration's global radius, and the image is their average.
//!
//! One iteration: the photon pass ([`photon_pass`]) fills the shared append buffer, the hash
//! grid is rebuilt over those photons, the eye pass ([`eye_pass`]) gathers them at the first
//! diffuse hit of each camera path, the estimate joins the film, and the radius shrinks
//! ([`radius`]).

mod eye_pass;
mod photon_pass;
mod radius;

pub use eye_pass::{density_estimate, GatherContext};
pub use photon_pass::{stores_photons, trace_light_path, MAX_LIGHT_PATHS};
pub use radius::RadiusSchedule;

use super::{IterationStats, PassTimes, RenderSettings, Snapshot, Stopwatch};
use crate::film::Film;
use crate::photon::{HashGrid, Kernel, PhotonBuffer};
use crate::scene::Scene;
use crate::StateError;
use eye_pass::{trace_eye_path, EyeCounters};
use glam::Vec3;
use photon_pass::PhotonCounters;
use rayon::prelude::*;

/// Light paths per parallel work item of the photon pass.
const PATHS_PER_TASK: u32 = 512;
/// Pixels per parallel work item of the eye pass.
const PIXELS_PER_TASK: usize = 1024;

/// The render state of progressive photon mapping.
pub struct PpmRenderer {
    settings: RenderSettings,
    film: Film,
    schedule: RadiusSchedule,
    /// Allocated once, grown when an iteration stores more photons than it holds.
    photons: PhotonBuffer,
    grid: HashGrid,
    estimates: Vec<Vec3>,
}

impl PpmRenderer {
    /// A fresh render. The number of light paths is capped at [`MAX_LIGHT_PATHS`].
    pub fn new(scene: &Scene, settings: RenderSettings) -> Self {
        let (w, h) = (scene.camera.width, scene.camera.height);
        Self::with_film(scene, settings, Film::new(w, h))
    }

    /// A render continuing from `snapshot`. Knaus and Zwicker's PPM carries nothing but the
    /// film between iterations: iteration i's photons and eye paths depend on (seed, i) and
    /// its radius on i alone, so the schedule restarts at the snapshot's next iteration.
    pub fn from_snapshot(
        scene: &Scene,
        settings: RenderSettings,
        snapshot: Snapshot,
    ) -> Result<Self, StateError> {
        snapshot.check_film_only(scene.camera.width, scene.camera.height)?;
        Ok(Self::with_film(scene, settings, snapshot.film))
    }

    /// What [`PpmRenderer::from_snapshot`] needs to continue: the film.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            film: self.film.clone(),
            pixels: Vec::new(),
        }
    }

    /// A render whose next iteration is `film.next_iteration()`.
    fn with_film(scene: &Scene, settings: RenderSettings, film: Film) -> Self {
        let mut settings = settings;
        settings.photons = settings.photons.clamp(1, MAX_LIGHT_PATHS);
        let (w, h) = (scene.camera.width, scene.camera.height);
        // About 3 photons per light path in a closed box with albedo ~0.7; grown on demand.
        let capacity = settings.photons as usize * 4;
        PpmRenderer {
            // The schedule is 1-based: 0-based iteration k uses its (k + 1)-th radius.
            schedule: RadiusSchedule::at_iteration(
                settings.radius,
                settings.alpha,
                film.next_iteration() + 1,
            ),
            settings,
            film,
            photons: PhotonBuffer::with_capacity(capacity),
            grid: HashGrid::new(),
            estimates: vec![Vec3::ZERO; (w * h) as usize],
        }
    }

    /// The photon pass: all light paths of this iteration, in parallel, into the shared buffer.
    /// If the buffer overflows, it grows and the pass is redone: light paths are keyed by
    /// (seed, iteration, path) so the redone pass stores exactly the same photons.
    fn photon_pass(&mut self, scene: &Scene, iteration: u64) -> PhotonCounters {
        let paths = self.settings.photons;
        loop {
            self.photons.clear();
            let buffer = &self.photons;
            let settings = &self.settings;
            let tasks = paths.div_ceil(PATHS_PER_TASK);
            let counters = (0..tasks)
                .into_par_iter()
                .map(|task| {
                    let mut counters = PhotonCounters::default();
                    let mut writer = buffer.writer();
                    let end = ((task + 1) * PATHS_PER_TASK).min(paths);
                    for path in task * PATHS_PER_TASK..end {
                        trace_light_path(
                            scene,
                            settings,
                            iteration,
                            path,
                            &mut writer,
                            &mut counters,
                        );
                    }
                    counters
                })
                .reduce(PhotonCounters::default, |a, b| PhotonCounters {
                    rays: a.rays + b.rays,
                    photons: a.photons + b.photons,
                });
            if !self.photons.overflowed() {
                return counters;
            }
            let needed = self.photons.pushed();
            self.photons.grow(needed + needed / 4);
        }
    }

    /// Renders one iteration.
    pub fn iterate(&mut self, scene: &Scene) -> IterationStats {
        let iteration = self.film.next_iteration();
        let radius = self.schedule.radius();
        let mut passes = PassTimes::default();
        let mut clock = Stopwatch::start();
        let photon_counters = self.photon_pass(scene, iteration);
        passes.photon = clock.lap();
        self.grid.build(self.photons.as_slice(), radius);
        passes.grid = clock.lap();

        let ctx = GatherContext {
            grid: &self.grid,
            kernel: Kernel::new(radius),
            radius,
            inv_paths: 1.0 / self.settings.photons as f32,
        };
        let width = scene.camera.width as usize;
        let settings = &self.settings;
        let eye = self
            .estimates
            .par_chunks_mut(PIXELS_PER_TASK)
            .enumerate()
            .map(|(task, pixels)| {
                let mut counters = EyeCounters::default();
                for (i, out) in pixels.iter_mut().enumerate() {
                    let pixel = task * PIXELS_PER_TASK + i;
                    *out = trace_eye_path(
                        scene,
                        settings,
                        &ctx,
                        iteration,
                        pixel,
                        width,
                        &mut counters,
                    );
                }
                counters
            })
            .reduce(EyeCounters::default, |a, b| EyeCounters {
                rays: a.rays + b.rays,
                shadow_rays: a.shadow_rays + b.shadow_rays,
            });
        passes.eye = clock.lap();

        let before = self.film.rejected();
        self.film.add_iteration(&self.estimates);
        passes.film = clock.lap();
        self.schedule.advance();
        IterationStats {
            rays: eye.rays + photon_counters.rays,
            photon_rays: photon_counters.rays,
            shadow_rays: eye.shadow_rays,
            light_paths: self.settings.photons as u64,
            photons: photon_counters.photons,
            radius,
            rejected: self.film.rejected() - before,
            passes,
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

    /// The radius the next iteration will use.
    pub fn radius(&self) -> f32 {
        self.schedule.radius()
    }

    /// The photons stored by the last iteration, in the grid's (deterministic) order.
    pub fn photon_map(&self) -> &HashGrid {
        &self.grid
    }

    /// Bytes held by the render state (film, photon buffer, grid, per-pixel estimates).
    pub fn memory_bytes(&self) -> usize {
        self.estimates.len() * std::mem::size_of::<Vec3>()
            + self.film.memory_bytes()
            + self.photons.memory_bytes()
            + self.grid.memory_bytes()
    }
}
